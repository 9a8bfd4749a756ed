"""Light sources (chapter 6): a point light."""

from __future__ import annotations

from dataclasses import dataclass

from raytracer.colors import Color
from raytracer.tuples import Tuple


@dataclass(frozen=True, slots=True)
class PointLight:
    """A light with no size: ``position`` (a point) and ``intensity`` (its color)."""

    position: Tuple
    intensity: Color


def point_light(position: Tuple, intensity: Color) -> PointLight:
    """Chapter 6: a point light at ``position`` shining with ``intensity``."""
    return PointLight(position, intensity)
