"""The sky (chapter 21 here, beyond the book): the light that reaches a path from every
direction in which it meets nothing.

A sky is a colour at the horizon and one at the zenith; a uniform sky has the two equal.
The colour seen along a direction d is

    t = max(0, d.y / |d|)                          (0 at and below the horizon, 1 straight up)
    sky_color = horizon + (zenith - horizon) * t   (component by component)

written as ``horizon + (zenith - horizon) * t`` rather than ``horizon * (1 - t) + zenith *
t`` so that a uniform sky gives its colour exactly, whatever the direction (the white
furnace's oracle). A world with no sky (``World.sky`` None) is black all around, as the
book's is. Only the path integrator looks at the sky; the book's Whitted integrator keeps
its black background.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.colors import BLACK, Color
from raytracer.tuples import Tuple


@dataclass(frozen=True, slots=True)
class Sky:
    """horizon: the colour at and below the horizon; zenith: the colour straight up (the
    same colour for a uniform sky)."""

    horizon: Color
    zenith: Color


def sky(color: Color) -> Sky:
    """A uniform sky: ``color`` in every direction."""
    return Sky(color, color)


def gradient_sky(horizon: Color, zenith: Color) -> Sky:
    """A sky that goes from ``horizon`` (at and below the horizon) to ``zenith`` (straight
    up) with the height of the direction (the module docstring gives the formula)."""
    return Sky(horizon, zenith)


def sky_color(s: Sky | None, direction: Tuple) -> Color:
    """The colour of the sky ``s`` seen along ``direction`` (any length but zero); black
    when there is no sky."""
    if s is None:
        return BLACK
    d = direction
    t = max(0.0, d.y / math.sqrt(d.x * d.x + d.y * d.y + d.z * d.z))
    return s.horizon + (s.zenith - s.horizon) * t
