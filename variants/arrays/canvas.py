"""The canvas the array tracers render into (chapter 2): the reference's ``Canvas``, backed
by a (height, width, 3) float array instead of a list of ``Color`` values.

``pixels`` is a list-like view of the array, so the reference's ``pixel_at``, ``write_pixel``
and ``canvas_to_ppm`` work unchanged (reading and writing the array); ``to_rgb8()`` (used by
``groundwork.images.write_image``) and ``to_array()`` convert the whole image with numpy.
``ArrayCanvasTracer`` is the two ``Tracer`` steps that make such a canvas and write a
region into it, for a tracer whose regions come as arrays.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any, overload

import numpy as np

from raytracer.camera import Camera
from raytracer.canvas import Canvas
from raytracer.colors import Color
from raytracer.tracer import Region, Tracer


class PixelView:
    """The pixels of a (height, width, 3) array as a flat, row-major sequence of colors."""

    __slots__ = ("array", "width")

    def __init__(self, array: np.ndarray) -> None:
        self.array = array
        self.width = array.shape[1]

    def __len__(self) -> int:
        return self.array.shape[0] * self.width

    def _pixel(self, index: int) -> Color:
        if index < 0:
            index += len(self)
        if not 0 <= index < len(self):
            raise IndexError(f"pixel index {index} is outside the canvas")
        r, g, b = self.array[index // self.width, index % self.width].tolist()
        return Color(r, g, b)

    @overload
    def __getitem__(self, index: int) -> Color: ...
    @overload
    def __getitem__(self, index: slice) -> list[Color]: ...
    def __getitem__(self, index: int | slice) -> Color | list[Color]:
        if isinstance(index, slice):
            return [self._pixel(i) for i in range(*index.indices(len(self)))]
        return self._pixel(index)

    def __setitem__(self, index: int, color: Color) -> None:
        if index < 0:
            index += len(self)
        if not 0 <= index < len(self):
            raise IndexError(f"pixel index {index} is outside the canvas")
        self.array[index // self.width, index % self.width] = (color.red, color.green, color.blue)

    def __iter__(self) -> Iterator[Color]:
        for row in self.array.tolist():
            for r, g, b in row:
                yield Color(r, g, b)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, PixelView):
            return self.array.shape == other.array.shape and bool(
                np.array_equal(self.array, other.array)
            )
        if isinstance(other, list):
            return len(other) == len(self) and all(a == b for a, b in zip(self, other, strict=True))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]


class ArrayCanvas(Canvas):
    """A ``Canvas`` whose pixels live in ``array`` (height, width, 3), float32 or float64."""

    __slots__ = ("array",)

    def __init__(self, array: np.ndarray) -> None:
        if array.ndim != 3 or array.shape[2] != 3:
            raise ValueError(f"ArrayCanvas: expected a (height, width, 3) array, got {array.shape}")
        self.array = array
        super().__init__(array.shape[1], array.shape[0], PixelView(array))  # type: ignore[arg-type]

    def to_array(self) -> np.ndarray:
        """The colors as a float64 (height, width, 3) array (unclamped)."""
        return np.asarray(self.array, dtype=np.float64)

    def to_rgb8(self) -> bytes:
        """Row-major RGB bytes, converted as ``raytracer.canvas.to_byte`` does: clamped to
        [0, 1], scaled by 255, rounded half up; NaN is 0. (In place on one float64 copy:
        clamping first gives the same bytes, and truncating a non-negative is flooring;
        ``fmax`` takes 0 over a NaN, so the copy and the clamp are two passes.)"""
        values = np.fmax(self.array, 0.0, dtype=np.float64)
        np.fmin(values, 1.0, out=values)
        values *= 255.0
        values += 0.5
        return values.astype(np.uint8).tobytes()

    def __reduce__(self) -> tuple[Any, ...]:
        return (ArrayCanvas, (self.array,))


class ArrayCanvasTracer(Tracer):
    """A tracer whose canvas is an ``ArrayCanvas`` of ``canvas_dtype()``: ``new_canvas``
    makes one, ``write_region`` fills a region of it in one array assignment."""

    __slots__ = ()

    def canvas_dtype(self) -> Any:
        """The float type of the canvases this tracer makes."""
        return np.float64

    def new_canvas(self, c: Camera) -> ArrayCanvas:
        """Chapter 2: an array-backed canvas, all black."""
        return ArrayCanvas(np.zeros((c.vsize, c.hsize, 3), dtype=self.canvas_dtype()))

    def write_region(self, image: Canvas, region: Region, values: Sequence[float]) -> None:
        """A region's pixels into ``image``: one array assignment on an ``ArrayCanvas``."""
        if not isinstance(image, ArrayCanvas):
            super().write_region(image, region, values)
            return
        x0, y0, x1, y1 = region
        block = np.asarray(values, dtype=image.array.dtype).reshape(y1 - y0, x1 - x0, 3)
        image.array[y0:y1, x0:x1] = block
