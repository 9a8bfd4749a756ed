"""Texture mapping (the book's bonus chapter): UV patterns (``uv_patterns``), the mappings
from a point to (u, v) (``mappings``), and the patterns that put one on a shape (``maps``).
The PPM reader for image textures is ``raytracer.ppm``.
"""

from raytracer.textures.mappings import (
    CUBE_FACES,
    CUBE_UV,
    MAPPINGS,
    cube_uv_back,
    cube_uv_down,
    cube_uv_front,
    cube_uv_left,
    cube_uv_right,
    cube_uv_up,
    cylindrical_map,
    face_from_point,
    planar_map,
    spherical_map,
)
from raytracer.textures.maps import CubeMap, TextureMap, cube_map, texture_map
from raytracer.textures.uv_patterns import (
    UVAlignCheck,
    UVCheckers,
    UVImage,
    UVPattern,
    uv_align_check,
    uv_checkers,
    uv_image,
    uv_pattern_at,
)

__all__ = [
    "CUBE_FACES",
    "CUBE_UV",
    "MAPPINGS",
    "CubeMap",
    "TextureMap",
    "UVAlignCheck",
    "UVCheckers",
    "UVImage",
    "UVPattern",
    "cube_map",
    "cube_uv_back",
    "cube_uv_down",
    "cube_uv_front",
    "cube_uv_left",
    "cube_uv_right",
    "cube_uv_up",
    "cylindrical_map",
    "face_from_point",
    "planar_map",
    "spherical_map",
    "texture_map",
    "uv_align_check",
    "uv_checkers",
    "uv_image",
    "uv_pattern_at",
]
