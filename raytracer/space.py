"""World space and object space (chapter 14): converting points and normals through a shape's
transform and its parents' transforms. Works for shapes without a parent (chapters 5-13).

These read ``shape.inverse_transform`` and ``shape.inverse_transpose`` (properties the naive
reference recomputes on every access) and ``shape.parent``: what ``Placed`` names. They
import nothing from the shapes, so that patterns and materials, which the shapes use, can
use them too.
"""

from __future__ import annotations

from typing import Protocol

from raytracer.matrices import Matrix
from raytracer.tuples import Tuple, normalize, vector


class Placed(Protocol):
    """What chapter 14's conversions read of a shape: its parent group (or None) and its
    inverse transform and inverse transpose (``raytracer.shapes.shape.Shape`` has them)."""

    @property
    def parent(self) -> Placed | None: ...
    @property
    def inverse_transform(self) -> Matrix: ...
    @property
    def inverse_transpose(self) -> Matrix: ...


def world_to_object(shape: Placed, point: Tuple) -> Tuple:
    """Chapter 14: a world-space point in ``shape``'s object space (through every parent)."""
    if shape.parent is not None:
        point = world_to_object(shape.parent, point)
    return shape.inverse_transform * point


def normal_to_world(shape: Placed, normal: Tuple) -> Tuple:
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
