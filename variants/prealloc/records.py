"""Flat, per-render copies of the reference's entities that the hot path reads (chapters 6,
10): a light and a material, plus the check that a shape or pattern really is one the
``prealloc`` variant reimplements.

A record is built once per render context (``TraceContext``) from the reference's objects;
it is never written during the render.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from raytracer.colors import Color
from raytracer.lights import PointLight
from raytracer.materials import Material
from variants.prealloc.buffers import Vec

if TYPE_CHECKING:
    from variants.prealloc.patterns import PatternRecord


class PreallocUnsupported(TypeError):
    """A shape or pattern type the ``prealloc`` variant has no implementation of. It never
    falls back to the reference's code: it says which type it cannot run."""


def check_reimplemented(obj: object, reference: type, methods: tuple[str, ...]) -> None:
    """Refuse ``obj`` if its class replaces one of ``methods`` that ``prealloc`` reimplements
    from ``reference`` (a learner's subclass with its own ``local_intersect``, say): running
    ``reference``'s version instead would silently change the picture."""
    cls = type(obj)
    for name in methods:
        if getattr(cls, name) is not getattr(reference, name):
            raise PreallocUnsupported(
                f"prealloc: {cls.__name__} overrides {reference.__name__}.{name}, which the "
                f"prealloc variant reimplements; it cannot run {cls.__name__}'s own version"
            )


def color_buffer(c: Color, owner: str) -> Vec:
    """A ``Color`` as ``[r, g, b]``; ``owner`` names where it came from, for the error."""
    if not isinstance(c, Color):
        raise PreallocUnsupported(
            f"prealloc: {owner} must be a color, got {type(c).__name__} (nested patterns are "
            "not supported)"
        )
    return [float(c.red), float(c.green), float(c.blue)]


class LightRecord:
    """Chapter 6: a point light as ``position`` ``[x, y, z, w]`` and ``intensity``
    ``[r, g, b]``."""

    __slots__ = ("intensity", "position")

    def __init__(self, light: PointLight) -> None:
        p = light.position
        self.position = [float(p.x), float(p.y), float(p.z), float(p.w)]
        self.intensity = color_buffer(light.intensity, "a light's intensity")


class MaterialRecord:
    """Chapters 6, 10, 11: a material's numbers, its colour as ``[r, g, b]``, and its
    pattern's record (or None)."""

    __slots__ = (
        "ambient",
        "color",
        "diffuse",
        "pattern",
        "reflective",
        "refractive_index",
        "shininess",
        "specular",
        "transparency",
    )

    def __init__(self, m: Material, pattern: PatternRecord | None) -> None:
        self.color = color_buffer(m.color, "a material's color")
        self.ambient = float(m.ambient)
        self.diffuse = float(m.diffuse)
        self.specular = float(m.specular)
        self.shininess = float(m.shininess)
        self.reflective = float(m.reflective)
        self.transparency = float(m.transparency)
        self.refractive_index = float(m.refractive_index)
        self.pattern = pattern
