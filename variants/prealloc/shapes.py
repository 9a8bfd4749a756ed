"""Shapes (chapters 5, 9, 12-16) intersecting into a reused intersection buffer and writing
their normals into a caller-owned buffer.

One record class per reference shape, built once per render context. A record holds the
shape's inverse and inverse transpose as flat lists, its material record, its parent's
record, and a ray buffer for the ray in its object space. ``local_intersect_into`` and
``local_normal_at_into`` are the twins of the reference's ``local_intersect`` and
``local_normal_at``: the same arithmetic in the same order, so the same floats. A group's
and a CSG shape's record keeps its bounding box (the bonus chapter 'Bounding boxes and
hierarchies'), computed once when the records are built, and tests it before its children.
"""

from __future__ import annotations

import math

from raytracer.bounds import BoundingBox
from raytracer.quartic import solve_quartic
from raytracer.rays import Ray
from raytracer.shapes.cone import Cone
from raytracer.shapes.csg import CSG, intersection_allowed
from raytracer.shapes.cube import Cube
from raytracer.shapes.cylinder import Cylinder
from raytracer.shapes.group import Group
from raytracer.shapes.plane import Plane
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.test_shape import TestShape
from raytracer.shapes.torus import Torus, torus_coefficients
from raytracer.shapes.triangle import Triangle
from raytracer.tuples import Tuple
from variants.prealloc.buffers import (
    IntersectionBuffer,
    Vec,
    add_intersection,
    new_ray,
    sort_intersections,
    tuple_buffer,
)
from variants.prealloc.errors import PreallocUnsupported, check_reimplemented
from variants.prealloc.geometry import flat_matrix, transform_point_into, transform_ray_into
from variants.prealloc.records import MaterialRecord

INF = math.inf


