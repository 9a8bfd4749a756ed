"""Axis-aligned bounding boxes (the bonus chapter 'Bounding boxes and hierarchies').

A ``BoundingBox`` is an immutable value, like a point: the book's ``add_point(box, p)`` and
``add_box(box1, box2)`` change the box in place, here they return a new box. The step library
rebinds the first argument's name when a statement's result has its type, so the book's
statement ``add_point(box, p)`` reads unchanged (and ``box ← add_point(box, p)`` works too).

Extents may be infinite (a plane, an untruncated cylinder). The empty box has
``min = point(∞, ∞, ∞)`` and ``max = point(-∞, -∞, -∞)``; any box whose ``min`` exceeds its
``max`` on some axis contains nothing and is treated as empty.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from raytracer.matrices import Matrix
from raytracer.rays import Ray
from raytracer.rays import transform as transform_ray
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, point

INF = math.inf

__all__ = [
    "BoundingBox",
    "add_box",
    "add_point",
    "bounding_box",
    "box_contains_box",
    "box_contains_point",
    "intersects",
    "split_bounds",
    "transform",
    "transform_box",
]


@dataclass(frozen=True, slots=True)
class BoundingBox:
    """The bonus chapter's box: every point p with ``min <= p <= max`` on all three axes.

    min, max: opposite corners (points; coordinates may be ±infinity).
    """

    min: Tuple
    max: Tuple

    @property
    def is_empty(self) -> bool:
        """True when the box contains no point (``min`` above ``max`` on some axis)."""
        lo, hi = self.min, self.max
        return lo.x > hi.x or lo.y > hi.y or lo.z > hi.z


EMPTY = BoundingBox(point(INF, INF, INF), point(-INF, -INF, -INF))
UNBOUNDED = BoundingBox(point(-INF, -INF, -INF), point(INF, INF, INF))


def _describe(value: object) -> str:
    return type(value).__name__


def _check_point(value: object, caller: str, what: str) -> Tuple:
    if not isinstance(value, Tuple) or value.w != 1:
        shown = "a vector" if isinstance(value, Tuple) else _describe(value)
        raise TypeError(f"{caller}: {what} must be a point, got {shown}")
    return value


def _check_box(value: object, caller: str, what: str = "the box") -> BoundingBox:
    if not isinstance(value, BoundingBox):
        raise TypeError(f"{caller}: {what} must be a bounding box, got {_describe(value)}")
    return value


def bounding_box(min: Tuple | None = None, max: Tuple | None = None) -> BoundingBox:
    """The bonus chapter: ``bounding_box(empty)`` (no arguments here) is the empty box;
    ``bounding_box(min=p, max=q)`` the box with corners ``p`` and ``q`` (points)."""
    if min is None and max is None:
        return EMPTY
    if min is None or max is None:
        given = "min" if max is None else "max"
        raise TypeError(
            f"bounding_box: only {given} given; give both min and max, or neither for an empty box"
        )
    return BoundingBox(
        _check_point(min, "bounding_box", "min"), _check_point(max, "bounding_box", "max")
    )


def _grow(box: BoundingBox, lo: Tuple, hi: Tuple) -> BoundingBox:
    """``box`` grown to take in the corners ``lo`` and ``hi`` (no checks)."""
    bmin, bmax = box.min, box.max
    return BoundingBox(
        point(min(bmin.x, lo.x), min(bmin.y, lo.y), min(bmin.z, lo.z)),
        point(max(bmax.x, hi.x), max(bmax.y, hi.y), max(bmax.z, hi.z)),
    )


def add_point(box: BoundingBox, p: Tuple) -> BoundingBox:
    """The bonus chapter: ``box`` grown just enough to contain the point ``p`` (a new box)."""
    _check_box(box, "add_point")
    _check_point(p, "add_point", "the point")
    return _grow(box, p, p)


def add_box(box1: BoundingBox, box2: BoundingBox) -> BoundingBox:
    """The bonus chapter: the smallest box containing ``box1`` and ``box2`` (a new box).

    Taken axis by axis (the smaller min, the larger max), so adding the empty box changes
    nothing (adding its two corners as points, as the book does, would make it infinite).
    """
    _check_box(box1, "add_box", "box1")
    _check_box(box2, "add_box", "box2")
    return _grow(box1, box2.min, box2.max)


def enclose(boxes: Iterable[BoundingBox]) -> BoundingBox:
    """The smallest box containing every box of ``boxes`` (the empty box for none): the
    bonus chapter's repeated ``add_box``, without its checks, for groups and CSG shapes."""
    box = EMPTY
    for other in boxes:
        box = _grow(box, other.min, other.max)
    return box


def box_contains_point(box: BoundingBox, p: Tuple) -> bool:
    """The bonus chapter: True when ``p`` is inside ``box`` or on its surface."""
    _check_box(box, "box_contains_point")
    _check_point(p, "box_contains_point", "the point")
    lo, hi = box.min, box.max
    return lo.x <= p.x <= hi.x and lo.y <= p.y <= hi.y and lo.z <= p.z <= hi.z


def box_contains_box(box: BoundingBox, box2: BoundingBox) -> bool:
    """The bonus chapter: True when ``box2`` lies entirely inside ``box`` (both of its
    corners are in ``box``)."""
    _check_box(box, "box_contains_box")
    _check_box(box2, "box_contains_box", "box2")
    return box_contains_point(box, box2.min) and box_contains_point(box, box2.max)


