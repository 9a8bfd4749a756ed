"""Shapes (chapters 5, 9, 12-16) intersecting into a reused intersection buffer and writing
their normals into a caller-owned buffer: what every shape record has.

One record class per reference shape (``solids``, ``triangles``, ``groups``; the table of
them is ``context``'s), built once per render context. A record holds the shape's inverse
and inverse transpose as flat lists, its material record, its parent's record, and a ray
buffer for the ray in its object space. ``local_intersect_into`` and
``local_normal_at_into`` are the twins of the reference's ``local_intersect`` and
``local_normal_at``: the same arithmetic in the same order, so the same floats.
"""

from __future__ import annotations

import math

from raytracer.shapes.shape import Shape
from variants.prealloc.buffers import (
    IntersectionBuffer,
    Vec,
    new_ray,
)
from variants.prealloc.geometry import flat_matrix, transform_point_into, transform_ray_into
from variants.prealloc.records import MaterialRecord

INF = math.inf


class ShapeRecord:
    """Chapter 9: what every shape record has.

    shape: the reference shape (what ``Intersection.object`` and ``comps.object`` are at
    the API boundary); inverse, inverse_transpose: flat 4x4 lists; parent: the parent's
    record or None; material: its ``MaterialRecord``; casts_shadow: the shape's flag;
    eps: the offset epsilon of the render; local_ray: the ray in object space (a buffer).
    """

    __slots__ = (
        "casts_shadow",
        "eps",
        "inverse",
        "inverse_transpose",
        "local_ray",
        "material",
        "parent",
        "shape",
    )

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        self.shape = shape
        self.inverse = flat_matrix(shape.inverse_transform)
        self.inverse_transpose = flat_matrix(shape.inverse_transpose)
        self.parent: ShapeRecord | None = None
        self.material = material
        self.casts_shadow = bool(shape.casts_shadow)
        self.eps = eps
        self.local_ray = new_ray()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Append the intersections of an object-space ray (twin: ``local_intersect``)."""
        raise NotImplementedError

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """The object-space normal at an object-space point (twin: ``local_normal_at``)."""
        raise NotImplementedError

    def finish(self, children: list[ShapeRecord]) -> None:
        """Take the records of the shapes this one contains (groups and CSG only)."""


def intersect_into(rec: ShapeRecord, ray: Vec, xs: IntersectionBuffer) -> None:
    """Chapters 5 and 9: ``intersect(shape, ray)`` appended to ``xs``: the ray into object
    space (into the record's own ray buffer), then the shape's own test."""
    local = rec.local_ray
    transform_ray_into(rec.inverse, ray, local)
    rec.local_intersect_into(local, xs)


def normal_at_into(
    rec: ShapeRecord, point: Vec, u: float | None, v: float | None, out: Vec
) -> None:
    """Chapters 6, 9, 14: ``out = normal_at(shape, point, hit)`` (u, v: the hit's)."""
    world_to_object_into(rec, point, out)
    rec.local_normal_at_into(out, u, v, out)
    normal_to_world_into(rec, out, out)


def world_to_object_into(rec: ShapeRecord, point: Vec, out: Vec) -> None:
    """Chapter 14: ``out = world_to_object(shape, point)``, through every parent (naive
    twin: ``raytracer.space.world_to_object``)."""
    if rec.parent is not None:
        world_to_object_into(rec.parent, point, out)
        point = out
    transform_point_into(rec.inverse, point, out)


def normal_to_world_into(rec: ShapeRecord, normal: Vec, out: Vec) -> None:
    """Chapter 14: ``out = normal_to_world(shape, normal)``: through the inverse transpose,
    w dropped, normalized (a zero normal stays zero), then through every parent (naive
    twin: ``raytracer.space.normal_to_world``)."""
    m = rec.inverse_transpose
    x, y, z, w = normal
    nx = m[0] * x + m[1] * y + m[2] * z + m[3] * w
    ny = m[4] * x + m[5] * y + m[6] * z + m[7] * w
    nz = m[8] * x + m[9] * y + m[10] * z + m[11] * w
    if nx != 0 or ny != 0 or nz != 0:
        length = math.sqrt(nx * nx + ny * ny + nz * nz + 0.0 * 0.0)
        out[0] = nx / length
        out[1] = ny / length
        out[2] = nz / length
        out[3] = 0.0 / length
    else:
        out[0] = nx
        out[1] = ny
        out[2] = nz
        out[3] = 0.0
    if rec.parent is not None:
        normal_to_world_into(rec.parent, out, out)
