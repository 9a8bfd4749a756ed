"""The records of the solid shapes (chapters 5, 9, 12, 13 and the torus): sphere, plane,
chapter 9's test shape, cube, cylinder, cone and torus, each the twin of the reference's
``local_intersect`` and ``local_normal_at``."""

from __future__ import annotations

import math

from raytracer.quartic import solve_quartic
from raytracer.rays import Ray
from raytracer.shapes.cone import Cone
from raytracer.shapes.cylinder import Cylinder
from raytracer.shapes.shape import Shape
from raytracer.shapes.test_shape import TestShape
from raytracer.shapes.torus import Torus, torus_coefficients
from raytracer.tuples import Tuple
from variants.prealloc.buffers import (
    IntersectionBuffer,
    Vec,
    add_intersection,
)
from variants.prealloc.records import MaterialRecord
from variants.prealloc.shapes import ShapeRecord

INF = math.inf


class SphereRecord(ShapeRecord):
    """Chapter 5: the unit sphere."""

    __slots__ = ()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 5: |origin + t * direction| = 1; twin: ``Sphere.local_intersect``."""
        ox, oy, oz, ow, dx, dy, dz, dw = ray
        # sphere_to_ray = origin - point(0, 0, 0): x - 0 is x, bit for bit
        sw = ow - 1.0
        a = dx * dx + dy * dy + dz * dz + dw * dw
        b = 2 * (dx * ox + dy * oy + dz * oz + dw * sw)
        c = ox * ox + oy * oy + oz * oz + sw * sw - 1
        discriminant = b * b - 4 * a * c
        if discriminant < 0:
            return
        root = math.sqrt(discriminant)
        add_intersection(xs, (-b - root) / (2 * a), self)
        add_intersection(xs, (-b + root) / (2 * a), self)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 6: point - point(0, 0, 0); twin: ``Sphere.local_normal_at``."""
        out[0] = point[0]
        out[1] = point[1]
        out[2] = point[2]
        out[3] = point[3] - 1.0


class PlaneRecord(ShapeRecord):
    """Chapter 9: the plane y = 0."""

    __slots__ = ()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 9: one intersection unless parallel; twin: ``Plane.local_intersect``."""
        dy = ray[5]
        if abs(dy) < self.eps:
            return
        add_intersection(xs, -ray[1] / dy, self)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 9: straight up; twin: ``Plane.local_normal_at``."""
        out[0] = 0.0
        out[1] = 1.0
        out[2] = 0.0
        out[3] = 0.0


class TestShapeRecord(ShapeRecord):
    """Chapter 9: the test shape: it records the object-space ray on the shape."""

    __test__ = False  # not a pytest test class, despite the name
    __slots__ = ()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 9: keep a copy of the ray (a reference Ray: the book reads it back);
        twin: ``TestShape.local_intersect``."""
        ox, oy, oz, ow, dx, dy, dz, dw = ray
        assert isinstance(self.shape, TestShape)
        self.shape.saved_ray = Ray(Tuple(ox, oy, oz, ow), Tuple(dx, dy, dz, dw))

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 9: the point as a vector; twin: ``TestShape.local_normal_at``."""
        out[0] = point[0]
        out[1] = point[1]
        out[2] = point[2]
        out[3] = 0.0


class CubeRecord(ShapeRecord):
    """Chapter 12: the cube from -1 to 1; ``slab`` holds one axis's [tmin, tmax]."""

    __slots__ = ("slab",)

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        self.slab = [0.0, 0.0]

    def check_axis_into(self, origin: float, direction: float) -> None:
        """Chapter 12: ``slab = [tmin, tmax]`` for one axis; twin: ``cube._check_axis``."""
        tmin_numerator = -1 - origin
        tmax_numerator = 1 - origin
        if abs(direction) >= self.eps:
            tmin = tmin_numerator / direction
            tmax = tmax_numerator / direction
        else:
            tmin = math.copysign(INF, tmin_numerator)
            tmax = math.copysign(INF, tmax_numerator)
        if tmin > tmax:
            tmin, tmax = tmax, tmin
        self.slab[0] = tmin
        self.slab[1] = tmax

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 12: the slab test; twin: ``Cube.local_intersect``. ``max``/``min`` of
        three are written out (the first of equal values wins, as with the builtins)."""
        slab = self.slab
        self.check_axis_into(ray[0], ray[4])
        tmin, tmax = slab
        self.check_axis_into(ray[1], ray[5])
        if slab[0] > tmin:
            tmin = slab[0]
        if slab[1] < tmax:
            tmax = slab[1]
        self.check_axis_into(ray[2], ray[6])
        if slab[0] > tmin:
            tmin = slab[0]
        if slab[1] < tmax:
            tmax = slab[1]
        if tmin > tmax:
            return
        add_intersection(xs, tmin, self)
        add_intersection(xs, tmax, self)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 12: along the largest coordinate; twin: ``Cube.local_normal_at``."""
        x, y, z = point[0], point[1], point[2]
        ax, ay, az = abs(x), abs(y), abs(z)
        largest = ax
        if ay > largest:
            largest = ay
        if az > largest:
            largest = az
        out[3] = 0.0
        if largest == ax:
            out[0], out[1], out[2] = x, 0.0, 0.0
        elif largest == ay:
            out[0], out[1], out[2] = 0.0, y, 0.0
        else:
            out[0], out[1], out[2] = 0.0, 0.0, z


