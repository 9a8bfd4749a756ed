"""Mappings (the bonus chapter "Texture mapping"): a point in pattern space to (u, v).

Each mapping is a function ``(point) -> (u, v)`` with u and v from 0 to 1. The angle around
the y axis is ``theta = atan2(x, z)``, from -π to π, and ``raw_u = theta / (2π)``; the book
turns it into ``u = 1 - (raw_u + 0.5)`` so that u grows counter-clockwise seen from above
(+y) and u = 0 (and 1) is the seam at -z. ``a % m`` is Python's remainder, which has the
sign of ``m``: ``-0.25 % 1 == 0.75``, as the book wants (a tiny negative ``a`` gives ``m``
itself, so a remainder can reach the top of its range).

The cube's six faces each have their own mapping (``cube_uv_front`` ...) over the face's
square from -1 to 1; ``face_from_point`` says which face a point of the unit cube is on.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Literal

from raytracer.tuples import Tuple

UV = tuple[float, float]
UVMapping = Callable[[Tuple], UV]
Face = Literal["left", "right", "front", "back", "up", "down"]


def spherical_map(p: Tuple) -> UV:
    """Texture mapping: a point on a sphere around the origin to (u, v), like longitude and
    latitude.

    theta = atan2(x, z); radius = sqrt(x*x + y*y + z*z); phi = acos(y / radius), with
    y / radius clamped to [-1, 1] (rounding can push it out); raw_u = theta / (2π);
    u = 1 - (raw_u + 0.5); v = 1 - phi / π (v = 1 at the north pole +y, 0 at the south
    pole). The origin has no direction: radius 0 gives phi = π/2 (v = 0.5), and
    atan2(0, 0) = 0 gives u = 0.5.
    """
    theta = math.atan2(p.x, p.z)
    radius = math.sqrt(p.x * p.x + p.y * p.y + p.z * p.z)
    phi = math.acos(max(-1.0, min(1.0, p.y / radius))) if radius > 0 else math.pi / 2
    raw_u = theta / (2 * math.pi)
    u = 1 - (raw_u + 0.5)
    v = 1 - phi / math.pi
    return u, v


def planar_map(p: Tuple) -> UV:
    """Texture mapping: the xz plane tiled by unit squares: u = x % 1, v = z % 1 (y is
    ignored)."""
    return p.x % 1.0, p.z % 1.0


def cylindrical_map(p: Tuple) -> UV:
    """Texture mapping: around the y axis, repeating every unit of height.

    theta = atan2(x, z); raw_u = theta / (2π); u = 1 - (raw_u + 0.5); v = y % 1.
    """
    theta = math.atan2(p.x, p.z)
    raw_u = theta / (2 * math.pi)
    u = 1 - (raw_u + 0.5)
    return u, p.y % 1.0


def face_from_point(p: Tuple) -> Face:
    """Texture mapping: the face of the cube from -1 to 1 that a point is on: the axis of
    the largest absolute coordinate and its sign. "right" is +x, "left" -x, "up" +y, "down"
    -y, "front" +z, "back" -z; a tie goes to x, then y (an edge or corner is on the first).
    """
    coord = max(abs(p.x), abs(p.y), abs(p.z))
    if coord == p.x:
        return "right"
    if coord == -p.x:
        return "left"
    if coord == p.y:
        return "up"
    if coord == -p.y:
        return "down"
    if coord == p.z:
        return "front"
    return "back"


def cube_uv_front(p: Tuple) -> UV:
    """Texture mapping: the front face (+z), seen from +z: u = ((x + 1) % 2) / 2,
    v = ((y + 1) % 2) / 2."""
    return ((p.x + 1) % 2.0) / 2.0, ((p.y + 1) % 2.0) / 2.0


def cube_uv_back(p: Tuple) -> UV:
    """Texture mapping: the back face (-z), seen from -z: u = ((1 - x) % 2) / 2,
    v = ((y + 1) % 2) / 2."""
    return ((1 - p.x) % 2.0) / 2.0, ((p.y + 1) % 2.0) / 2.0


def cube_uv_left(p: Tuple) -> UV:
    """Texture mapping: the left face (-x), seen from -x: u = ((z + 1) % 2) / 2,
    v = ((y + 1) % 2) / 2."""
    return ((p.z + 1) % 2.0) / 2.0, ((p.y + 1) % 2.0) / 2.0


def cube_uv_right(p: Tuple) -> UV:
    """Texture mapping: the right face (+x), seen from +x: u = ((1 - z) % 2) / 2,
    v = ((y + 1) % 2) / 2."""
    return ((1 - p.z) % 2.0) / 2.0, ((p.y + 1) % 2.0) / 2.0


def cube_uv_up(p: Tuple) -> UV:
    """Texture mapping: the upper face (+y), seen from above with -z at the top:
    u = ((x + 1) % 2) / 2, v = ((1 - z) % 2) / 2."""
    return ((p.x + 1) % 2.0) / 2.0, ((1 - p.z) % 2.0) / 2.0


def cube_uv_down(p: Tuple) -> UV:
    """Texture mapping: the lower face (-y), seen from below with +z at the top:
    u = ((x + 1) % 2) / 2, v = ((z + 1) % 2) / 2."""
    return ((p.x + 1) % 2.0) / 2.0, ((p.z + 1) % 2.0) / 2.0


MAPPINGS: dict[str, UVMapping] = {
    "spherical": spherical_map,
    "planar": planar_map,
    "cylindrical": cylindrical_map,
}
"""The mappings a ``TextureMap`` takes, by the scene format's name (the cube has its own
pattern, ``CubeMap``)."""

CUBE_FACES: tuple[Face, ...] = ("left", "front", "right", "back", "up", "down")
"""The faces in the order ``cube_map`` takes their UV patterns."""

CUBE_UV: dict[Face, UVMapping] = {
    "left": cube_uv_left,
    "front": cube_uv_front,
    "right": cube_uv_right,
    "back": cube_uv_back,
    "up": cube_uv_up,
    "down": cube_uv_down,
}
"""Each face's mapping."""
