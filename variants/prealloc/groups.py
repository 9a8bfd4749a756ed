"""The records of groups (chapter 14) and CSG shapes (chapter 16). A group's and a CSG
shape's record keeps its bounding box (the bonus chapter 'Bounding boxes and hierarchies'),
computed once when the records are built, and tests it before its children."""

from __future__ import annotations

import math

from raytracer.bounds import BoundingBox
from raytracer.shapes.csg import CSG, intersection_allowed
from variants.prealloc.buffers import (
    IntersectionBuffer,
    Vec,
    add_intersection,
    sort_intersections,
)
from variants.prealloc.shapes import ShapeRecord, intersect_into

INF = math.inf


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
