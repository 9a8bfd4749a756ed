"""Groups (chapter 14): a shape made of other shapes, whose transform applies to them all.

A group is an entity like every shape: ``add_child`` appends to ``children`` and sets the
child's ``parent``. Groups compare by value through their children (a child's ``parent`` is
never compared, so equality does not loop back up the tree).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.bounds import BoundingBox, enclose, ray_meets_box, transform_box
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape, intersect, intersections
from raytracer.tuples import Tuple


@dataclass(slots=True, eq=True)
class Group(Shape):
    """Chapter 14: ``children``, the shapes in the group, in the order they were added."""

    children: list[Shape] = field(default_factory=list)

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 14: every child's intersections with the ray, in one list sorted by t.

        The bonus chapter 'Bounding boxes and hierarchies': a ray that misses the group's
        box (``local_bounds``) misses every child, which are then not asked at all.
        """
        if not ray_meets_box(self.local_bounds(), local_ray):
            return []
        xs: list[Intersection] = []
        for child in self.children:
            xs.extend(intersect(child, local_ray))
        return intersections(*xs)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the box around every child's
        box in the group's space (each child's ``parent_space_bounds_of``); empty for an
        empty group. Computed afresh on every call, so it never goes stale when a child
        changes (the naive baseline; the ``cached`` variant keeps it)."""
        return enclose(transform_box(c.local_bounds(), c.transform) for c in self.children)

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 14: a group has no surface of its own; a hit is always on a child."""
        raise TypeError(
            "local_normal_at(Group): a group has no surface of its own; normals are computed "
            "on the child that was hit"
        )


def group() -> Group:
    """Chapter 14: a new, empty group."""
    return Group()


def add_child(g: Group, shape: Shape) -> None:
    """Chapter 14: put ``shape`` into ``g`` and make ``g`` its parent.

    A group cannot contain itself, directly or through its own parents (that would make
    intersecting it loop forever): such a call is a ``ValueError``.
    """
    ancestor: Shape | None = g
    while ancestor is not None:
        if ancestor is shape:
            raise ValueError(
                f"add_child({type(g).__name__}, {type(shape).__name__}): the shape is the "
                "group itself or one of its parents; a group cannot contain itself"
            )
        ancestor = ancestor.parent
    g.children.append(shape)
    shape.parent = g
