"""The robust variant's shapes (chapters 5, 9, 12, 13, 15): intersections that stay right
when the scene is very large, very small, or far from the origin.

Each shape is a twin of ``cached``'s (inverse transforms computed once, when set) with its own
``local_intersect``:

- quadratics (sphere, cylinder, cone) are solved without cancellation: the discriminant comes
  from cross products (Lagrange's identity, ``b² - ac = a - |o × d|²`` for the unit sphere)
  instead of subtracting two large squares, and the roots as ``q / a`` and ``c / q`` with
  ``q = -(b + sign(b) √disc)`` instead of ``(-b ± √disc) / 2a``;
- "parallel" tests (plane, cube slabs, cylinder and cone sides and caps) ask whether the
  direction component is exactly 0, not whether it is below ``EPSILON``: in object space a
  direction's length is 1 / (the object's scale), so a fixed threshold loses every hit on an
  object scaled by 1e4 or more;
- a triangle is missed when the ray lies in its plane, or its corners lie on one line, to
  within 2**-40 of the sizes involved (a relative test, the same at every scale);
- an intersection at an infinite or NaN distance is no intersection;
- a torus's quartic is not solved in closed form (the reference's Ferrari, whose fixed
  tolerance loses or invents roots near double ones and means something else at every
  scale): the ray's origin is moved to its closest approach to the torus's centre (the
  coefficients stay of the size of the torus however far the ray comes from) and the
  quartic's roots are isolated between its turning points and refined by Newton steps kept
  inside each stretch (``variants.robust.roots``); a turning point where the quartic is
  zero to within its rounding is a double root (a ray grazing the tube).

The one exception is the cone's ray parallel to one half (its quadratic term exactly 0): the
book's scenario expects ``t = -c / 2b`` (with the book's ``b``, twice the one here), half the
true distance, and this variant keeps the book's answer there.

A shape whose transform is singular (assigned directly, bypassing ``set_transform``) raises a
``NotInvertibleError`` naming the shape when it is used, and so does the camera.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from raytracer.intersections import Intersection
from raytracer.patterns import Pattern
from raytracer.rays import Ray
from raytracer.shapes.cone import Cone
from raytracer.shapes.cube import Cube
from raytracer.shapes.cylinder import Cylinder, within_radius
from raytracer.shapes.plane import Plane
from raytracer.shapes.shape import Shape
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.torus import Torus, torus_coefficients
from raytracer.shapes.triangle import Triangle
from variants.cached import CACHED_CLASSES, derive_class
from variants.robust.roots import real_roots

# a triangle is missed when det² <= FLAT² |e1|² |e2|² |d|² (the sine of the angle between the
# ray and the plane, or between the triangle's sides, below 2**-40, about 1e-12)
FLAT = 2.0**-40
_FLAT_SQUARED = FLAT * FLAT


def _finite(*ts: float) -> bool:
    return all(math.isfinite(t) for t in ts)


def _roots(a: float, half_b: float, c: float, disc: float) -> tuple[float, float]:
    """The two roots of ``a t² + 2 half_b t + c`` (``disc = half_b² - a c >= 0``, ``a != 0``),
    smaller first, each computed without cancellation."""
    q = -(half_b + math.copysign(math.sqrt(disc), half_b))
    if q == 0.0:  # half_b = 0 and disc = 0, so c = 0: a double root at 0
        return 0.0, 0.0
    t0, t1 = q / a, c / q
    return (t0, t1) if t0 <= t1 else (t1, t0)


class RobustShape:
    """Base of the solver mixins below; a shape without its own solver (a group, CSG) gets
    it alone and keeps ``cached``'s intersection. (A singular transform is already reported
    by name by the reference's ``inverse_transform``, which ``cached`` falls back to.)"""

    __slots__ = ()


class SphereSolver(RobustShape):
    """Chapter 5's unit sphere, solved without cancellation."""

    __slots__ = ()

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        o, d = local_ray.origin, local_ray.direction
        a = d.x * d.x + d.y * d.y + d.z * d.z
        if a == 0.0:
            return []
        half_b = o.x * d.x + o.y * d.y + o.z * d.z
        cx = o.y * d.z - o.z * d.y
        cy = o.z * d.x - o.x * d.z
        cz = o.x * d.y - o.y * d.x
        disc = a - (cx * cx + cy * cy + cz * cz)  # = half_b² - a c, by Lagrange's identity
        if disc < 0.0:
            return []
        c = o.x * o.x + o.y * o.y + o.z * o.z - 1.0
        t0, t1 = _roots(a, half_b, c, disc)
        if not _finite(t0, t1):
            return []
        shape: Any = self
        return [Intersection(t0, shape), Intersection(t1, shape)]


