"""World space and object space (chapter 14): converting points and normals through a shape's
transform and its parents' transforms. Works for shapes without a parent (chapters 5-13).

These read ``shape.inverse_transform`` and ``shape.inverse_transpose`` (properties the naive
reference recomputes on every access) and ``shape.parent``; they import nothing from the
shapes, so patterns can use them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from raytracer.tuples import Tuple, normalize, vector

if TYPE_CHECKING:
    from raytracer.shapes.shape import Shape


def world_to_object(shape: Shape, point: Tuple) -> Tuple:
    """Chapter 14: a world-space point in ``shape``'s object space (through every parent)."""
    if shape.parent is not None:
        point = world_to_object(shape.parent, point)
    return shape.inverse_transform * point


def normal_to_world(shape: Shape, normal: Tuple) -> Tuple:
    """Chapter 14: an object-space normal of ``shape`` in world space, normalized.

    A zero normal (the tip of a cone, chapter 13) has no direction and stays zero, where
    dividing by its length would fail.
    """
    normal = shape.inverse_transpose * normal
    normal = vector(normal.x, normal.y, normal.z)  # drop the translated w
    if normal.x != 0 or normal.y != 0 or normal.z != 0:
        normal = normalize(normal)
    if shape.parent is not None:
        normal = normal_to_world(shape.parent, normal)
    return normal
