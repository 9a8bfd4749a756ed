"""The plane (chapter 9): the xz plane of object space, infinite in x and z."""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, point, vector


@dataclass(slots=True, eq=True)
class Plane(Shape):
    """Chapter 9: the plane y = 0 in object space."""

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 9: one intersection, or none for a ray parallel to (or in) the plane."""
        if abs(local_ray.direction.y) < epsilon():
            return []
        t = -local_ray.origin.y / local_ray.direction.y
        return [Intersection(t, self)]

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 9: straight up, everywhere."""
        return vector(0, 1, 0)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': infinite in x and z, flat at
        y = 0."""
        return BoundingBox(point(-math.inf, 0, -math.inf), point(math.inf, 0, math.inf))


def plane() -> Plane:
    """Chapter 9: a new plane."""
    return Plane()