class PlaneSolver(RobustShape):
    """Chapter 9's plane: parallel only when the direction's y is exactly 0."""

    __slots__ = ()

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        dy = local_ray.direction.y
        if dy == 0.0:
            return []
        t = -local_ray.origin.y / dy
        if not math.isfinite(t):
            return []
        shape: Any = self
        return [Intersection(t, shape)]


def _check_axis(origin: float, direction: float) -> tuple[float, float]:
    """Chapter 12's slab on one axis; a direction of exactly 0 never reaches a face (the
    signs decide, as in the reference), any other divides (giving ±inf when it overflows)."""
    tmin_numerator = -1.0 - origin
    tmax_numerator = 1.0 - origin
    if direction != 0.0:
        tmin = tmin_numerator / direction
        tmax = tmax_numerator / direction
    else:
        tmin = -math.inf if tmin_numerator <= 0 else math.inf
        tmax = math.inf if tmax_numerator >= 0 else -math.inf
    return (tmin, tmax) if tmin <= tmax else (tmax, tmin)


class CubeSolver(RobustShape):
    """Chapter 12's cube with exact parallel tests."""

    __slots__ = ()

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        o, d = local_ray.origin, local_ray.direction
        xtmin, xtmax = _check_axis(o.x, d.x)
        ytmin, ytmax = _check_axis(o.y, d.y)
        ztmin, ztmax = _check_axis(o.z, d.z)
        tmin = max(xtmin, ytmin, ztmin)
        tmax = min(xtmax, ytmax, ztmax)
        if tmin > tmax or not _finite(tmin, tmax):
            return []
        shape: Any = self
        return [Intersection(tmin, shape), Intersection(tmax, shape)]


class CylinderSolver(RobustShape):
    """Chapter 13's cylinder: the side solved without cancellation, exact parallel tests."""

    __slots__ = ()
    minimum: float
    maximum: float
    closed: bool

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        o, d = local_ray.origin, local_ray.direction
        shape: Any = self
        xs: list[Intersection] = []
        a = d.x * d.x + d.z * d.z
        if a != 0.0:  # not parallel to the y axis
            half_b = o.x * d.x + o.z * d.z
            cross = o.x * d.z - o.z * d.x
            disc = a - cross * cross  # = half_b² - a c
            if disc < 0.0:
                return []  # outside the infinite cylinder, so the caps are missed too
            c = o.x * o.x + o.z * o.z - 1.0
            for t in _roots(a, half_b, c, disc):
                y = o.y + t * d.y
                if math.isfinite(t) and self.minimum < y < self.maximum:
                    xs.append(Intersection(t, shape))
        if self.closed and d.y != 0.0:
            for y in (self.minimum, self.maximum):
                t = (y - o.y) / d.y
                if math.isfinite(t) and within_radius(local_ray, t, 1.0):
                    xs.append(Intersection(t, shape))
        return xs


class ConeSolver(RobustShape):
    """Chapter 13's cone: the sides solved without cancellation (the discriminant from the
    2x2 minors of origin and direction, the squared term as a product of a difference),
    exact parallel tests."""

    __slots__ = ()
    minimum: float
    maximum: float
    closed: bool

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        o, d = local_ray.origin, local_ray.direction
        shape: Any = self
        # dz² - dy² as (dz - dy)(dz + dy): exact-ish when the ray runs nearly along a side
        a = d.x * d.x + (d.z - d.y) * (d.z + d.y)
        half_b = o.x * d.x - o.y * d.y + o.z * d.z
        c = o.x * o.x - o.y * o.y + o.z * o.z
        ts: tuple[float, ...] = ()
        if a == 0.0:
            if half_b != 0.0:
                # the book's -c / 2b with its b = 2 half_b (its scenario expects this value)
                ts = (-c / (4.0 * half_b),)
        else:
            m_xy = o.x * d.y - o.y * d.x
            m_yz = o.y * d.z - o.z * d.y
            m_xz = o.x * d.z - o.z * d.x
            disc = m_xy * m_xy + m_yz * m_yz - m_xz * m_xz  # = half_b² - a c
            if disc >= 0.0:
                ts = _roots(a, half_b, c, disc)
        xs: list[Intersection] = []
        for t in ts:
            y = o.y + t * d.y
            if math.isfinite(t) and self.minimum < y < self.maximum:
                xs.append(Intersection(t, shape))
        if self.closed and d.y != 0.0:
            for y in (self.minimum, self.maximum):
                t = (y - o.y) / d.y
                if math.isfinite(t) and within_radius(local_ray, t, abs(y)):
                    xs.append(Intersection(t, shape))
        return xs


