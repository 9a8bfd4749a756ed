"""Writing canvases as image files (PNG or PPM) and reading PNGs back.

PNG is encoded here (``png_bytes``: 8-bit RGB, each row's "up" filter, zlib at its fastest
level: smaller than Pillow's own fast PNG of a render, and without importing Pillow and
the plugins its ``save`` loads, a quarter of a quick render's command), from the canvas's
own ``to_rgb8()`` when it has one (so a variant with an array-backed canvas skips the
per-pixel path), else from ``raytracer.canvas_to_rgb8``. PPM is the book's plain text
(``canvas_to_ppm``). Files are written atomically (``groundwork.files.write_atomically``).
PNGs are read back through Pillow (``read_png``), imported only then.
"""

from __future__ import annotations

import math
import os
import struct
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from groundwork.files import write_atomically
from raytracer.canvas import canvas_to_ppm, canvas_to_rgb8

FORMATS = (".png", ".ppm")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# IHDR after the size: bit depth 8, colour type 2 (RGB), deflate, filter set 0, no interlace
PNG_RGB8 = (8, 2, 0, 0, 0)
PNG_UP = 2  # the filter type a row gets: each byte minus the byte above it (mod 256)


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
    return png_bytes(data, canvas.width, canvas.height)


def png_bytes(rgb: bytes, width: int, height: int) -> bytes:
    """A PNG file of ``width`` x ``height`` row-major RGB bytes: one IDAT chunk of rows
    filtered "up" (a render's rows resemble the rows above them, so the differences pack
    small), deflated at zlib's fastest level."""
    rows = np.frombuffer(rgb, dtype=np.uint8).reshape(height, width * 3)
    filtered = np.empty((height, width * 3 + 1), dtype=np.uint8)
    filtered[:, 0] = PNG_UP
    filtered[:1, 1:] = rows[:1]  # the first row's "above" is zeros
    np.subtract(rows[1:], rows[:-1], out=filtered[1:, 1:])  # uint8: wraps mod 256
    header = struct.pack(">IIBBBBB", width, height, *PNG_RGB8)
    return b"".join(
        [
            PNG_SIGNATURE,
            _png_chunk(b"IHDR", header),
            _png_chunk(b"IDAT", zlib.compress(filtered.tobytes(), 1)),
            _png_chunk(b"IEND", b""),
        ]
    )


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    """A PNG chunk: its length, type, data and the CRC-32 of type and data."""
    crc = zlib.crc32(data, zlib.crc32(kind))
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)


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
        with np.errstate(all="ignore"):  # a sum past the largest float: looked at below
            total = float(array.sum())
        if math.isfinite(total):  # a NaN or an infinity would spread to the sum
            return None
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
    from PIL import Image  # deferred: a render writes PNGs without Pillow

    with Image.open(path, formats=["PNG"]) as image:  # never another format by its content
        rgb = image.convert("RGB")
        return rgb.width, rgb.height, rgb.tobytes()
