"""Packing the texture patterns (the bonus chapter "Texture mapping") into two flat arrays
the kernels read: ``ti`` (ints) and ``tf`` (floats), laid out as ``layout`` says.

A ``TextureMap`` or ``CubeMap`` becomes a map record in ``ti`` (its mapping, then where its
uv patterns' records start); each uv pattern a uv record (its kind, where its floats start
in ``tf``, an image's size); a ``UVImage``'s canvas its pixels in ``tf``, row by row from
the top, three floats each. A primitive row names its map record (``PAT_TEX``). The same
pattern, uv pattern or canvas used by many shapes is packed once.

Only the reference's classes are packed, and only the three mappings the reference
defines; anything else is a ``PackError`` naming the object, never an approximation.
"""

from __future__ import annotations

import itertools
import operator
from typing import Any

import numpy as np

from raytracer.canvas import Canvas
from raytracer.colors import Color
from raytracer.patterns import Pattern
from raytracer.textures.mappings import cylindrical_map, planar_map, spherical_map
from raytracer.textures.maps import CubeMap, TextureMap
from raytracer.textures.uv_patterns import UVAlignCheck, UVCheckers, UVImage, UVPattern
from variants.numba import layout as L
from variants.numba.errors import PackError

MAPPINGS = {
    id(spherical_map): L.M_SPHERICAL,
    id(planar_map): L.M_PLANAR,
    id(cylindrical_map): L.M_CYLINDRICAL,
}
UV_CLASSES: tuple[tuple[type[UVPattern], int], ...] = (
    (UVCheckers, L.UV_CHECKERS),
    (UVAlignCheck, L.UV_ALIGN_CHECK),
    (UVImage, L.UV_IMAGE),
)
UV_NAMES = {
    L.UV_CHECKERS: "uv_checkers",
    L.UV_ALIGN_CHECK: "uv_align_check",
    L.UV_IMAGE: "uv_image",
}
_RGB = operator.attrgetter("red", "green", "blue")


def _rgb(c: Color, what: str) -> list[float]:
    if not isinstance(c, Color):
        raise _error(what, f"is a {type(c).__name__}, not a color")
    return [float(c.red), float(c.green), float(c.blue)]


def _error(what: str, problem: str) -> Exception:
    return PackError(f"numba: {what} {problem}")


