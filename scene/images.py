"""Image files for image textures (the bonus chapter "Texture mapping"), read once per load.

``- file: NAME`` in a ``type: image`` UV pattern is read relative to the scene file's folder:
a plain PPM (P3) through the variant's ``canvas_from_ppm``, anything else (PNG, binary PPM,
JPEG ...) through Pillow, its 8-bit values divided by 255 like the PPM reader's (no gamma
curve, as chapter 2's ``canvas_to_ppm`` writes them). A decoded image is kept for the rest
of the load (``Context.images``): a cube may show one picture on six faces.
"""

from __future__ import annotations

import io
import struct
import warnings
from pathlib import Path
from typing import Any

from yaml.nodes import Node

from raytracer.canvas import Canvas
from raytracer.colors import Color
from scene.context import Context
from scene.errors import SceneError
from scene.files import describe, read_bytes
from scene.memory import NotEnoughMemory, check

PLAIN_PPM_SUFFIXES = (".ppm", ".pnm")
MAX_IMAGE_BYTES = 64 * 1024 * 1024  # a larger texture file is almost certainly a mistake
# a texture becomes one color value a pixel (about 60 bytes each in the reference): 4096x4096
# is about a gigabyte; more is almost certainly a mistake
MAX_IMAGE_PIXELS = 4096 * 4096
# what a texture's pixel costs while it is read, at the peak (measured): a plain PPM's text
# split into numbers, then colors; an image Pillow decodes, as colors
PPM_BYTES_PER_PIXEL = 300
IMAGE_BYTES_PER_PIXEL = 150


def image_path(ctx: Context, node: Node) -> Path:
    """The image file a ``file:`` names, relative to the scene file; it must exist."""
    name = ctx.reader.string(node, "the image's file")
    path = (ctx.reader.path.parent / name).resolve()
    odd = describe(path)  # a named pipe would block the reader, a device never end
    if odd is not None:
        ctx.reader.fail(node, f"cannot read image file {path}: {odd}")
    if not path.is_file():
        ctx.reader.fail(
            node,
            f"image file not found: {path} ('{name}' is read relative to the scene file's folder)",
        )
    return path


def load_image(ctx: Context, node: Node) -> Any:
    """The canvas of the image file ``node`` names, decoded once per load."""
    path = image_path(ctx, node)
    if path not in ctx.images:
        ctx.images[path] = _decode(ctx, node, path)
    return ctx.images[path]


def _decode(ctx: Context, node: Node, path: Path) -> Any:
    try:
        data = read_bytes(path, MAX_IMAGE_BYTES)
    except OSError as error:
        ctx.reader.fail(node, f"cannot read image file {path}: {error.strerror or error}")
    if path.suffix.lower() in PLAIN_PPM_SUFFIXES and not data.startswith(b"P6"):
        reader = ctx.need("canvas_from_ppm", node, "a PPM image texture")
        size = _plain_ppm_size(data)
        if size is not None:  # else the reader says what is wrong with it
            _too_large(ctx, node, path, *size, PPM_BYTES_PER_PIXEL)
        try:
            return reader(data.decode("latin-1"))
        except ValueError as error:
            ctx.reader.fail(node, f"the image file {path} is not a plain PPM image: {error}")
    return _decode_with_pillow(ctx, node, path, data)


def _plain_ppm_size(data: bytes) -> tuple[int, int] | None:
    """A plain PPM's width and height from its header (Pillow reads it without the pixels),
    or None when Pillow cannot read the header."""
    from PIL import Image

    try:
        with Image.open(io.BytesIO(data), formats=["PPM"]) as image:
            return image.size
    except (OSError, SyntaxError, ValueError, EOFError):
        return None


def _too_large(
    ctx: Context, node: Node, path: Path, width: int, height: int, per_pixel: int
) -> None:
    """Refuse a texture of more pixels than ``MAX_IMAGE_PIXELS``, or than fit in memory at
    ``per_pixel`` bytes each, before its pixels are decoded."""
    if width * height > MAX_IMAGE_PIXELS:
        ctx.reader.fail(
            node,
            f"the image file {path} is {width}x{height} = {width * height:,} pixels; textures "
            f"up to {MAX_IMAGE_PIXELS:,} pixels (4096x4096) are read",
        )
    try:
        check(width * height * per_pixel, f"the {width}x{height} texture {path}")
    except NotEnoughMemory as error:
        ctx.reader.fail(node, str(error))


def _levels(ctx: Context, node: Node, path: Path, image: Any) -> list[float]:
    """The decoded ``image``'s channel levels from 0 to 1, three a pixel, row by row: 8-bit
    values divided by 255, a 16-bit grey image's by 65535 (Pillow's conversion to RGB would
    clip them at 255: 25% grey would turn white). Equal values share one float."""
    mode = image.mode
    if mode.startswith("I;16") or mode == "I":
        grey = list(image.getdata())
        if mode == "I" and (min(grey, default=0) < 0 or max(grey, default=0) > 65535):
            ctx.reader.fail(
                node, f"the image file {path} has 32-bit pixels; textures are 8 or 16 bits "
                "a channel: save it as an 8- or 16-bit PNG",
            )  # fmt: skip
        table = [i / 65535 for i in range(65536)]
        return [table[v] for v in grey for _ in range(3)]
    if mode == "F":
        ctx.reader.fail(
            node, f"the image file {path} has floating-point pixels (mode F); textures are 8 "
            "or 16 bits a channel: save it as an 8- or 16-bit PNG",
        )  # fmt: skip
    table = [i / 255 for i in range(256)]
    return [table[v] for v in image.convert("RGB").tobytes()]


def _decode_with_pillow(ctx: Context, node: Node, path: Path, data: bytes) -> Canvas:
    from PIL import Image, UnidentifiedImageError  # only scenes with image textures need it

    try:
        with warnings.catch_warnings():  # Pillow warns of a huge image on stderr; refuse it
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(data)) as image:
                _too_large(ctx, node, path, *image.size, IMAGE_BYTES_PER_PIXEL)  # before
                image.load()  # its pixels are decoded
                levels = _levels(ctx, node, path, image)
    except SceneError:  # a ValueError, from _too_large
        raise
    except UnidentifiedImageError:
        ctx.reader.fail(node, f"the image file {path} is not an image Pillow can read")
    except (Image.DecompressionBombWarning, Image.DecompressionBombError) as error:
        ctx.reader.fail(node, f"the image file {path} is too large to read: {error}")
    except (OSError, SyntaxError, ValueError, EOFError, struct.error) as error:
        ctx.reader.fail(node, f"the image file {path} is broken: {error}")
    width, height = image.size
    pixels = [Color(levels[i], levels[i + 1], levels[i + 2]) for i in range(0, len(levels), 3)]
    try:
        return Canvas(width, height, pixels)
    except ValueError as error:
        ctx.reader.fail(node, f"the image file {path} cannot be a texture: {error}")
