"""The flat triangle (chapter 15): three corners, with its edges and normal worked out once,
when it is built (the book's design: they are part of the triangle's data)."""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, cross, dot, magnitude, normalize, point, vector


def face_normal(e1: Tuple, e2: Tuple) -> Tuple:
    """Chapter 15: ``normalize(cross(e2, e1))``.

    A degenerate triangle (its corners on one line, or two of them equal) has no area and
    no direction: its normal is the zero vector rather than a division by zero. Rays never
    hit such a triangle (see ``Triangle.local_intersect``), so the tracer never shades it.
    """
    n = cross(e2, e1)
    if magnitude(n) == 0:
        return vector(0, 0, 0)
    return normalize(n)


@dataclass(slots=True, eq=True)
class Triangle(Shape):
    """Chapter 15: the triangle with corners ``p1``, ``p2``, ``p3`` (points).

    e1, e2: the edges p2 - p1 and p3 - p1; normal: the face normal (zero when degenerate).
    These three are computed when the triangle is built; change a corner through
    ``triangle()`` again, not by assignment.
    """

    p1: Tuple
    p2: Tuple
    p3: Tuple
    e1: Tuple = field(init=False)
    e2: Tuple = field(init=False)
    normal: Tuple = field(init=False)

    def __post_init__(self) -> None:
        self.e1 = self.p2 - self.p1
        self.e2 = self.p3 - self.p1
        self.normal = face_normal(self.e1, self.e2)

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 15: the Möller–Trumbore test; one intersection or none.

        A ray parallel to the triangle's plane misses (the determinant is within epsilon of
        zero); so does every ray against a degenerate triangle, whose determinant is 0.
        """
        dir_cross_e2 = cross(local_ray.direction, self.e2)
        det = dot(self.e1, dir_cross_e2)
        if abs(det) < epsilon():
            return []
        f = 1.0 / det
        p1_to_origin = local_ray.origin - self.p1
        u = f * dot(p1_to_origin, dir_cross_e2)
        if u < 0 or u > 1:
            return []
        origin_cross_e1 = cross(p1_to_origin, self.e1)
        v = f * dot(local_ray.direction, origin_cross_e1)
        if v < 0 or u + v > 1:
            return []
        t = f * dot(self.e2, origin_cross_e1)
        return [self.intersection_at(t, u, v)]

    def intersection_at(self, t: float, u: float, v: float) -> Intersection:
        """The intersection a hit at ``t`` produces; a flat triangle does not keep u and v."""
        return Intersection(t, self)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 15: the same normal everywhere on the face."""
        return self.normal

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the box around the three
        corners (a smooth triangle's too)."""
        p1, p2, p3 = self.p1, self.p2, self.p3
        return BoundingBox(
            point(min(p1.x, p2.x, p3.x), min(p1.y, p2.y, p3.y), min(p1.z, p2.z, p3.z)),
            point(max(p1.x, p2.x, p3.x), max(p1.y, p2.y, p3.y), max(p1.z, p2.z, p3.z)),
        )


def triangle(p1: Tuple, p2: Tuple, p3: Tuple) -> Triangle:
    """Chapter 15: a new triangle with corners ``p1``, ``p2``, ``p3``."""
    return Triangle(p1, p2, p3)
