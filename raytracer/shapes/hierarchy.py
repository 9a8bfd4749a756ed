"""Bounding volume hierarchies (the bonus chapter 'Bounding boxes and hierarchies'): a group
with many children is split into subgroups by where the children lie, recursively, so that a
ray missing a subgroup's box skips all of its children at once.

These change groups in place, as the book does (a group is an entity). A subgroup is made of
its group's own class, so a variant's group (``cached``'s) makes subgroups of its kind.
"""

from __future__ import annotations

from collections.abc import Sequence

from raytracer.bounds import BoundingBox, box_contains_box, enclose, split_bounds, transform_box
from raytracer.matrices import book_name
from raytracer.shapes.csg import CSG
from raytracer.shapes.group import Group, add_child
from raytracer.shapes.shape import Shape

__all__ = ["divide", "make_subgroup", "partition_children"]


def _check_group(g: object, caller: str) -> Group:
    if not isinstance(g, Group):
        raise TypeError(f"{caller}({book_name(g)}): expected a group, got {book_name(g)}")
    return g


def partition_children(g: Group) -> tuple[list[Shape], list[Shape]]:
    """The bonus chapter: ``(left, right)``, the children of ``g`` whose boxes (in ``g``'s
    space) fit in the left or the right half of ``g``'s box (``split_bounds``), each taken
    out of ``g``; the children that fit in neither half stay, in their order."""
    _check_group(g, "partition_children")
    return _partition(g, {})


Boxes = dict[int, BoundingBox]
"""Shapes' boxes in their parent's space, by ``id``, remembered through one ``divide``: a
subgroup has the identity transform, so a child's box is the same in its new group."""


def _box_in_parent(child: Shape, boxes: Boxes) -> BoundingBox:
    box = boxes.get(id(child))
    if box is None:
        box = boxes[id(child)] = transform_box(child.local_bounds(), child.transform)
    return box


def _partition(g: Group, boxes: Boxes) -> tuple[list[Shape], list[Shape]]:
    whole = enclose(_box_in_parent(child, boxes) for child in g.children)
    left_box, right_box = split_bounds(whole)  # g.local_bounds(), from the remembered boxes
    left: list[Shape] = []
    right: list[Shape] = []
    kept: list[Shape] = []
    for child in g.children:
        box = _box_in_parent(child, boxes)
        if box_contains_box(left_box, box):
            left.append(child)
        elif box_contains_box(right_box, box):
            right.append(child)
        else:
            kept.append(child)
    g.children = kept  # assigned, not changed in place: a variant may watch the attribute
    return left, right


def make_subgroup(g: Group, shapes: Sequence[Shape]) -> None:
    """The bonus chapter: a new group (of ``g``'s class) holding ``shapes``, added to ``g``
    as its last child. A shape of ``shapes`` that is still a child of ``g`` moves into the
    subgroup rather than being in both."""
    _check_group(g, "make_subgroup")
    if isinstance(shapes, Shape) or not isinstance(shapes, Sequence):
        raise TypeError(
            f"make_subgroup(Group, {book_name(shapes)}): expected a list of shapes, "
            f"got {book_name(shapes)}"
        )
    for s in shapes:
        if not isinstance(s, Shape):
            raise TypeError(
                f"make_subgroup(Group, [...]): every item must be a shape, got {book_name(s)}"
            )
    moving = {id(s) for s in shapes}
    if any(id(child) in moving for child in g.children):
        g.children = [child for child in g.children if id(child) not in moving]
    subgroup = type(g)()
    for s in shapes:
        add_child(subgroup, s)
    add_child(g, subgroup)


def _check_threshold(threshold: object, shape: object) -> int:
    if isinstance(threshold, bool) or not isinstance(threshold, int) or threshold < 1:
        raise ValueError(
            f"divide({book_name(shape)}, {threshold!r}): the threshold must be a whole number "
            "of at least 1 (a group with that many children or more is split)"
        )
    return threshold


def divide(shape: Shape, threshold: int) -> None:
    """The bonus chapter: split every group in ``shape`` (itself included, through groups
    and both operands of CSG shapes) that has at least ``threshold`` children: the children
    of each half of its box go into a new subgroup (``partition_children``,
    ``make_subgroup``); then the same for each child. Other shapes are left as they are.

    Beyond the book: a split that would put every child into one subgroup (children all at
    one point, or in one infinite half) is not made, since it would divide forever.
    """
    if not isinstance(shape, Shape):
        raise TypeError(f"divide({book_name(shape)}): expected a shape, got {book_name(shape)}")
    _divide(shape, _check_threshold(threshold, shape), {})


def _divide(shape: Shape, threshold: int, boxes: Boxes) -> None:
    if isinstance(shape, Group):
        if len(shape.children) >= threshold:
            before = shape.children
            left, right = _partition(shape, boxes)
            if not shape.children and (not left or not right):
                shape.children = before  # one side took everything: nothing gained
            else:
                if left:
                    make_subgroup(shape, left)
                if right:
                    make_subgroup(shape, right)
        for child in shape.children:
            _divide(child, threshold, boxes)
    elif isinstance(shape, CSG):
        _divide(shape.left, threshold, boxes)
        _divide(shape.right, threshold, boxes)
