"""Constructive solid geometry (chapter 16): two shapes combined by union, intersection or
difference, keeping only the intersections that lie on the combined solid's surface."""

from __future__ import annotations

from dataclasses import dataclass

from raytracer.bounds import BoundingBox, enclose, ray_meets_box, transform_box
from raytracer.rays import Ray
from raytracer.shapes.group import Group
from raytracer.shapes.shape import Intersection, Shape, intersect, intersections
from raytracer.tuples import Tuple

OPERATIONS = ("union", "intersection", "difference")


def _check_operation(operation: object, caller: str) -> str:
    if operation not in OPERATIONS:
        known = ", ".join(repr(name) for name in OPERATIONS)
        raise ValueError(f"{caller}: unknown CSG operation {operation!r}; choose {known}")
    return str(operation)


@dataclass(slots=True, eq=True)
class CSG(Shape):
    """Chapter 16: ``left`` and ``right`` combined by ``operation`` ("union",
    "intersection" or "difference": left minus right). Building one makes it the parent of
    both operands."""

    operation: str
    left: Shape
    right: Shape

    def __post_init__(self) -> None:
        _check_operation(self.operation, "CSG")
        self.left.parent = self
        self.right.parent = self

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 16: both operands' intersections, sorted by t, then filtered.

        The bonus chapter 'Bounding boxes and hierarchies': a ray that misses the box around
        both operands (``local_bounds``) misses them, which are then not asked at all.
        """
        if not ray_meets_box(self.local_bounds(), local_ray):
            return []
        xs = intersections(*intersect(self.left, local_ray), *intersect(self.right, local_ray))
        return filter_intersections(self, xs)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the box around both operands'
        boxes in the CSG shape's space, whatever the operation. Computed afresh on every
        call (the naive baseline; the ``cached`` variant keeps it)."""
        operands = (self.left, self.right)
        return enclose(transform_box(s.local_bounds(), s.transform) for s in operands)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 16: a CSG shape has no surface of its own; a hit is always on an operand."""
        raise TypeError(
            "local_normal_at(CSG): a CSG shape has no surface of its own; normals are "
            "computed on the operand that was hit"
        )


def csg(operation: str, left: Shape, right: Shape) -> CSG:
    """Chapter 16: a new CSG shape; ``operation`` is "union", "intersection" or
    "difference"."""
    return CSG(operation, left, right)


def intersection_allowed(operation: str, lhit: bool, inl: bool, inr: bool) -> bool:
    """Chapter 16: whether an intersection is on the combined surface.

    lhit: it is on the left operand (else the right); inl / inr: the ray is at that moment
    inside the left / right operand.
    """
    _check_operation(operation, "intersection_allowed")
    if operation == "union":
        return (lhit and not inr) or (not lhit and not inl)
    if operation == "intersection":
        return (lhit and inr) or (not lhit and inl)
    return (lhit and not inr) or (not lhit and inl)  # difference


def includes(container: Shape, shape: Shape) -> bool:
    """Chapter 16: True when ``shape`` is ``container`` itself or inside it (through groups
    and CSG operands). Shapes are matched by identity: two equal spheres are two shapes."""
    if container is shape:
        return True
    if isinstance(container, Group):
        return any(includes(child, shape) for child in container.children)
    if isinstance(container, CSG):
        return includes(container.left, shape) or includes(container.right, shape)
    return False


def filter_intersections(c: CSG, xs: list[Intersection]) -> list[Intersection]:
    """Chapter 16: the intersections (sorted by t) that ``c``'s operation keeps, in a new
    list; walks them in order, tracking whether the ray is inside each operand."""
    inl = inr = False
    kept: list[Intersection] = []
    for i in xs:
        lhit = includes(c.left, i.object)
        if intersection_allowed(c.operation, lhit, inl, inr):
            kept.append(i)
        if lhit:
            inl = not inl
        else:
            inr = not inr
    return kept