class TriangleSolver(RobustShape):
    """Chapter 15's Möller–Trumbore test with a relative flatness test (see ``FLAT``)."""

    __slots__ = ()
    p1: Any
    e1: Any
    e2: Any

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        d, e1, e2 = local_ray.direction, self.e1, self.e2
        # d x e2
        qx = d.y * e2.z - d.z * e2.y
        qy = d.z * e2.x - d.x * e2.z
        qz = d.x * e2.y - d.y * e2.x
        det = e1.x * qx + e1.y * qy + e1.z * qz
        e1e1 = e1.x * e1.x + e1.y * e1.y + e1.z * e1.z
        e2e2 = e2.x * e2.x + e2.y * e2.y + e2.z * e2.z
        dd = d.x * d.x + d.y * d.y + d.z * d.z
        if det * det <= _FLAT_SQUARED * e1e1 * e2e2 * dd:
            return []  # in the triangle's plane, or the triangle has no area
        f = 1.0 / det
        o = local_ray.origin
        px, py, pz = o.x - self.p1.x, o.y - self.p1.y, o.z - self.p1.z
        u = f * (px * qx + py * qy + pz * qz)
        if u < 0 or u > 1:
            return []
        # (origin - p1) x e1
        rx = py * e1.z - pz * e1.y
        ry = pz * e1.x - px * e1.z
        rz = px * e1.y - py * e1.x
        v = f * (d.x * rx + d.y * ry + d.z * rz)
        if v < 0 or u + v > 1:
            return []
        t = f * (e2.x * rx + e2.y * ry + e2.z * rz)
        if not math.isfinite(t):
            return []
        shape: Any = self  # the reference Triangle (or SmoothTriangle) makes the hit
        return [shape.intersection_at(t, u, v)]


def torus_roots(
    ox: float, oy: float, oz: float, dx: float, dy: float, dz: float, big: float, small: float
) -> list[float]:
    """Chapter 20's intersections (see the module): the real roots t of the torus's quartic
    along the ray (``roots.real_roots``), increasing, each to a unit or two in the last
    place; a double root listed twice."""
    dd = dx * dx + dy * dy + dz * dz
    if dd == 0.0 or not math.isfinite(dd):
        return []
    shift = -(ox * dx + oy * dy + oz * dz) / dd  # the closest approach to the centre
    px, py, pz = ox + shift * dx, oy + shift * dy, oz + shift * dz
    c = torus_coefficients(px, py, pz, dx, dy, dz, big, small)
    if not all(math.isfinite(v) for v in c):
        return []
    return [r + shift for r in real_roots(c) if math.isfinite(r + shift)]


class TorusSolver(RobustShape):
    """Chapter 20's torus: its quartic's roots isolated and refined (``torus_roots``)."""

    __slots__ = ()

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        o, d = local_ray.origin, local_ray.direction
        shape: Any = self
        ts = torus_roots(o.x, o.y, o.z, d.x, d.y, d.z, shape.major_radius, shape.minor_radius)
        return [Intersection(t, shape) for t in ts]


# reference class -> the mixin that replaces its intersection (every other shape: RobustShape)
_MIXINS: dict[type, type] = {
    Torus: TorusSolver,
    Sphere: SphereSolver,
    Plane: PlaneSolver,
    Cube: CubeSolver,
    Cylinder: CylinderSolver,
    Cone: ConeSolver,
    Triangle: TriangleSolver,
}


def _mixin_for(reference: type) -> type:
    for base in reference.__mro__:
        if base in _MIXINS:
            return _MIXINS[base]
    return RobustShape


def _derive_twins() -> dict[type, type]:
    """Every reference class -> its robust twin: shapes derive from ``cached``'s twins with
    the mixin above; patterns and the camera stay ``cached``'s twins."""
    twins: dict[type, type] = {}
    for reference, cached in CACHED_CLASSES.items():
        if issubclass(reference, Pattern):
            twins[reference] = cached
        elif issubclass(reference, Shape):
            name = f"Robust{reference.__name__}"
            twin = derive_class(_mixin_for(reference), cached, name, __name__)
            globals()[name] = twin  # so that pickle finds it (pooled workers)
            twins[reference] = twin
        else:
            twins[reference] = cached
    return twins


ROBUST_CLASSES: Mapping[type, type] = _derive_twins()
