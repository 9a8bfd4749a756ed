"""Image error: how far a variant's picture is from the reference's, and heat maps of where.

Pictures are compared as float RGB arrays (height x width x 3), each channel clamped to
[0, 1] as the PNG shows it, before rounding to bytes: max and mean absolute difference over
all channels, RMSE, PSNR (peak 1.0; infinite when identical) and the number of pixels whose
largest channel difference exceeds 1/255 (one step of an 8-bit channel).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

ONE_STEP = 1.0 / 255.0


def canvas_array(canvas: Any, pixel_at: Any = None) -> np.ndarray:
    """A canvas as a float64 array (height, width, 3) of its unclamped colors.

    Uses the canvas's own ``to_array()`` if it has one, its ``pixels`` list if it is the
    reference's layout, else ``pixel_at(canvas, x, y)`` for every pixel.
    """
    to_array = getattr(canvas, "to_array", None)
    if callable(to_array):
        found = np.asarray(to_array(), dtype=np.float64)
        return found.reshape(canvas.height, canvas.width, 3)
    pixels = getattr(canvas, "pixels", None)
    if isinstance(pixels, list) and len(pixels) == canvas.width * canvas.height:
        flat = [(p.red, p.green, p.blue) for p in pixels]
        return np.array(flat, dtype=np.float64).reshape(canvas.height, canvas.width, 3)
    if pixel_at is None:
        raise TypeError(f"cannot read the pixels of a {type(canvas).__name__} without pixel_at")
    rows = [
        [(c.red, c.green, c.blue) for c in (pixel_at(canvas, x, y) for x in range(canvas.width))]
        for y in range(canvas.height)
    ]
    return np.array(rows, dtype=np.float64)


@dataclass(frozen=True)
class ImageError:
    """The difference between two pictures of the same size (see the module docstring)."""

    max_abs: float
    mean_abs: float
    rmse: float
    psnr: float  # decibels; math.inf when identical
    pixels_over_one_step: int
    pixels: int

    def as_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["psnr"] = None if math.isinf(self.psnr) else self.psnr  # JSON has no infinity
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> ImageError:
        psnr = data.get("psnr")
        return cls(
            float(data["max_abs"]),
            float(data["mean_abs"]),
            float(data["rmse"]),
            math.inf if psnr is None else float(psnr),
            int(data["pixels_over_one_step"]),
            int(data["pixels"]),
        )


def clamped(image: np.ndarray) -> np.ndarray:
    return np.clip(np.nan_to_num(image, nan=0.0), 0.0, 1.0)


def image_error(image: np.ndarray, reference: np.ndarray) -> ImageError:
    """How far ``image`` is from ``reference`` (both height x width x 3, same size)."""
    if image.shape != reference.shape:
        raise ValueError(
            f"image_error: sizes differ, {image.shape[1]}x{image.shape[0]} against "
            f"{reference.shape[1]}x{reference.shape[0]}"
        )
    diff = np.abs(clamped(image) - clamped(reference))
    rmse = float(np.sqrt(np.mean(diff * diff)))
    return ImageError(
        max_abs=float(diff.max()),
        mean_abs=float(diff.mean()),
        rmse=rmse,
        psnr=math.inf if rmse == 0 else 20 * math.log10(1.0 / rmse),
        pixels_over_one_step=int(np.count_nonzero(diff.max(axis=2) > ONE_STEP)),
        pixels=int(diff.shape[0] * diff.shape[1]),
    )


def to_rgb8(image: np.ndarray) -> np.ndarray:
    """Bytes as the PNG writer makes them: clamp, scale by 255, round half up."""
    return np.floor(clamped(image) * 255 + 0.5).astype(np.uint8)


def save_png(image: np.ndarray, path: Path, scale: int = 1) -> None:
    """Write a float RGB array as a PNG (``scale``: whole-pixel enlargement for small renders)."""
    # deferred: saves ~45 ms (Pillow) of a measuring process, which writes no PNG
    from PIL import Image

    rgb = to_rgb8(image)
    if scale > 1:
        rgb = np.repeat(np.repeat(rgb, scale, axis=0), scale, axis=1)
    Image.fromarray(rgb, "RGB").save(path, format="PNG")


HEAT_LOW = 1e-6  # heat maps: a difference this small or smaller is black
HEAT_HIGH = 1.0  # ... and this large is the brightest colour
HEAT_MAP = "inferno"


def heat_level(difference: np.ndarray | float, low: float = HEAT_LOW) -> np.ndarray:
    """Where a difference falls on the heat maps' logarithmic scale: 0 at ``low`` and
    below, 1 at ``HEAT_HIGH``; each tenfold larger difference a step up."""
    value = np.maximum(np.asarray(difference, dtype=np.float64), low)
    return np.asarray(np.clip(np.log10(value / low) / np.log10(HEAT_HIGH / low), 0.0, 1.0))


def heat_map(image: np.ndarray, reference: np.ndarray, low: float = HEAT_LOW) -> np.ndarray:
    """Where two pictures differ: each pixel's largest channel difference on a logarithmic
    colour scale (``heat_level``: ``low`` and below black, 1 the brightest), through the
    'inferno' colour map, as an RGB float array. The scale is amplified so that a float32
    rounding (1e-6) and a whole step of a byte (1/255) both show, apart."""
    # deferred: saves ~500 ms (matplotlib) of a measuring process, which draws no heat map
    from matplotlib import colormaps

    diff = np.abs(clamped(image) - clamped(reference)).max(axis=2)
    colored = colormaps[HEAT_MAP](heat_level(diff, low))[..., :3]
    return np.asarray(colored, dtype=np.float64)


def where_different(image: np.ndarray, reference: np.ndarray) -> dict[str, Any]:
    """Where two pictures differ by more than one step of a byte (``ONE_STEP``): how many
    pixels, and the box (x0, y0, x1, y1, pixels from the top left, inclusive) holding the
    middle 90% of them across and down (stray pixels elsewhere left out)."""
    off = np.abs(clamped(image) - clamped(reference)).max(axis=2) > ONE_STEP
    ys, xs = np.nonzero(off)
    found: dict[str, Any] = {"pixels_off": int(off.sum()), "pixels": int(off.size)}
    if len(xs):
        x0, x1 = np.percentile(xs, [5, 95])
        y0, y1 = np.percentile(ys, [5, 95])
        found["box"] = [int(x0), int(y0), int(x1), int(y1)]
    return found