class TextureTable:
    """The texture records of one packed world (or shape), built as patterns are met."""

    def __init__(self) -> None:
        self.ints: list[int] = []
        self.blocks: list[np.ndarray] = []  # the floats, in order
        self.n_floats = 0
        self.uv_kinds: set[int] = set()
        self.images = 0  # distinct canvases
        self.texels = 0  # their pixels
        self._maps: dict[int, int] = {}  # id(pattern) -> its map record
        self._uvs: dict[int, int] = {}  # id(uv pattern) -> its uv record
        self._canvases: dict[int, int] = {}  # id(canvas) -> where its pixels start in tf
        self._alive: list[Any] = []  # what the ids above belong to, kept while packing

    def _floats(self, values: np.ndarray) -> int:
        at = self.n_floats
        self.blocks.append(np.asarray(values, dtype=np.float64).reshape(-1))
        self.n_floats += self.blocks[-1].size
        return at

    def pattern(self, pattern: Pattern, where: str) -> int:
        """Where the map record of ``pattern`` (a ``TextureMap`` or ``CubeMap``) starts in
        ``ti``; ``where`` names the shape it is on, for errors."""
        found = self._maps.get(id(pattern))
        if found is not None:
            return found
        what = f"the texture pattern of {where}"
        if isinstance(pattern, TextureMap):
            mapping = MAPPINGS.get(id(pattern.mapping))
            if mapping is None:
                name = getattr(pattern.mapping, "__name__", type(pattern.mapping).__name__)
                raise _error(
                    what,
                    f"maps points with {name}; the kernels know spherical_map, planar_map "
                    "and cylindrical_map",
                )
            uvs = [self.uv(pattern.uv_pattern, f"{what} (its uv_pattern)")]
        elif isinstance(pattern, CubeMap):
            mapping = L.M_CUBE
            faces = (pattern.left, pattern.front, pattern.right, pattern.back, pattern.up,
                     pattern.down)  # fmt: skip
            names = ("left", "front", "right", "back", "up", "down")
            uvs = [
                self.uv(face, f"{what} (its {name} face)")
                for face, name in zip(faces, names, strict=True)
            ]
        else:
            raise _error(what, f"is a {type(pattern).__name__}, not a texture pattern")
        at = len(self.ints)
        record = [0] * L.NMAP
        record[L.MAP_KIND] = mapping
        record[L.MAP_UV : L.MAP_UV + len(uvs)] = uvs
        self.ints.extend(record)
        self._maps[id(pattern)] = at
        self._alive.append(pattern)
        return at

    def uv(self, uv_pattern: UVPattern, what: str) -> int:
        """Where the uv record of ``uv_pattern`` starts in ``ti``."""
        found = self._uvs.get(id(uv_pattern))
        if found is not None:
            return found
        kind = next(
            (
                k
                for cls, k in UV_CLASSES
                if isinstance(uv_pattern, cls) and type(uv_pattern).uv_color_at is cls.uv_color_at
            ),
            None,
        )
        if kind is None:
            known = ", ".join(UV_NAMES.values())
            raise _error(
                what,
                f"is a {type(uv_pattern).__name__}; the kernels know the uv patterns {known}",
            )
        record = [0] * L.NUV
        record[L.UV_KIND] = kind
        if isinstance(uv_pattern, UVCheckers):
            values = [float(uv_pattern.width), float(uv_pattern.height)]
            values += _rgb(uv_pattern.a, f"{what}'s color a") + _rgb(uv_pattern.b, f"{what}'s b")
            record[L.UV_AT] = self._floats(np.array(values))
        elif isinstance(uv_pattern, UVAlignCheck):
            colors = (uv_pattern.main, uv_pattern.ul, uv_pattern.ur, uv_pattern.bl, uv_pattern.br)
            values = [v for c in colors for v in _rgb(c, f"a color of {what}")]
            record[L.UV_AT] = self._floats(np.array(values))
        else:
            image: Canvas = uv_pattern.canvas  # type: ignore[attr-defined]
            record[L.UV_AT] = self.image(image, what)
            record[L.UV_WIDTH] = int(image.width)
            record[L.UV_HEIGHT] = int(image.height)
        at = len(self.ints)
        self.ints.extend(record)
        self.uv_kinds.add(kind)
        self._uvs[id(uv_pattern)] = at
        self._alive.append(uv_pattern)
        return at

    def image(self, image: Canvas, what: str) -> int:
        """Where the pixels of ``image`` start in ``tf`` (packed once per canvas)."""
        found = self._canvases.get(id(image))
        if found is not None:
            return found
        if not isinstance(image, Canvas):
            raise _error(what, f"shows a {type(image).__name__}, not a canvas")
        count = int(image.width) * int(image.height)
        array = getattr(image, "array", None)
        if isinstance(array, np.ndarray) and array.shape == (image.height, image.width, 3):
            values = array.astype(np.float64)  # an array-backed canvas
        else:
            values = np.fromiter(
                itertools.chain.from_iterable(map(_RGB, image.pixels)),
                dtype=np.float64,
                count=3 * count,
            )
        at = self._floats(values)
        self._canvases[id(image)] = at
        self._alive.append(image)
        self.images += 1
        self.texels += count
        return at

    def arrays(self, dtype: Any) -> tuple[np.ndarray, np.ndarray]:
        """(ti, tf): the records as the kernels read them (at least one element each, so
        that a pointer to them is valid)."""
        ti = np.array(self.ints or [0], dtype=np.int64)
        floats = np.concatenate(self.blocks) if self.blocks else np.zeros(1)
        return ti, np.ascontiguousarray(floats.astype(dtype, copy=False))

    def describe(self) -> str:
        """One line for ``explain``: the texture patterns packed, their uv patterns and
        images."""
        uv = ", ".join(UV_NAMES[k] for k in sorted(self.uv_kinds)) or "none"
        images = (
            f"; {self.images} image{'s' if self.images != 1 else ''}, {self.texels:,} pixels"
            if self.images
            else ""
        )
        return f"texture patterns: {len(self._maps)} (uv patterns: {uv}{images})"