class CylinderRecord(ShapeRecord):
    """Chapter 13: the cylinder of radius 1 around y, from ``minimum`` to ``maximum``."""

    __slots__ = ("closed", "maximum", "minimum")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, Cylinder | Cone)
        self.minimum = shape.minimum
        self.maximum = shape.maximum
        self.closed = shape.closed

    def add_side_hit(self, t: float, oy: float, dy: float, xs: IntersectionBuffer) -> None:
        """Chapter 13: keep a side hit only between minimum and maximum (exclusive)."""
        y = oy + t * dy
        if self.minimum < y < self.maximum:
            add_intersection(xs, t, self)

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 13: the side, then the caps; twin: ``Cylinder.local_intersect``."""
        ox, oy, oz, _, dx, dy, dz, _ = ray
        a = dx * dx + dz * dz
        if abs(a) >= self.eps:
            b = 2 * ox * dx + 2 * oz * dz
            c = ox * ox + oz * oz - 1
            discriminant = b * b - 4 * a * c
            if discriminant < 0:
                return  # outside the infinite cylinder, so the caps are missed too
            root = math.sqrt(discriminant)
            t0 = (-b - root) / (2 * a)
            t1 = (-b + root) / (2 * a)
            if t0 > t1:
                t0, t1 = t1, t0
            self.add_side_hit(t0, oy, dy, xs)
            self.add_side_hit(t1, oy, dy, xs)
        self.intersect_caps_into(ray, xs)

    def cap_radius(self, y: float) -> float:
        """The radius of the cap at height y: 1 for a cylinder."""
        return 1.0

    def intersect_caps_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 13: the caps of a closed shape; twin: ``_intersect_caps``."""
        ox, oy, oz, _, dx, dy, dz, _ = ray
        if not self.closed or abs(dy) < self.eps:
            return
        for y in (self.minimum, self.maximum):
            t = (y - oy) / dy
            # within_radius
            x = ox + t * dx
            z = oz + t * dz
            radius = self.cap_radius(y)
            if x * x + z * z <= radius * radius:
                add_intersection(xs, t, self)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 13: up or down on a cap, else away from the axis; twin:
        ``Cylinder.local_normal_at``."""
        x, y, z = point[0], point[1], point[2]
        distance = x * x + z * z
        out[3] = 0.0
        if distance < 1 and y >= self.maximum - self.eps:
            out[0], out[1], out[2] = 0.0, 1.0, 0.0
        elif distance < 1 and y <= self.minimum + self.eps:
            out[0], out[1], out[2] = 0.0, -1.0, 0.0
        else:
            out[0], out[1], out[2] = x, 0.0, z


class TorusRecord(ShapeRecord):
    """Chapter 20 (beyond the book): the torus of radii ``major`` and ``minor``."""

    __slots__ = ("major", "minor")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, Torus)
        self.major = shape.major_radius
        self.minor = shape.minor_radius

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 20: the quartic's real roots (the reference's coefficients and closed
        form: its few roots come back as a small list); twin: ``Torus.local_intersect``."""
        ox, oy, oz, _, dx, dy, dz, _ = ray
        a, b, c, d, e = torus_coefficients(ox, oy, oz, dx, dy, dz, self.major, self.minor)
        if a == 0:
            return
        for t in solve_quartic(a, b, c, d, e):
            add_intersection(xs, t, self)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 20: from the tube's centre circle; twin: ``Torus.local_normal_at``."""
        x, y, z = point[0], point[1], point[2]
        across = math.sqrt(x * x + z * z)
        out[3] = 0.0
        if across == 0:
            out[0], out[1], out[2] = 0.0, 1.0 if y >= 0 else -1.0, 0.0
            return
        scale = self.major / across
        out[0], out[1], out[2] = x - x * scale, y, z - z * scale


class ConeRecord(CylinderRecord):
    """Chapter 13: the double cone x² + z² = y², from ``minimum`` to ``maximum``."""

    __slots__ = ()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 13: the sides, then the caps; twin: ``Cone.local_intersect``."""
        ox, oy, oz, _, dx, dy, dz, _ = ray
        a = dx * dx - dy * dy + dz * dz
        b = 2 * (ox * dx - oy * dy + oz * dz)
        c = ox * ox - oy * oy + oz * oz
        eps = self.eps
        if abs(a) < eps:
            if abs(b) >= eps:
                self.add_side_hit(-c / (2 * b), oy, dy, xs)
        else:
            discriminant = b * b - 4 * a * c
            if discriminant >= 0:
                root = math.sqrt(discriminant)
                t0 = (-b - root) / (2 * a)
                t1 = (-b + root) / (2 * a)
                if not t0 <= t1:  # the reference's "(t0, t1) if t0 <= t1 else (t1, t0)"
                    t0, t1 = t1, t0
                self.add_side_hit(t0, oy, dy, xs)
                self.add_side_hit(t1, oy, dy, xs)
        self.intersect_caps_into(ray, xs)

    def cap_radius(self, y: float) -> float:
        """The radius of the cap at height y: |y| for a cone."""
        return abs(y)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 13: up or down on a cap, else (x, ∓√(x² + z²), z); twin:
        ``Cone.local_normal_at``."""
        x, y, z = point[0], point[1], point[2]
        distance = x * x + z * z
        out[3] = 0.0
        if distance < self.maximum * self.maximum and y >= self.maximum - self.eps:
            out[0], out[1], out[2] = 0.0, 1.0, 0.0
        elif distance < self.minimum * self.minimum and y <= self.minimum + self.eps:
            out[0], out[1], out[2] = 0.0, -1.0, 0.0
        else:
            side_y = math.sqrt(distance)
            if y > 0:
                side_y = -side_y
            out[0], out[1], out[2] = x, side_y, z
