"""The axis-aligned cube (chapter 12): from -1 to 1 on every axis of object space."""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, point, vector


def _check_axis(origin: float, direction: float) -> tuple[float, float]:
    """Chapter 12: where a ray crosses the two faces at -1 and 1 on one axis, nearest first.

    A direction within epsilon of zero never reaches a face: the crossings are at plus or
    minus infinity, the ray being inside this slab for all t or for none. (The book multiplies
    by infinity; a ray lying exactly in a face's plane would give 0 * infinity = NaN, so the
    signs decide instead, and a ray in a face's plane counts as inside the slab.)
    """
    tmin_numerator = -1 - origin
    tmax_numerator = 1 - origin
    if abs(direction) >= epsilon():
        tmin = tmin_numerator / direction
        tmax = tmax_numerator / direction
    else:
        tmin = -math.inf if tmin_numerator <= 0 else math.inf
        tmax = math.inf if tmax_numerator >= 0 else -math.inf
    if tmin > tmax:
        tmin, tmax = tmax, tmin
    return tmin, tmax


@dataclass(slots=True, eq=True)
class Cube(Shape):
    """Chapter 12: the cube whose faces lie at x, y and z = -1 and 1 in object space."""

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 12: the slab test: the latest entry and the earliest exit over the three
        axes; the ray misses when it leaves one slab before entering another."""
        origin, direction = local_ray.origin, local_ray.direction
        xtmin, xtmax = _check_axis(origin.x, direction.x)
        ytmin, ytmax = _check_axis(origin.y, direction.y)
        ztmin, ztmax = _check_axis(origin.z, direction.z)
        tmin = max(xtmin, ytmin, ztmin)
        tmax = min(xtmax, ytmax, ztmax)
        if tmin > tmax:
            return []
        return [Intersection(tmin, self), Intersection(tmax, self)]

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 12: along the axis of the largest coordinate (x, then y, wins a tie)."""
        ax, ay, az = abs(local_point.x), abs(local_point.y), abs(local_point.z)
        largest = max(ax, ay, az)
        if largest == ax:
            return vector(local_point.x, 0, 0)
        if largest == ay:
            return vector(0, local_point.y, 0)
        return vector(0, 0, local_point.z)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': from (-1, -1, -1) to
        (1, 1, 1)."""
        return BoundingBox(point(-1, -1, -1), point(1, 1, 1))


def cube() -> Cube:
    """Chapter 12: a new cube."""
    return Cube()
