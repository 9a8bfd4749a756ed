"""The cylinder (chapter 13): radius 1 around the y axis, optionally truncated and capped."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, point, vector


def within_radius(ray: Ray, t: float, radius: float) -> bool:
    """Chapter 13: True when the ray at ``t`` is within ``radius`` of the y axis (a cap)."""
    x = ray.origin.x + t * ray.direction.x
    z = ray.origin.z + t * ray.direction.z
    return x * x + z * z <= radius * radius


def intersect_caps(
    shape: Shape, local_ray: Ray, minimum: float, maximum: float, radius: Callable[[float], float]
) -> list[Intersection]:
    """Chapter 13: the hits on the end caps at y = minimum and y = maximum of a closed
    cylinder or cone; ``radius(y)``: the cap's radius at height y."""
    direction_y = local_ray.direction.y
    if abs(direction_y) < epsilon():
        return []
    xs: list[Intersection] = []
    for y in (minimum, maximum):
        t = (y - local_ray.origin.y) / direction_y
        if within_radius(local_ray, t, radius(y)):
            xs.append(Intersection(t, shape))
    return xs


def side_hits(
    shape: Shape, local_ray: Ray, ts: tuple[float, ...], minimum: float, maximum: float
) -> list[Intersection]:
    """Chapter 13: the side hits at ``ts`` that lie strictly between minimum and maximum
    along y (a truncated cylinder or cone)."""
    origin_y, direction_y = local_ray.origin.y, local_ray.direction.y
    return [Intersection(t, shape) for t in ts if minimum < origin_y + t * direction_y < maximum]


def _unit_radius(_: float) -> float:
    return 1.0


@dataclass(slots=True, eq=True)
class Cylinder(Shape):
    """Chapter 13: x² + z² = 1 in object space.

    minimum, maximum: where the cylinder is cut off along y (exclusive; default unbounded);
    closed: True puts flat caps on the cut ends.
    """

    minimum: float = -math.inf
    maximum: float = math.inf
    closed: bool = False

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 13: the side (a quadratic in x and z, kept where minimum < y < maximum),
        then the caps."""
        origin, direction = local_ray.origin, local_ray.direction
        xs: list[Intersection] = []
        a = direction.x * direction.x + direction.z * direction.z
        if abs(a) >= epsilon():  # not parallel to the y axis
            b = 2 * origin.x * direction.x + 2 * origin.z * direction.z
            c = origin.x * origin.x + origin.z * origin.z - 1
            discriminant = b * b - 4 * a * c
            if discriminant < 0:
                return []  # outside the infinite cylinder, so the caps are missed too
            root = math.sqrt(discriminant)
            t0 = (-b - root) / (2 * a)
            t1 = (-b + root) / (2 * a)
            if t0 > t1:
                t0, t1 = t1, t0
            xs = side_hits(self, local_ray, (t0, t1), self.minimum, self.maximum)
        xs.extend(self._intersect_caps(local_ray))
        return xs

    def _intersect_caps(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 13: the caps at minimum and maximum, for a closed cylinder."""
        if not self.closed:
            return []
        return intersect_caps(self, local_ray, self.minimum, self.maximum, _unit_radius)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 13: straight up or down on a cap, else away from the y axis."""
        distance = local_point.x * local_point.x + local_point.z * local_point.z
        if distance < 1 and local_point.y >= self.maximum - epsilon():
            return vector(0, 1, 0)
        if distance < 1 and local_point.y <= self.minimum + epsilon():
            return vector(0, -1, 0)
        return vector(local_point.x, 0, local_point.z)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': radius 1 around the y axis,
        from minimum to maximum along y (infinite when untruncated)."""
        return BoundingBox(point(-1, self.minimum, -1), point(1, self.maximum, 1))


def cylinder() -> Cylinder:
    """Chapter 13: a new open cylinder, infinitely long."""
    return Cylinder()
