"""The scenes the harness renders: the scene files and their presets (``presets``), the OBJ
meshes (``make_meshes``) and the image textures (``make_textures``) they use."""

from scenes import FOLDER as SCENES

__all__ = ["SCENES"]
