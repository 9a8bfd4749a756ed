"""The unit sphere at the origin (chapter 5) and the glass sphere (chapter 11)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.materials import material
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tuples import Tuple, dot, point


@dataclass(slots=True, eq=True)
class Sphere(Shape):
    """Chapter 5: the sphere of radius 1 centred on the object-space origin."""

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 5: solve |origin + t * direction| = 1 for t (0 or 2 intersections)."""
        sphere_to_ray = local_ray.origin - point(0, 0, 0)
        a = dot(local_ray.direction, local_ray.direction)
        b = 2 * dot(local_ray.direction, sphere_to_ray)
        c = dot(sphere_to_ray, sphere_to_ray) - 1
        discriminant = b * b - 4 * a * c
        if discriminant < 0:
            return []
        root = math.sqrt(discriminant)
        t1 = (-b - root) / (2 * a)
        t2 = (-b + root) / (2 * a)
        return [Intersection(t1, self), Intersection(t2, self)]

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 6: from the centre through the point."""
        return local_point - point(0, 0, 0)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': from (-1, -1, -1) to
        (1, 1, 1)."""
        return BoundingBox(point(-1, -1, -1), point(1, 1, 1))


def sphere() -> Sphere:
    """Chapter 5: a new unit sphere."""
    return Sphere()


def glass_sphere() -> Sphere:
    """Chapter 11: a sphere of glass: transparency 1, refractive index 1.5."""
    return Sphere(material=material(transparency=1.0, refractive_index=1.5))
