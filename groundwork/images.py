"""Writing canvases as image files (PNG or PPM) and reading PNGs back.

PNG goes through Pillow, from the canvas's own ``to_rgb8()`` when it has one (so a variant
with an array-backed canvas skips the per-pixel path), else from
``raytracer.canvas_to_rgb8``. PPM is the book's plain text (``canvas_to_ppm``). Files are
written atomically (``groundwork.files.write_atomically``).
"""

from __future__ import annotations

import io
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from groundwork.files import write_atomically
from raytracer.canvas import canvas_to_ppm, canvas_to_rgb8

FORMATS = (".png", ".ppm")


def rgb8(canvas: Any) -> bytes:
    """The canvas as row-major RGB bytes: its own ``to_rgb8()`` if it has one."""
    to_rgb8 = getattr(canvas, "to_rgb8", None)
    if callable(to_rgb8):
        return bytes(to_rgb8())
    return canvas_to_rgb8(canvas)


def _encode(canvas: Any, suffix: str) -> bytes:
    if suffix == ".ppm":
        return canvas_to_ppm(canvas).encode("ascii")
    data = rgb8(canvas)
    expected = canvas.width * canvas.height * 3
    if len(data) != expected:
        raise ValueError(
            f"write_image: the {canvas.width}x{canvas.height} canvas gave {len(data)} bytes "
            f"of RGB, expected {expected}"
        )
    image = Image.frombytes("RGB", (canvas.width, canvas.height), data)
    buffer = io.BytesIO()
    image.save(buffer, format="PNG", compress_level=1)  # fast; files stay small for renders
    return buffer.getvalue()


def canvas_problem(canvas: Any, width: int, height: int) -> str | None:
    """What is wrong with ``canvas`` as the picture of a ``width`` x ``height`` camera (a
    variant's render, perhaps a learner's): not a canvas, another size, or a pixel that is
    not a finite number (NaN would be written black); None when it is fit to write."""
    size = (getattr(canvas, "width", None), getattr(canvas, "height", None))
    if not all(isinstance(side, int) for side in size) or not hasattr(canvas, "pixels"):
        return f"returned {type(canvas).__name__}, not a canvas"
    if size != (width, height):
        return f"returned a {size[0]}x{size[1]} canvas for a {width}x{height} camera"
    array = getattr(canvas, "array", None)
    if isinstance(array, np.ndarray) and array.ndim == 3:
        bad = np.argwhere(~np.isfinite(array).all(axis=-1))
        first = None if not len(bad) else (int(bad[0][1]), int(bad[0][0]))
        count = len(bad)
    else:
        found = [
            i for i, p in enumerate(canvas.pixels)
            if not (math.isfinite(p.red) and math.isfinite(p.green) and math.isfinite(p.blue))
        ]  # fmt: skip
        first = None if not found else (found[0] % width, found[0] // width)
        count = len(found)
    if first is None:
        return None
    return (
        f"returned {count} pixel{'s' if count > 1 else ''} that are not finite numbers (NaN "
        f"or infinite), the first at x={first[0]}, y={first[1]}"
    )


def write_image(canvas: Any, path: str | os.PathLike[str]) -> Path:
    """Write ``canvas`` to ``path`` as PNG or PPM, chosen by the extension; returns the path.

    canvas: a ``raytracer.Canvas`` (or a variant's subclass); path: ends in .png or .ppm.
    """
    target = Path(path)
    suffix = target.suffix.lower()
    if suffix not in FORMATS:
        shown = repr(target.suffix) if target.suffix else "no extension"
        raise ValueError(
            f"write_image({str(target)!r}): unknown image extension {shown}; "
            f"use {' or '.join(FORMATS)}"
        )
    return write_atomically(target, _encode(canvas, suffix))


def read_png(path: str | os.PathLike[str]) -> tuple[int, int, bytes]:
    """A PNG's ``(width, height, row-major RGB bytes)``."""
    with Image.open(path, formats=["PNG"]) as image:  # never another format by its content
        rgb = image.convert("RGB")
        return rgb.width, rgb.height, rgb.tobytes()
