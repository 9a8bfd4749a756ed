"""The double-napped cone (chapter 13): x² + z² = y², optionally truncated and capped."""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.cylinder import intersect_caps, side_hits
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, point, vector


@dataclass(slots=True, eq=True)
class Cone(Shape):
    """Chapter 13: two cones tip to tip at the object-space origin, opening along ±y.

    minimum, maximum: where the cone is cut off along y (exclusive; default unbounded);
    closed: True puts flat caps on the cut ends (radius |y| at each).
    """

    minimum: float = -math.inf
    maximum: float = math.inf
    closed: bool = False

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 13: the sides (a quadratic; when its squared term vanishes the ray runs
        parallel to one half and meets the other once), kept where minimum < y < maximum,
        then the caps."""
        origin, direction = local_ray.origin, local_ray.direction
        a = direction.x * direction.x - direction.y * direction.y + direction.z * direction.z
        b = 2 * (origin.x * direction.x - origin.y * direction.y + origin.z * direction.z)
        c = origin.x * origin.x - origin.y * origin.y + origin.z * origin.z
        ts: list[float] = []
        if abs(a) < epsilon():
            if abs(b) >= epsilon():
                ts.append(-c / (2 * b))
        else:
            discriminant = b * b - 4 * a * c
            if discriminant >= 0:
                root = math.sqrt(discriminant)
                t0 = (-b - root) / (2 * a)
                t1 = (-b + root) / (2 * a)
                ts.extend((t0, t1) if t0 <= t1 else (t1, t0))
        xs = side_hits(self, local_ray, tuple(ts), self.minimum, self.maximum)
        xs.extend(self._intersect_caps(local_ray))
        return xs

    def _intersect_caps(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 13: the caps at minimum and maximum, for a closed cone (radius |y|)."""
        if not self.closed:
            return []
        return intersect_caps(self, local_ray, self.minimum, self.maximum, abs)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 13: straight up or down on a cap; on the sides (x, ∓√(x² + z²), z),
        not normalized (``normal_at`` does that). At the tip it is the zero vector."""
        x, y, z = local_point.x, local_point.y, local_point.z
        distance = x * x + z * z
        if distance < self.maximum * self.maximum and y >= self.maximum - epsilon():
            return vector(0, 1, 0)
        if distance < self.minimum * self.minimum and y <= self.minimum + epsilon():
            return vector(0, -1, 0)
        side_y = math.sqrt(distance)
        if y > 0:
            side_y = -side_y
        return vector(x, side_y, z)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the radius at height y is |y|,
        so the widest end decides x and z; infinite when untruncated."""
        r = max(abs(self.minimum), abs(self.maximum))
        return BoundingBox(point(-r, self.minimum, -r), point(r, self.maximum, r))


def cone() -> Cone:
    """Chapter 13: a new open cone, infinitely long in both directions."""
    return Cone()
