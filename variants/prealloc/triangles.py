"""The records of triangles and smooth triangles (chapter 15): the reference's numbers
(corners, edges, normal) as buffers, Möller-Trumbore's test, the interpolated normal."""

from __future__ import annotations

from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.triangle import Triangle
from variants.prealloc.buffers import (
    IntersectionBuffer,
    Vec,
    add_intersection,
    tuple_buffer,
)
from variants.prealloc.records import MaterialRecord
from variants.prealloc.shapes import ShapeRecord


class TriangleRecord(ShapeRecord):
    """Chapter 15: the triangle, with ``p1``, ``e1``, ``e2`` and ``normal`` as buffers."""

    __slots__ = ("e1", "e2", "normal", "p1")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, Triangle)
        self.p1 = tuple_buffer(shape.p1)
        self.e1 = tuple_buffer(shape.e1)
        self.e2 = tuple_buffer(shape.e2)
        self.normal = tuple_buffer(shape.normal)

    def add_hit(self, xs: IntersectionBuffer, t: float, u: float, v: float) -> None:
        """Twin of ``Triangle.intersection_at``: a flat triangle does not keep u and v."""
        add_intersection(xs, t, self)

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 15: Möller–Trumbore; twin: ``Triangle.local_intersect``."""
        ox, oy, oz, ow, dx, dy, dz, dw = ray
        e1x, e1y, e1z, e1w = self.e1
        e2x, e2y, e2z, e2w = self.e2
        # dir_cross_e2 = cross(direction, e2), a vector (w = 0.0)
        cx = dy * e2z - dz * e2y
        cy = dz * e2x - dx * e2z
        cz = dx * e2y - dy * e2x
        det = e1x * cx + e1y * cy + e1z * cz + e1w * 0.0
        if abs(det) < self.eps:
            return
        f = 1.0 / det
        p1x, p1y, p1z, p1w = self.p1
        px, py, pz, pw = ox - p1x, oy - p1y, oz - p1z, ow - p1w  # p1_to_origin
        u = f * (px * cx + py * cy + pz * cz + pw * 0.0)
        if u < 0 or u > 1:
            return
        # origin_cross_e1 = cross(p1_to_origin, e1), a vector (w = 0.0)
        qx = py * e1z - pz * e1y
        qy = pz * e1x - px * e1z
        qz = px * e1y - py * e1x
        v = f * (dx * qx + dy * qy + dz * qz + dw * 0.0)
        if v < 0 or u + v > 1:
            return
        t = f * (e2x * qx + e2y * qy + e2z * qz + e2w * 0.0)
        self.add_hit(xs, t, u, v)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 15: the face normal; twin: ``Triangle.local_normal_at``."""
        n = self.normal
        out[0], out[1], out[2], out[3] = n[0], n[1], n[2], n[3]


class SmoothTriangleRecord(TriangleRecord):
    """Chapter 15: the smooth triangle, with its corner normals as buffers."""

    __slots__ = ("n1", "n2", "n3")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, SmoothTriangle)
        self.n1 = tuple_buffer(shape.n1)
        self.n2 = tuple_buffer(shape.n2)
        self.n3 = tuple_buffer(shape.n3)

    def add_hit(self, xs: IntersectionBuffer, t: float, u: float, v: float) -> None:
        """Twin of ``SmoothTriangle.intersection_at``: the hit keeps u and v."""
        add_intersection(xs, t, self, u, v)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 15: n2 * u + n3 * v + n1 * (1 - u - v); twin:
        ``SmoothTriangle.local_normal_at``."""
        if u is None or v is None:
            raise ValueError(
                "local_normal_at(SmoothTriangle): needs the hit with its u and v "
                "(an intersection from local_intersect or intersection_with_uv)"
            )
        n1, n2, n3 = self.n1, self.n2, self.n3
        rest = 1 - u - v
        out[0] = n2[0] * u + n3[0] * v + n1[0] * rest
        out[1] = n2[1] * u + n3[1] * v + n1[1] * rest
        out[2] = n2[2] * u + n3[2] * v + n1[2] * rest
        out[3] = n2[3] * u + n3[3] * v + n1[3] * rest