class ShapeRecord:
    """Chapter 9: what every shape record has.

    shape: the reference shape (what ``Intersection.object`` and ``comps.object`` are at
    the API boundary); inverse, inverse_transpose: flat 4x4 lists; parent: the parent's
    record or None; material: its ``MaterialRecord``; casts_shadow: the shape's flag;
    eps: the offset epsilon of the render; local_ray: the ray in object space (a buffer).
    """

    __slots__ = (
        "casts_shadow",
        "eps",
        "inverse",
        "inverse_transpose",
        "local_ray",
        "material",
        "parent",
        "shape",
    )

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        self.shape = shape
        self.inverse = flat_matrix(shape.inverse_transform)
        self.inverse_transpose = flat_matrix(shape.inverse_transpose)
        self.parent: ShapeRecord | None = None
        self.material = material
        self.casts_shadow = bool(shape.casts_shadow)
        self.eps = eps
        self.local_ray = new_ray()

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Append the intersections of an object-space ray (twin: ``local_intersect``)."""
        raise NotImplementedError

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """The object-space normal at an object-space point (twin: ``local_normal_at``)."""
        raise NotImplementedError

    def finish(self, children: list[ShapeRecord]) -> None:
        """Take the records of the shapes this one contains (groups and CSG only)."""


def intersect_into(rec: ShapeRecord, ray: Vec, xs: IntersectionBuffer) -> None:
    """Chapters 5 and 9: ``intersect(shape, ray)`` appended to ``xs``: the ray into object
    space (into the record's own ray buffer), then the shape's own test."""
    local = rec.local_ray
    transform_ray_into(rec.inverse, ray, local)
    rec.local_intersect_into(local, xs)


def normal_at_into(
    rec: ShapeRecord, point: Vec, u: float | None, v: float | None, out: Vec
) -> None:
    """Chapters 6, 9, 14: ``out = normal_at(shape, point, hit)`` (u, v: the hit's)."""
    world_to_object_into(rec, point, out)
    rec.local_normal_at_into(out, u, v, out)
    normal_to_world_into(rec, out, out)


def world_to_object_into(rec: ShapeRecord, point: Vec, out: Vec) -> None:
    """Chapter 14: ``out = world_to_object(shape, point)``, through every parent (naive
    twin: ``raytracer.shapes.space.world_to_object``)."""
    if rec.parent is not None:
        world_to_object_into(rec.parent, point, out)
        point = out
    transform_point_into(rec.inverse, point, out)


def normal_to_world_into(rec: ShapeRecord, normal: Vec, out: Vec) -> None:
    """Chapter 14: ``out = normal_to_world(shape, normal)``: through the inverse transpose,
    w dropped, normalized (a zero normal stays zero), then through every parent (naive
    twin: ``raytracer.shapes.space.normal_to_world``)."""
    m = rec.inverse_transpose
    x, y, z, w = normal
    nx = m[0] * x + m[1] * y + m[2] * z + m[3] * w
    ny = m[4] * x + m[5] * y + m[6] * z + m[7] * w
    nz = m[8] * x + m[9] * y + m[10] * z + m[11] * w
    if nx != 0 or ny != 0 or nz != 0:
        length = math.sqrt(nx * nx + ny * ny + nz * nz + 0.0 * 0.0)
        out[0] = nx / length
        out[1] = ny / length
        out[2] = nz / length
        out[3] = 0.0 / length
    else:
        out[0] = nx
        out[1] = ny
        out[2] = nz
        out[3] = 0.0
    if rec.parent is not None:
        normal_to_world_into(rec.parent, out, out)


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


class TriangleRecord(ShapeRecord):
    """Chapter 15: the triangle, with ``p1``, ``e1``, ``e2`` and ``normal`` as buffers."""

    __slots__ = ("e1", "e2", "normal", "p1")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, Triangle)
        self.p1 = tuple_buffer(shape.p1)
        self.e1 = tuple_buffer(shape.e1)
        self.e2 = tuple_buffer(shape.e2)
        self.normal = tuple_buffer(shape.normal)

    def add_hit(self, xs: IntersectionBuffer, t: float, u: float, v: float) -> None:
        """Twin of ``Triangle.intersection_at``: a flat triangle does not keep u and v."""
        add_intersection(xs, t, self)

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 15: Möller–Trumbore; twin: ``Triangle.local_intersect``."""
        ox, oy, oz, ow, dx, dy, dz, dw = ray
        e1x, e1y, e1z, e1w = self.e1
        e2x, e2y, e2z, e2w = self.e2
        # dir_cross_e2 = cross(direction, e2), a vector (w = 0.0)
        cx = dy * e2z - dz * e2y
        cy = dz * e2x - dx * e2z
        cz = dx * e2y - dy * e2x
        det = e1x * cx + e1y * cy + e1z * cz + e1w * 0.0
        if abs(det) < self.eps:
            return
        f = 1.0 / det
        p1x, p1y, p1z, p1w = self.p1
        px, py, pz, pw = ox - p1x, oy - p1y, oz - p1z, ow - p1w  # p1_to_origin
        u = f * (px * cx + py * cy + pz * cz + pw * 0.0)
        if u < 0 or u > 1:
            return
        # origin_cross_e1 = cross(p1_to_origin, e1), a vector (w = 0.0)
        qx = py * e1z - pz * e1y
        qy = pz * e1x - px * e1z
        qz = px * e1y - py * e1x
        v = f * (dx * qx + dy * qy + dz * qz + dw * 0.0)
        if v < 0 or u + v > 1:
            return
        t = f * (e2x * qx + e2y * qy + e2z * qz + e2w * 0.0)
        self.add_hit(xs, t, u, v)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 15: the face normal; twin: ``Triangle.local_normal_at``."""
        n = self.normal
        out[0], out[1], out[2], out[3] = n[0], n[1], n[2], n[3]


class SmoothTriangleRecord(TriangleRecord):
    """Chapter 15: the smooth triangle, with its corner normals as buffers."""

    __slots__ = ("n1", "n2", "n3")

    def __init__(self, shape: Shape, material: MaterialRecord, eps: float) -> None:
        super().__init__(shape, material, eps)
        assert isinstance(shape, SmoothTriangle)
        self.n1 = tuple_buffer(shape.n1)
        self.n2 = tuple_buffer(shape.n2)
        self.n3 = tuple_buffer(shape.n3)

    def add_hit(self, xs: IntersectionBuffer, t: float, u: float, v: float) -> None:
        """Twin of ``SmoothTriangle.intersection_at``: the hit keeps u and v."""
        add_intersection(xs, t, self, u, v)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        """Chapter 15: n2 * u + n3 * v + n1 * (1 - u - v); twin:
        ``SmoothTriangle.local_normal_at``."""
        if u is None or v is None:
            raise ValueError(
                "local_normal_at(SmoothTriangle): needs the hit with its u and v "
                "(an intersection from local_intersect or intersection_with_uv)"
            )
        n1, n2, n3 = self.n1, self.n2, self.n3
        rest = 1 - u - v
        out[0] = n2[0] * u + n3[0] * v + n1[0] * rest
        out[1] = n2[1] * u + n3[1] * v + n1[1] * rest
        out[2] = n2[2] * u + n3[2] * v + n1[2] * rest
        out[3] = n2[3] * u + n3[3] * v + n1[3] * rest


def box_buffer(box: BoundingBox) -> Vec | None:
    """A bounding box as ``[xmin, ymin, zmin, xmax, ymax, zmax]``, or None when it is empty
    (the bonus chapter)."""
    lo, hi = box.min, box.max
    if box.is_empty:
        return None
    return [float(lo.x), float(lo.y), float(lo.z), float(hi.x), float(hi.y), float(hi.z)]


def meets_box(box: Vec | None, ray: Vec, eps: float) -> bool:
    """The bonus chapter: whether an object-space ray's line passes through ``box`` (a
    ``box_buffer``); twin: ``raytracer.bounds.ray_meets_box``, the same divisions and
    comparisons, so the same answer. A slab the ray never enters ends the test at once."""
    if box is None:
        return False
    ox, oy, oz, _, dx, dy, dz, _ = ray
    tmin, tmax = -INF, INF
    lo, hi = box[0], box[3]
    inside = lo <= ox <= hi
    if inside and -eps < dx < eps:
        pass  # in the slab for all t, as for the cube
    elif dx != 0:
        tmin = (lo - ox) / dx
        tmax = (hi - ox) / dx
        if tmin > tmax:
            tmin, tmax = tmax, tmin
    elif not inside:
        return False
    lo, hi = box[1], box[4]
    inside = lo <= oy <= hi
    if inside and -eps < dy < eps:
        pass
    elif dy != 0:
        t1 = (lo - oy) / dy
        t2 = (hi - oy) / dy
        if t1 > t2:
            t1, t2 = t2, t1
        if t1 > tmin:
            tmin = t1
        if t2 < tmax:
            tmax = t2
    elif not inside:
        return False
    lo, hi = box[2], box[5]
    inside = lo <= oz <= hi
    if inside and -eps < dz < eps:
        pass
    elif dz != 0:
        t1 = (lo - oz) / dz
        t2 = (hi - oz) / dz
        if t1 > t2:
            t1, t2 = t2, t1
        if t1 > tmin:
            tmin = t1
        if t2 < tmax:
            tmax = t2
    elif not inside:
        return False
    return tmin <= tmax


class GroupRecord(ShapeRecord):
    """Chapter 14: a group; ``children`` are its children's records, ``box`` its bounding
    box (a ``box_buffer``, the bonus chapter)."""

    __slots__ = ("box", "children")

    def finish(self, children: list[ShapeRecord]) -> None:
        self.children = children
        self.box = box_buffer(self.shape.local_bounds())

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 14: every child's intersections, sorted by t (only the ones this group
        appended), none without asking them when the ray misses the box; twin:
        ``Group.local_intersect``."""
        if not meets_box(self.box, ray, self.eps):
            return
        start = xs.count
        for child in self.children:
            intersect_into(child, ray, xs)
        sort_intersections(xs, start)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        raise TypeError(
            "local_normal_at(Group): a group has no surface of its own; normals are computed "
            "on the child that was hit"
        )


class CSGRecord(ShapeRecord):
    """Chapter 16: ``left`` and ``right`` combined by an operation.

    allowed: ``intersection_allowed(operation, lhit, inl, inr)`` for all eight cases,
    indexed ``allowed[lhit][inl][inr]``; in_left: every record ``includes(left, ...)`` is
    true of; xs: the buffer for both operands' intersections before filtering; box: the
    bounding box around both operands (a ``box_buffer``, the bonus chapter).
    """

    __slots__ = ("allowed", "box", "in_left", "left", "right", "xs")

    def finish(self, children: list[ShapeRecord]) -> None:
        assert isinstance(self.shape, CSG)
        self.left, self.right = children
        operation = self.shape.operation
        self.allowed = tuple(
            tuple(
                tuple(intersection_allowed(operation, lhit, inl, inr) for inr in (False, True))
                for inl in (False, True)
            )
            for lhit in (False, True)
        )
        self.in_left = frozenset(subtree(self.left))
        self.xs = IntersectionBuffer()
        self.box = box_buffer(self.shape.local_bounds())

    def local_intersect_into(self, ray: Vec, xs: IntersectionBuffer) -> None:
        """Chapter 16: both operands' intersections, sorted, then filtered, none without
        asking them when the ray misses the box; twin: ``CSG.local_intersect``."""
        if not meets_box(self.box, ray, self.eps):
            return
        both = self.xs
        both.count = 0
        intersect_into(self.left, ray, both)
        intersect_into(self.right, ray, both)
        sort_intersections(both)
        filter_intersections_into(self, both, xs)

    def local_normal_at_into(self, point: Vec, u: float | None, v: float | None, out: Vec) -> None:
        raise TypeError(
            "local_normal_at(CSG): a CSG shape has no surface of its own; normals are "
            "computed on the operand that was hit"
        )


def subtree(rec: ShapeRecord) -> list[ShapeRecord]:
    """``rec`` and every record inside it (through groups and CSG operands): the records
    that chapter 16's ``includes(rec, ...)`` is true of."""
    found = [rec]
    if isinstance(rec, GroupRecord):
        for child in rec.children:
            found.extend(subtree(child))
    elif isinstance(rec, CSGRecord):
        found.extend(subtree(rec.left))
        found.extend(subtree(rec.right))
    return found


