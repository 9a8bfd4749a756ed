"""Patterns (chapter 10, the bonus chapter "Texture mapping") writing their colour into a
caller-owned ``[r, g, b]``.

One record class per reference pattern, with the pattern's inverse transform as a flat
list and its two colours as ``[r, g, b]`` lists; ``pattern_at_into`` is the twin of the
reference's ``local_pattern_at``, the same arithmetic in the same order. The texture maps'
records hold a UV record per UV pattern (``uv_color_into``, the twin of ``uv_color_at``)
and the twin of their mapping, on the point's three floats.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from raytracer.patterns import (
    CheckersPattern,
    GradientPattern,
    Pattern,
    RingPattern,
    StripePattern,
    TestPattern,
)
from raytracer.textures import (
    CubeMap,
    TextureMap,
    UVAlignCheck,
    UVCheckers,
    UVImage,
    UVPattern,
    cylindrical_map,
    planar_map,
    spherical_map,
)
from variants.prealloc.buffers import Vec, color_buffer
from variants.prealloc.errors import PreallocUnsupported, check_reimplemented
from variants.prealloc.geometry import flat_matrix


class PatternRecord:
    """Chapter 10: what every pattern has: ``inverse`` (flat), and ``a``/``b`` colours."""

    __slots__ = ("a", "b", "inverse", "pattern")

    def __init__(self, pattern: Pattern) -> None:
        self.pattern = pattern
        self.inverse = flat_matrix(pattern.inverse_transform)
        name = type(pattern).__name__
        self.a = color_buffer(pattern.a, f"{name}.a") if hasattr(pattern, "a") else None
        self.b = color_buffer(pattern.b, f"{name}.b") if hasattr(pattern, "b") else None

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        """The colour at a pattern-space point (naive twin: ``local_pattern_at``)."""
        raise NotImplementedError


def _copy_color(c: Vec | None, out: Vec) -> None:
    assert c is not None
    out[0] = c[0]
    out[1] = c[1]
    out[2] = c[2]


class StripeRecord(PatternRecord):
    """Chapter 10: ``StripePattern.local_pattern_at``: a if floor(x) is even, else b."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        _copy_color(self.a if math.floor(point[0]) % 2 == 0 else self.b, out)


class GradientRecord(PatternRecord):
    """Chapter 10: ``GradientPattern.local_pattern_at``: a + (b - a) * fraction of x."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        a, b = self.a, self.b
        assert a is not None and b is not None
        x = point[0]
        fraction = x - math.floor(x)
        out[0] = a[0] + (b[0] - a[0]) * fraction
        out[1] = a[1] + (b[1] - a[1]) * fraction
        out[2] = a[2] + (b[2] - a[2]) * fraction


class RingRecord(PatternRecord):
    """Chapter 10: ``RingPattern.local_pattern_at``: by floor of the distance from y."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        x, z = point[0], point[2]
        distance = math.sqrt(x * x + z * z)
        _copy_color(self.a if math.floor(distance) % 2 == 0 else self.b, out)