def _range(row: tuple[float, ...], lo: Tuple, hi: Tuple) -> tuple[float, float]:
    """The least and greatest value of ``row · (x, y, z, 1)`` over the box ``lo``..``hi``.

    Each term is taken at the corner that makes it least (or greatest): the same as
    transforming all eight corners, and a zero coefficient never meets an infinite
    coordinate (0 * ∞ would be NaN).
    """
    least = greatest = row[3]
    for m, a, b in ((row[0], lo.x, hi.x), (row[1], lo.y, hi.y), (row[2], lo.z, hi.z)):
        if m == 0:
            continue
        ma, mb = m * a, m * b
        if ma <= mb:
            least, greatest = least + ma, greatest + mb
        else:
            least, greatest = least + mb, greatest + ma
    return least, greatest


def transform_box(box: BoundingBox, m: Matrix) -> BoundingBox:
    """The bonus chapter: the axis-aligned box around ``box`` transformed by ``m`` (an affine
    4x4 matrix): the box of its eight transformed corners. The empty box stays empty."""
    if box.is_empty:
        return EMPTY
    lo, hi = box.min, box.max
    (xmin, xmax), (ymin, ymax), (zmin, zmax) = (_range(m.rows[r], lo, hi) for r in range(3))
    return BoundingBox(point(xmin, ymin, zmin), point(xmax, ymax, zmax))


def transform(value: Ray | BoundingBox, m: Matrix) -> Ray | BoundingBox:
    """Chapter 5 (a ray) and the bonus chapter (a bounding box): ``value`` transformed by
    ``m``, a new ray or a new box."""
    if isinstance(value, Ray):
        return transform_ray(value, m)
    if isinstance(value, BoundingBox):
        if not isinstance(m, Matrix) or m.size != 4:
            raise TypeError(f"transform(BoundingBox): expected a 4x4 matrix, got {_describe(m)}")
        return transform_box(value, m)
    raise TypeError(
        f"transform({_describe(value)}): expected a ray or a bounding box to transform, "
        f"got {_describe(value)}"
    )


def _slab(origin: float, direction: float, lo: float, hi: float, eps: float) -> tuple[float, float]:
    """Where a ray is between ``lo`` and ``hi`` on one axis, as ``(t_enter, t_leave)``.

    The cube's ``check_axis`` (chapter 12) for any slab, made generous so that a box never
    misses a ray that a shape inside it meets: with the origin between the faces, a
    direction within ``eps`` of zero is in the slab for all t, as for the cube; any other
    nonzero direction divides (the cube's EPSILON test alone would miss a scaled-up group's
    short object-space rays), and a zero one is in the slab for all t or for none.
    """
    inside = lo <= origin <= hi
    if inside and -eps < direction < eps:
        return -INF, INF
    if direction != 0:
        t1 = (lo - origin) / direction
        t2 = (hi - origin) / direction
        return (t1, t2) if t1 <= t2 else (t2, t1)
    return (-INF, INF) if inside else (INF, -INF)


def ray_meets_box(box: BoundingBox, r: Ray) -> bool:
    """``intersects`` without its argument checks: for groups' and CSG shapes' hot path."""
    lo, hi = box.min, box.max
    if lo.x > hi.x or lo.y > hi.y or lo.z > hi.z:
        return False
    origin, direction, eps = r.origin, r.direction, epsilon()
    xmin, xmax = _slab(origin.x, direction.x, lo.x, hi.x, eps)
    ymin, ymax = _slab(origin.y, direction.y, lo.y, hi.y, eps)
    zmin, zmax = _slab(origin.z, direction.z, lo.z, hi.z, eps)
    return max(xmin, ymin, zmin) <= min(xmax, ymax, zmax)


def intersects(box: BoundingBox, r: Ray) -> bool:
    """The bonus chapter: True when the line of ``r`` passes through ``box`` (the cube's slab
    test on any box, chapter 12). As in the book, a box behind the ray's origin counts: a
    group's intersections include negative t."""
    _check_box(box, "intersects")
    if not isinstance(r, Ray):
        raise TypeError(f"intersects: the ray must be a ray, got {_describe(r)}")
    return ray_meets_box(box, r)


def _middle(lo: float, hi: float) -> float:
    """Where to cut ``lo``..``hi``: halfway; an infinite extent has no middle, so it is cut
    at 0 (both ends infinite) or at its finite end."""
    if math.isinf(lo) and math.isinf(hi):
        return 0.0
    if math.isinf(lo):
        return hi
    if math.isinf(hi):
        return lo
    return lo + (hi - lo) / 2


def split_bounds(box: BoundingBox) -> tuple[BoundingBox, BoundingBox]:
    """The bonus chapter: ``box`` cut in two across its longest axis (x, then y, then z
    on a tie), at the middle: ``(left, right)``, left holding the smaller coordinates.
    Both halves of the empty box are empty."""
    _check_box(box, "split_bounds")
    if box.is_empty:
        return EMPTY, EMPTY
    lo, hi = box.min, box.max
    dx, dy, dz = hi.x - lo.x, hi.y - lo.y, hi.z - lo.z
    greatest = max(dx, dy, dz)
    x0, y0, z0 = lo.x, lo.y, lo.z
    x1, y1, z1 = hi.x, hi.y, hi.z
    if greatest == dx:
        x0 = x1 = _middle(lo.x, hi.x)
    elif greatest == dy:
        y0 = y1 = _middle(lo.y, hi.y)
    else:
        z0 = z1 = _middle(lo.z, hi.z)
    left = BoundingBox(lo, point(x1, y1, z1))
    right = BoundingBox(point(x0, y0, z0), hi)
    return left, right
