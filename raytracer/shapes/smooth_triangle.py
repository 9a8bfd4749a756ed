"""The smooth triangle (chapter 15): a triangle with a normal at each corner, blended across
the face by where the ray hit it (``u`` and ``v``), so a mesh of them looks curved."""

from __future__ import annotations

from dataclasses import dataclass

from raytracer.shapes.shape import Intersection, intersection_with_uv
from raytracer.shapes.triangle import Triangle
from raytracer.tuples import Tuple


@dataclass(slots=True, eq=True)
class SmoothTriangle(Triangle):
    """Chapter 15: corners ``p1 p2 p3`` with the normals ``n1 n2 n3`` (vectors) at them."""

    n1: Tuple
    n2: Tuple
    n3: Tuple

    def intersection_at(self, t: float, u: float, v: float) -> Intersection:
        """Chapter 15: the hit keeps ``u`` and ``v`` for the normal."""
        return intersection_with_uv(t, self, u, v)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 15: ``n2 * u + n3 * v + n1 * (1 - u - v)`` from the hit's u and v (not
        normalized; ``normal_at`` does that). The point itself is not used."""
        if hit is None or hit.u is None or hit.v is None:
            raise ValueError(
                "local_normal_at(SmoothTriangle): needs the hit with its u and v "
                "(an intersection from local_intersect or intersection_with_uv)"
            )
        u, v = hit.u, hit.v
        return self.n2 * u + self.n3 * v + self.n1 * (1 - u - v)


def smooth_triangle(
    p1: Tuple, p2: Tuple, p3: Tuple, n1: Tuple, n2: Tuple, n3: Tuple
) -> SmoothTriangle:
    """Chapter 15: a new smooth triangle: corners ``p1 p2 p3``, corner normals ``n1 n2 n3``."""
    return SmoothTriangle(p1, p2, p3, n1, n2, n3)