class CheckersRecord(PatternRecord):
    """Chapter 10: ``CheckersPattern.local_pattern_at``: by floor(x) + floor(y) + floor(z)."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        total = math.floor(point[0]) + math.floor(point[1]) + math.floor(point[2])
        _copy_color(self.a if total % 2 == 0 else self.b, out)


class TestPatternRecord(PatternRecord):
    """Chapter 10: ``TestPattern.local_pattern_at``: the point itself as a colour."""

    __test__ = False  # not a pytest test class, despite the name
    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        out[0] = point[0]
        out[1] = point[1]
        out[2] = point[2]


# ------------------------------------------------------------ texture mapping (bonus chapter)


class UVRecord:
    """A UV pattern: ``uv_color_into(u, v, out)`` is the twin of its ``uv_color_at``."""

    __slots__ = ()

    def uv_color_into(self, u: float, v: float, out: Vec) -> None:
        raise NotImplementedError


class UVCheckersRecord(UVRecord):
    """``UVCheckers.uv_color_at``: a if floor(u * width) + floor(v * height) is even."""

    __slots__ = ("a", "b", "height", "width")

    def __init__(self, p: UVCheckers) -> None:
        self.width = p.width
        self.height = p.height
        self.a = color_buffer(p.a, "UVCheckers.a")
        self.b = color_buffer(p.b, "UVCheckers.b")

    def uv_color_into(self, u: float, v: float, out: Vec) -> None:
        square = math.floor(u * self.width) + math.floor(v * self.height)
        _copy_color(self.a if square % 2 == 0 else self.b, out)


class UVAlignCheckRecord(UVRecord):
    """``UVAlignCheck.uv_color_at``: a corner patch where u and v are within 0.2 of it."""

    __slots__ = ("bl", "br", "main", "ul", "ur")

    def __init__(self, p: UVAlignCheck) -> None:
        self.main = color_buffer(p.main, "UVAlignCheck.main")
        self.ul = color_buffer(p.ul, "UVAlignCheck.ul")
        self.ur = color_buffer(p.ur, "UVAlignCheck.ur")
        self.bl = color_buffer(p.bl, "UVAlignCheck.bl")
        self.br = color_buffer(p.br, "UVAlignCheck.br")

    def uv_color_into(self, u: float, v: float, out: Vec) -> None:
        c = self.main
        if v > 0.8:
            if u < 0.2:
                c = self.ul
            elif u > 0.8:
                c = self.ur
        elif v < 0.2:
            if u < 0.2:
                c = self.bl
            elif u > 0.8:
                c = self.br
        _copy_color(c, out)


class UVImageRecord(UVRecord):
    """``UVImage.uv_color_at``: the pixel (round(u * (w - 1)), round((1 - v) * (h - 1))),
    from the canvas's colours as one flat ``[r, g, b, r, g, b, ...]`` list."""

    __slots__ = ("height", "pixels", "width")

    def __init__(self, p: UVImage) -> None:
        canvas = p.canvas
        self.width = canvas.width
        self.height = canvas.height
        pixels: list[float] = []
        for c in canvas.pixels:
            pixels.extend(color_buffer(c, "a pixel of UVImage.canvas"))
        self.pixels = pixels

    def uv_color_into(self, u: float, v: float, out: Vec) -> None:
        width, height = self.width, self.height
        col = round(u * (width - 1))
        row = round((1 - v) * (height - 1))
        if not (0 <= col < width and 0 <= row < height):
            raise ValueError(
                f"uv_image: (u, v) = ({u!r}, {v!r}) is pixel ({col}, {row}), outside the "
                f"{width}x{height} image; u and v run from 0 to 1"
            )
        i = (row * width + col) * 3
        pixels = self.pixels
        out[0] = pixels[i]
        out[1] = pixels[i + 1]
        out[2] = pixels[i + 2]


UV_RECORDS: dict[type[UVPattern], type[UVRecord]] = {
    UVCheckers: UVCheckersRecord,
    UVAlignCheck: UVAlignCheckRecord,
    UVImage: UVImageRecord,
}


def uv_record(p: UVPattern) -> UVRecord:
    """The record of a reference UV pattern; ``PreallocUnsupported`` for any other."""
    for cls in type(p).__mro__:
        record_class = UV_RECORDS.get(cls)
        if record_class is not None:
            check_reimplemented(p, cls, ("uv_color_at",))
            return record_class(p)  # type: ignore[call-arg]
    raise PreallocUnsupported(
        f"prealloc: no implementation for UV pattern type {type(p).__name__}; it runs "
        f"{', '.join(cls.__name__ for cls in UV_RECORDS)}"
    )


def _spherical(x: float, y: float, z: float) -> tuple[float, float]:
    """``spherical_map`` on the point's floats."""
    theta = math.atan2(x, z)
    radius = math.sqrt(x * x + y * y + z * z)
    phi = math.acos(max(-1.0, min(1.0, y / radius))) if radius > 0 else math.pi / 2
    raw_u = theta / (2 * math.pi)
    return 1 - (raw_u + 0.5), 1 - phi / math.pi


