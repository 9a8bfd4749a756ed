"""The abstract shape (chapter 9, refactoring chapters 5 and 6; ``parent`` from chapter 14),
and chapter 5's ``Intersection``, which a shape's ``local_intersect`` makes and which names
its shape (``raytracer.intersections`` hands it on with the rest of chapter 5).

A shape is an entity: ``set_transform``, ``s.material ← m`` and ``add_child`` change it in
place. Shapes compare by value (type, transform, material and their own fields, never
``parent``) and are never hashed.

Naive on purpose: ``inverse_transform`` inverts ``transform`` on every access. Everything in
the tracer reads a shape's inverse through that property, so a variant can subclass a shape
and cache it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

from raytracer.bounds import UNBOUNDED, BoundingBox, transform_box
from raytracer.materials import Material, material
from raytracer.matrices import (
    Matrix,
    NotInvertibleError,
    book_name,
    identity_matrix,
    inverse_of,
    is_invertible,
    transpose,
)
from raytracer.rays import Ray
from raytracer.rays import transform as transform_ray
from raytracer.space import normal_to_world, world_to_object
from raytracer.tuples import Tuple

__all__ = [
    "Intersection",
    "Shape",
    "bounds_of",
    "intersect",
    "intersection",
    "intersection_with_uv",
    "intersections",
    "local_intersect",
    "local_normal_at",
    "normal_at",
    "normal_to_world",
    "parent_space_bounds_of",
    "set_transform",
    "world_to_object",
]

DEFAULT_MATERIAL = material()  # every new shape's (a Material never changes)
SHAPE_HINT = ", so it cannot be intersected or shaded (set_transform refuses such a transform)"


@dataclass(slots=True, eq=True, kw_only=True)
class Shape(ABC):
    """Chapter 9: what every shape has (keyword-only, so that a subclass's own fields, such
    as a triangle's corners, come first and positionally).

    transform: object space to world space (default: the identity);
    material: how the surface looks (default: ``material()``);
    casts_shadow: False for an object that never shadows others (a scene's ``shadow: false``);
    parent: the group containing this shape (chapter 14), or None.
    """

    transform: Matrix = identity_matrix
    material: Material = DEFAULT_MATERIAL  # immutable: one shared until a shape gets its own
    casts_shadow: bool = True
    parent: Shape | None = field(default=None, compare=False, repr=False)

    @property
    def inverse_transform(self) -> Matrix:
        """The inverse of ``transform``, computed on every access (the naive baseline)."""
        return inverse_of(self.transform, book_name(self), SHAPE_HINT)

    @property
    def inverse_transpose(self) -> Matrix:
        """The transpose of the inverse, for normals; computed on every access (naive)."""
        return transpose(self.inverse_transform)

    @abstractmethod
    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """The intersections of a ray already in object space with this shape."""

    @abstractmethod
    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """The object-space normal at an object-space point (``hit``: for smooth triangles)."""

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the box around the shape in
        its object space. Each shape kind defines its own; a kind that does not is taken
        to be everywhere (infinite), so a group holding it always tests it."""
        return UNBOUNDED


@dataclass(frozen=True, slots=True)
class Intersection:
    """Where a ray meets a shape: distance ``t`` along the ray, and the ``object`` hit.

    u, v: where on a triangle the hit is (chapter 15); None for other shapes.
    """

    t: float
    object: Shape
    u: float | None = None
    v: float | None = None


def intersection(t: float, obj: Shape) -> Intersection:
    """Chapter 5: an intersection at ``t`` with ``obj``."""
    return Intersection(t, obj)


def intersection_with_uv(t: float, obj: Shape, u: float, v: float) -> Intersection:
    """Chapter 15: an intersection that also records the triangle's ``u`` and ``v``."""
    return Intersection(t, obj, u, v)


def intersections(*xs: Intersection) -> list[Intersection]:
    """Chapter 5: a new list of the given intersections sorted by ``t`` (stable)."""
    return sorted(xs, key=lambda i: i.t)


def intersect(shape: Shape, ray: Ray) -> list[Intersection]:
    """Chapters 5 and 9: the intersections of a world-space ``ray`` with ``shape``."""
    return shape.local_intersect(transform_ray(ray, shape.inverse_transform))


def normal_at(shape: Shape, world_point: Tuple, hit: Intersection | None = None) -> Tuple:
    """Chapters 6, 9 and 14: the world-space surface normal of ``shape`` at ``world_point``.

    hit: the intersection being shaded (only smooth triangles use it, chapter 15).
    """
    local_point = world_to_object(shape, world_point)
    local_normal = shape.local_normal_at(local_point, hit)
    return normal_to_world(shape, local_normal)


def local_intersect(shape: Shape, local_ray: Ray) -> list[Intersection]:
    """Chapter 9: the shape-specific intersection of an object-space ray."""
    return shape.local_intersect(local_ray)


def local_normal_at(shape: Shape, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
    """Chapter 9: the shape-specific normal at an object-space point."""
    return shape.local_normal_at(local_point, hit)


def _check_shape(shape: object, caller: str) -> Shape:
    if not isinstance(shape, Shape):
        raise TypeError(f"{caller}: expected a shape, got {type(shape).__name__}")
    return shape


def bounds_of(shape: Shape) -> BoundingBox:
    """The bonus chapter 'Bounding boxes and hierarchies': ``shape``'s box in its own object
    space (``local_bounds``, the shape's own method)."""
    return _check_shape(shape, "bounds_of").local_bounds()


def parent_space_bounds_of(shape: Shape) -> BoundingBox:
    """The bonus chapter 'Bounding boxes and hierarchies': ``shape``'s box transformed by
    its transform, i.e. in the space of its parent group (or of the world)."""
    shape = _check_shape(shape, "parent_space_bounds_of")
    return transform_box(shape.local_bounds(), shape.transform)


def set_transform(shape: Shape, m: Matrix) -> None:
    """Chapter 5: give ``shape`` the transformation ``m``; it must be invertible."""
    if not is_invertible(m):
        raise NotInvertibleError(
            f"set_transform({type(shape).__name__}): the transform is not invertible "
            "(determinant 0)"
        )
    shape.transform = m