def filter_intersections_into(
    rec: CSGRecord, xs: IntersectionBuffer, out: IntersectionBuffer
) -> None:
    """Chapter 16: append to ``out`` the entries of ``xs`` (sorted by t) that the
    operation keeps; twin: ``raytracer.shapes.csg.filter_intersections``."""
    allowed, in_left = rec.allowed, rec.in_left
    ts, objects, us, vs = xs.ts, xs.objects, xs.us, xs.vs
    inl = inr = False
    for i in range(xs.count):
        obj = objects[i]
        lhit = obj in in_left
        if allowed[lhit][inl][inr]:
            add_intersection(out, ts[i], obj, us[i], vs[i])
        if lhit:
            inl = not inl
        else:
            inr = not inr


# reference class -> (record class, the methods the record reimplements)
SHAPE_RECORDS: dict[type[Shape], tuple[type[ShapeRecord], tuple[str, ...]]] = {
    Sphere: (SphereRecord, ("local_intersect", "local_normal_at")),
    Plane: (PlaneRecord, ("local_intersect", "local_normal_at")),
    TestShape: (TestShapeRecord, ("local_intersect", "local_normal_at")),
    Cube: (CubeRecord, ("local_intersect", "local_normal_at")),
    Cylinder: (CylinderRecord, ("local_intersect", "_intersect_caps", "local_normal_at")),
    Cone: (ConeRecord, ("local_intersect", "_intersect_caps", "local_normal_at")),
    Torus: (TorusRecord, ("local_intersect", "local_normal_at")),
    SmoothTriangle: (
        SmoothTriangleRecord,
        ("local_intersect", "intersection_at", "local_normal_at"),
    ),
    Triangle: (TriangleRecord, ("local_intersect", "intersection_at", "local_normal_at")),
    Group: (GroupRecord, ("local_intersect", "local_normal_at")),
    CSG: (CSGRecord, ("local_intersect", "local_normal_at")),
}


def record_class(shape: Shape) -> type[ShapeRecord]:
    """The record class for a reference shape (or a subclass that only caches, like
    ``cached``'s); ``PreallocUnsupported`` naming the type for anything else."""
    for cls in type(shape).__mro__:
        entry = SHAPE_RECORDS.get(cls)
        if entry is not None:
            record, methods = entry
            check_reimplemented(shape, cls, methods)
            return record
    raise PreallocUnsupported(
        f"prealloc: no implementation for shape type {type(shape).__name__}; it runs "
        f"{', '.join(cls.__name__ for cls in SHAPE_RECORDS)}"
    )
