"""The torus (chapter 20 here, beyond the book): a tube of radius ``minor_radius`` around a
circle of radius ``major_radius`` in the xz plane, centred on the origin, around the y axis.

A point is on it where (x² + y² + z² + R² - r²)² = 4 R² (x² + z²). Along a ray that is a
quartic in t, solved in closed form (``raytracer.quartic``): the stiffest shape of the
project (rays grazing the tube or running along the axis meet it at nearly double roots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.bounds import BoundingBox
from raytracer.quartic import solve_quartic
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tuples import Tuple, point, vector


def torus_coefficients(
    ox: float, oy: float, oz: float, dx: float, dy: float, dz: float, big: float, small: float
) -> tuple[float, float, float, float, float]:
    """The quartic a t⁴ + b t³ + c t² + d t + e along the ray (o, d) for the torus of radii
    ``big`` (R) and ``small`` (r): (a, b, c, d, e)."""
    dd = dx * dx + dy * dy + dz * dz
    od = ox * dx + oy * dy + oz * dz
    oo = ox * ox + oy * oy + oz * oz
    k = oo + big * big - small * small
    four_r2 = 4 * big * big
    return (
        dd * dd,
        4 * dd * od,
        2 * dd * k + 4 * od * od - four_r2 * (dx * dx + dz * dz),
        4 * od * k - 2 * four_r2 * (ox * dx + oz * dz),
        k * k - four_r2 * (ox * ox + oz * oz),
    )


@dataclass(slots=True, eq=True)
class Torus(Shape):
    """Chapter 20: major_radius R (the tube's centre line, a circle in the xz plane) and
    minor_radius r (the tube's)."""

    major_radius: float = 1.0
    minor_radius: float = 0.25

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 20: the real roots of the quartic (``torus_coefficients``), up to four,
        in increasing t."""
        o, d = local_ray.origin, local_ray.direction
        a, b, c, d_, e = torus_coefficients(
            o.x, o.y, o.z, d.x, d.y, d.z, self.major_radius, self.minor_radius
        )
        if a == 0:
            return []  # a direction of length zero
        return [Intersection(t, self) for t in solve_quartic(a, b, c, d_, e)]

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 20: from the nearest point of the tube's centre circle to the point (not
        normalized; ``normal_at`` does that)."""
        x, y, z = local_point.x, local_point.y, local_point.z
        across = math.sqrt(x * x + z * z)
        if across == 0:  # on the axis: only a torus fatter than its hole reaches it
            return vector(0, 1 if y >= 0 else -1, 0)
        scale = self.major_radius / across
        return vector(x - x * scale, y, z - z * scale)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': R + r across, r up and down."""
        outer = self.major_radius + self.minor_radius
        return BoundingBox(
            point(-outer, -self.minor_radius, -outer), point(outer, self.minor_radius, outer)
        )


def torus() -> Torus:
    """Chapter 20: a new torus, radii 1 and 0.25."""
    return Torus()
