"""Texture-mapped patterns (the bonus chapter "Texture mapping"): a UV pattern put on a
shape by a mapping, as a chapter 10 ``Pattern``.

Both are reference patterns like the stripes: the point they see is in pattern space
(``pattern_at_shape`` converts a world point through the shape and the pattern's own
``transform``), and ``set_pattern_transform`` places them. A sphere of radius 1 at the
origin, the unit cylinder, the xz plane and the cube from -1 to 1 are the shapes the
mappings are made for; scale the pattern (or the shape) to fit others.
"""

from __future__ import annotations

from dataclasses import dataclass

from raytracer.colors import Color
from raytracer.patterns import Pattern
from raytracer.textures.mappings import (
    UVMapping,
    cube_uv_back,
    cube_uv_down,
    cube_uv_front,
    cube_uv_left,
    cube_uv_right,
    cube_uv_up,
    face_from_point,
)
from raytracer.textures.uv_patterns import UVPattern
from raytracer.tuples import Tuple


@dataclass(slots=True, eq=True)
class TextureMap(Pattern):
    """A UV pattern wrapped onto a shape: the color at a point is
    ``uv_pattern_at(uv_pattern, *mapping(point))``.

    uv_pattern: the UV pattern (``UVCheckers``, ``UVAlignCheck``, ``UVImage``); mapping:
    ``spherical_map``, ``planar_map`` or ``cylindrical_map`` (any ``point -> (u, v)``
    function works here; the other variants know those three).
    """

    uv_pattern: UVPattern
    mapping: UVMapping

    def local_pattern_at(self, point: Tuple) -> Color:
        u, v = self.mapping(point)
        return self.uv_pattern.uv_color_at(u, v)


@dataclass(slots=True, eq=True)
class CubeMap(Pattern):
    """A UV pattern per face of the cube from -1 to 1: ``face_from_point`` picks the face,
    its ``cube_uv_*`` mapping gives (u, v), and that face's UV pattern the color.

    left, front, right, back, up, down: the UV patterns of the faces -x, +z, +x, -z, +y, -y.
    """

    left: UVPattern
    front: UVPattern
    right: UVPattern
    back: UVPattern
    up: UVPattern
    down: UVPattern

    def local_pattern_at(self, point: Tuple) -> Color:
        face = face_from_point(point)
        if face == "left":
            u, v = cube_uv_left(point)
            return self.left.uv_color_at(u, v)
        if face == "right":
            u, v = cube_uv_right(point)
            return self.right.uv_color_at(u, v)
        if face == "front":
            u, v = cube_uv_front(point)
            return self.front.uv_color_at(u, v)
        if face == "back":
            u, v = cube_uv_back(point)
            return self.back.uv_color_at(u, v)
        if face == "up":
            u, v = cube_uv_up(point)
            return self.up.uv_color_at(u, v)
        u, v = cube_uv_down(point)
        return self.down.uv_color_at(u, v)


def texture_map(uv_pattern: UVPattern, mapping: UVMapping) -> TextureMap:
    """Texture mapping: ``uv_pattern`` on a shape through ``mapping`` (``spherical_map``,
    ``planar_map``, ``cylindrical_map``)."""
    return TextureMap(uv_pattern, mapping)


def cube_map(
    left: UVPattern,
    front: UVPattern,
    right: UVPattern,
    back: UVPattern,
    up: UVPattern,
    down: UVPattern,
) -> CubeMap:
    """Texture mapping: a cube's six faces, each with its own UV pattern."""
    return CubeMap(left, front, right, back, up, down)