def _planar(x: float, y: float, z: float) -> tuple[float, float]:
    """``planar_map`` on the point's floats."""
    return x % 1.0, z % 1.0


def _cylindrical(x: float, y: float, z: float) -> tuple[float, float]:
    """``cylindrical_map`` on the point's floats."""
    theta = math.atan2(x, z)
    raw_u = theta / (2 * math.pi)
    return 1 - (raw_u + 0.5), y % 1.0


MAPPING_TWINS: dict[Callable[..., Any], Callable[[float, float, float], tuple[float, float]]] = {
    spherical_map: _spherical,
    planar_map: _planar,
    cylindrical_map: _cylindrical,
}


class TextureMapRecord(PatternRecord):
    """``TextureMap.local_pattern_at``: the UV record's colour at the mapping's (u, v)."""

    __slots__ = ("mapping", "uv")

    def __init__(self, pattern: TextureMap) -> None:
        super().__init__(pattern)
        mapping = MAPPING_TWINS.get(pattern.mapping)
        if mapping is None:
            raise PreallocUnsupported(
                f"prealloc: no implementation for the texture mapping {pattern.mapping!r}; "
                "it runs spherical_map, planar_map, cylindrical_map"
            )
        self.mapping = mapping
        self.uv = uv_record(pattern.uv_pattern)

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        u, v = self.mapping(point[0], point[1], point[2])
        self.uv.uv_color_into(u, v, out)


class CubeMapRecord(PatternRecord):
    """``CubeMap.local_pattern_at``: ``face_from_point``'s face, then that face's
    ``cube_uv_*`` (u, v) on its UV record."""

    __slots__ = ("back", "down", "front", "left", "right", "up")

    def __init__(self, pattern: CubeMap) -> None:
        super().__init__(pattern)
        self.left = uv_record(pattern.left)
        self.front = uv_record(pattern.front)
        self.right = uv_record(pattern.right)
        self.back = uv_record(pattern.back)
        self.up = uv_record(pattern.up)
        self.down = uv_record(pattern.down)

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        x, y, z = point[0], point[1], point[2]
        coord = max(abs(x), abs(y), abs(z))
        if coord == x:
            self.right.uv_color_into(((1 - z) % 2.0) / 2.0, ((y + 1) % 2.0) / 2.0, out)
        elif coord == -x:
            self.left.uv_color_into(((z + 1) % 2.0) / 2.0, ((y + 1) % 2.0) / 2.0, out)
        elif coord == y:
            self.up.uv_color_into(((x + 1) % 2.0) / 2.0, ((1 - z) % 2.0) / 2.0, out)
        elif coord == -y:
            self.down.uv_color_into(((x + 1) % 2.0) / 2.0, ((z + 1) % 2.0) / 2.0, out)
        elif coord == z:
            self.front.uv_color_into(((x + 1) % 2.0) / 2.0, ((y + 1) % 2.0) / 2.0, out)
        else:
            self.back.uv_color_into(((1 - x) % 2.0) / 2.0, ((y + 1) % 2.0) / 2.0, out)


PATTERN_RECORDS: dict[type[Pattern], type[PatternRecord]] = {
    StripePattern: StripeRecord,
    GradientPattern: GradientRecord,
    RingPattern: RingRecord,
    CheckersPattern: CheckersRecord,
    TestPattern: TestPatternRecord,
    TextureMap: TextureMapRecord,
    CubeMap: CubeMapRecord,
}


def pattern_record(pattern: Pattern) -> PatternRecord:
    """The record of a reference pattern (or a subclass that only caches, like ``cached``'s);
    ``PreallocUnsupported`` naming the type for any other pattern."""
    for cls in type(pattern).__mro__:
        record_class = PATTERN_RECORDS.get(cls)
        if record_class is not None:
            check_reimplemented(pattern, cls, ("local_pattern_at",))
            return record_class(pattern)
    raise PreallocUnsupported(
        f"prealloc: no implementation for pattern type {type(pattern).__name__}; it runs "
        f"{', '.join(cls.__name__ for cls in PATTERN_RECORDS)}"
    )
