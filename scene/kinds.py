"""The kinds of leaf shape (chapters 5, 9, 12, 13, 15): one table, one row per kind.

Each row says everything about a kind that is not how a tracer intersects or shades it: its
name (the book's factory, and the scene format's ``add:``), the chapter, the reference's
class, its parameters (the scene format's key, the shape's attribute, the default and what
values it takes), the most intersections a ray can have with one, and its box in object
space. Its number is its place in the table. The scene loader, the builder of the book's
world, the packers of the compiled and vectorized tracers, the kernel specialization,
``--explain`` and the differential tests read their lists of kinds from here; a tracer's own
intersection and normal code for a kind stays in that tracer, in one place per kind.

Groups, CSG shapes and OBJ models are not leaf kinds: they hold other shapes (the scene
format's ``STRUCTURES``, ``scene.shapes``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

from raytracer.api import BOOK_API
from raytracer.shapes.cone import Cone
from raytracer.shapes.cube import Cube
from raytracer.shapes.cylinder import Cylinder
from raytracer.shapes.plane import Plane
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.test_shape import TestShape
from raytracer.shapes.torus import Torus
from raytracer.shapes.triangle import Triangle

Box = tuple[tuple[float, float, float], tuple[float, float, float]]
"""An axis-aligned box: (lo x, y, z), (hi x, y, z)."""

SHAPE_METHODS = ("local_intersect", "local_normal_at")
"""What a subclass of a reference shape must inherit unchanged to count as its kind for a
tracer that compiles the kind's own intersection and normal."""


class Parameter(NamedTuple):
    """One parameter of a kind.

    key: the scene format's key (``min``); attribute: the reference shape's (``minimum``);
    default: the value a new shape has (its type says whether the parameter is a number or
    a boolean); infinite: a number that may be infinite (a cylinder's unbounded ends);
    above: the number it must be greater than (None: any), for the error, ``meaning``: what
    the parameter is; largest: the largest finite size it may have (None: any), past which
    a ray's arithmetic leaves floating point in every variant, and ``overflow`` says how.
    """

    key: str
    attribute: str
    default: float | bool
    infinite: bool = False
    above: float | None = None
    meaning: str = ""
    largest: float | None = None
    overflow: str = ""

    @property
    def boolean(self) -> bool:
        return isinstance(self.default, bool)


class Kind(NamedTuple):
    """One kind of leaf shape.

    name: the book's factory (``cylinder()``) and the scene format's ``add:``; reference:
    the reference's class; parameters: what a shape of
    this kind holds besides its transform and material; max_hits: the most intersections a
    ray can have with one; addable: a scene file can ``add:`` it (triangles come from OBJ
    models); renders: a tracer can render it (the test shape records rays in Python);
    corners: the points its factory takes (a triangle's 3), then as many normals if
    ``smooth``.
    """

    name: str
    reference: type[Shape]
    max_hits: int
    parameters: tuple[Parameter, ...] = ()
    addable: bool = True
    renders: bool = True
    corners: int = 0
    smooth: bool = False

    @property
    def chapter(self) -> int:
        """Where the book introduces it (its factory's chapter, ``raytracer.api``)."""
        return BOOK_API[self.name]

    @property
    def number(self) -> int:
        """Its place in ``KINDS``: the number tracers store in their tables."""
        return KINDS.index(self)

    @property
    def keys(self) -> tuple[str, ...]:
        """The scene format's keys for its parameters."""
        return tuple(p.key for p in self.parameters)

    def values(self, given: Mapping[str, Any] | None = None) -> dict[str, Any]:
        """Every parameter's value by attribute: ``given``'s, else the default."""
        given = given or {}
        return {p.attribute: given.get(p.attribute, p.default) for p in self.parameters}

    def local_box(self, values: Mapping[str, Any] | None = None) -> Box | None:
        """Its box in object space with these parameter values (the reference shape's
        ``local_bounds``, the bonus chapter 'Bounding boxes and hierarchies'); None when it
        is unbounded. Not for triangles (their box is their corners')."""
        shape = self.reference()
        for attribute, value in self.values(values).items():
            setattr(shape, attribute, value)
        box = shape.local_bounds()
        lo, hi = (box.min.x, box.min.y, box.min.z), (box.max.x, box.max.y, box.max.z)
        if not all(math.isfinite(v) for v in (*lo, *hi)):
            return None
        return (lo, hi)


