"""UV patterns (the bonus chapter "Texture mapping"): colors over the unit square (u, v).

A UV pattern knows nothing of 3D space: a ``TextureMap`` or ``CubeMap`` (``textures.maps``)
turns a point into (u, v) with a mapping and asks the UV pattern for the color there. u runs
left to right and v bottom to top, both from 0 to 1 (1 included: the mappings give 1 at a
seam). UV patterns are immutable values; ``uv_pattern_at`` asks a pattern's ``uv_color_at``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

from raytracer.canvas import Canvas, pixel_at
from raytracer.colors import Color


class UVPattern(ABC):
    """The bonus chapter "Texture mapping": what every UV pattern answers."""

    __slots__ = ()

    @abstractmethod
    def uv_color_at(self, u: float, v: float) -> Color:
        """The color at (u, v) of the unit square."""


@dataclass(frozen=True, slots=True)
class UVCheckers(UVPattern):
    """Checkers over the unit square: ``width`` squares along u, ``height`` along v.

    The square of (u, v) is ``floor(u * width) + floor(v * height)``: even gives ``a``, odd
    ``b``, so the corner square at (0, 0) is ``a``. width, height: how many squares across
    and up (a sphere's spherical map wants width = 2 * height for square-looking checks);
    positive.
    """

    width: float
    height: float
    a: Color
    b: Color

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            size = getattr(self, name)
            if not (isinstance(size, int | float) and 0 < size < math.inf):
                raise ValueError(
                    f"uv_checkers: the {name} must be a positive number of squares, got {size!r}"
                )

    def uv_color_at(self, u: float, v: float) -> Color:
        square = math.floor(u * self.width) + math.floor(v * self.height)
        return self.a if square % 2 == 0 else self.b


@dataclass(frozen=True, slots=True)
class UVAlignCheck(UVPattern):
    """A square of ``main`` with a colored patch in each corner, to see how a map is turned.

    The patches are 0.2 wide: v > 0.8 is the top row (``ul`` where u < 0.2, ``ur`` where
    u > 0.8), v < 0.2 the bottom row (``bl``, ``br``); everywhere else is ``main``.
    """

    main: Color
    ul: Color
    ur: Color
    bl: Color
    br: Color

    def uv_color_at(self, u: float, v: float) -> Color:
        if v > 0.8:
            if u < 0.2:
                return self.ul
            if u > 0.8:
                return self.ur
        elif v < 0.2:
            if u < 0.2:
                return self.bl
            if u > 0.8:
                return self.br
        return self.main


@dataclass(frozen=True, slots=True)
class UVImage(UVPattern):
    """An image (a canvas) stretched over the unit square: (0, 0) is its bottom left pixel.

    v is flipped, because a canvas's row 0 is its top: the pixel of (u, v) is column
    ``round(u * (width - 1))``, row ``round((1 - v) * (height - 1))``, with Python's
    ``round`` (a half goes to the even neighbour). The canvas is the image's, not a copy:
    do not draw on it afterwards.
    """

    canvas: Canvas

    def uv_color_at(self, u: float, v: float) -> Color:
        x = u * (self.canvas.width - 1)
        y = (1 - v) * (self.canvas.height - 1)
        return pixel_at(self.canvas, round(x), round(y))


def uv_checkers(width: float, height: float, a: Color, b: Color) -> UVCheckers:
    """Texture mapping: ``width`` x ``height`` checkers of ``a`` and ``b`` over (u, v)."""
    return UVCheckers(width, height, a, b)


def uv_align_check(main: Color, ul: Color, ur: Color, bl: Color, br: Color) -> UVAlignCheck:
    """Texture mapping: ``main`` with the corner patches upper left, upper right, bottom left,
    bottom right."""
    return UVAlignCheck(main, ul, ur, bl, br)


def uv_image(canvas: Canvas) -> UVImage:
    """Texture mapping: the image on ``canvas`` as a UV pattern."""
    return UVImage(canvas)


def uv_pattern_at(pattern: UVPattern, u: float, v: float) -> Color:
    """Texture mapping: the color of a UV pattern at (u, v)."""
    return pattern.uv_color_at(u, v)
