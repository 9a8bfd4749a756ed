"""The scenes the harness renders: the scene files and their presets (``presets``), the OBJ
meshes (``make_meshes``) and the image textures (``make_textures``) they use."""

from pathlib import Path

SCENES = Path(__file__).resolve().parents[1] / "scenes"
"""The folder of the project's scene files, their textures and OBJ models."""