# A cap's height is squared (a cone's radius there) and a torus's radii are raised to the
# fourth power (its quartic's coefficients): past these sizes the sum overflows to infinity
# and every variant draws NaN or nothing (a cone's max of 1e300, a torus of radius 1e300)
CAP_LARGEST = 1e150
CAP_OVERFLOW = "squared, as the caps' test squares it, it overflows"
RADIUS_LARGEST = 1e60
RADIUS_OVERFLOW = "the torus's quartic raises it to the fourth power, which overflows"

CAPPED = (
    Parameter("min", "minimum", -math.inf, infinite=True, largest=CAP_LARGEST,
              overflow=CAP_OVERFLOW),
    Parameter("max", "maximum", math.inf, infinite=True, largest=CAP_LARGEST,
              overflow=CAP_OVERFLOW),
    Parameter("closed", "closed", False),
)  # fmt: skip

RADII = (
    Parameter("major-radius", "major_radius", 1.0, above=0.0,
              meaning="the distance from the centre to the middle of the tube",
              largest=RADIUS_LARGEST, overflow=RADIUS_OVERFLOW),
    Parameter("minor-radius", "minor_radius", 0.25, above=0.0, meaning="the tube's radius",
              largest=RADIUS_LARGEST, overflow=RADIUS_OVERFLOW),
)  # fmt: skip

KINDS: tuple[Kind, ...] = (
    Kind("sphere", Sphere, max_hits=2),
    Kind("plane", Plane, max_hits=1),
    Kind("cube", Cube, max_hits=2),
    Kind("cylinder", Cylinder, max_hits=4, parameters=CAPPED),
    Kind("cone", Cone, max_hits=4, parameters=CAPPED),
    Kind("torus", Torus, max_hits=4, parameters=RADII),
    Kind("triangle", Triangle, max_hits=1, addable=False, corners=3),
    Kind("smooth_triangle", SmoothTriangle, max_hits=1, addable=False, corners=3, smooth=True),
    Kind("test_shape", TestShape, max_hits=0, addable=False, renders=False),
)
"""Every leaf kind, in the order tracers number them."""

BY_NAME: dict[str, Kind] = {kind.name: kind for kind in KINDS}
ADDABLE: tuple[Kind, ...] = tuple(kind for kind in KINDS if kind.addable)
TRIANGLES: tuple[Kind, ...] = tuple(kind for kind in KINDS if kind.corners)


def kind(name: str) -> Kind:
    """The kind called ``name`` (``KeyError`` for any other)."""
    return BY_NAME[name]


def _most_derived_first() -> tuple[Kind, ...]:
    return tuple(sorted(KINDS, key=lambda k: -len(k.reference.__mro__)))


_LOOKUP = _most_derived_first()  # a smooth triangle is a triangle: it must be found first


def unchanged(cls: type, base: type, methods: Sequence[str]) -> bool:
    """True when ``cls`` inherits every one of ``methods`` from ``base`` unchanged."""
    return all(getattr(cls, name) is getattr(base, name) for name in methods)


def reference_kind(shape: object) -> tuple[Kind | None, type | None]:
    """``(kind, None)`` when ``shape`` is a reference leaf shape (or a subclass that keeps
    its intersection and normal); ``(None, cls)`` when it is a subclass of the reference
    class ``cls`` that changes them; ``(None, None)`` when it is no leaf kind."""
    for k in _LOOKUP:
        if isinstance(shape, k.reference):
            if unchanged(type(shape), k.reference, SHAPE_METHODS):
                return k, None
            return None, k.reference
    return None, None


def names(kinds: Sequence[Kind]) -> str:
    """``sphere, plane, ...``: for the 'known: ...' part of an error."""
    return ", ".join(k.name for k in kinds)
