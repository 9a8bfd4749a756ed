"""Image files for image textures (the bonus chapter "Texture mapping"), read once per load.

``- file: NAME`` in a ``type: image`` UV pattern is read relative to the scene file's folder:
a plain PPM (P3) through the variant's ``canvas_from_ppm``, anything else (PNG, binary PPM,
JPEG ...) through Pillow, its 8-bit values divided by 255 like the PPM reader's (no gamma
curve, as chapter 2's ``canvas_to_ppm`` writes them). A decoded image is kept for the rest
of the load (``Context.images``): a cube may show one picture on six faces.
"""

from __future__ import annotations

import struct
import warnings
from pathlib import Path
from typing import Any

from yaml.nodes import Node

from raytracer.canvas import Canvas
from raytracer.colors import Color
from scene.context import Context
from scene.errors import SceneError

PLAIN_PPM_SUFFIXES = (".ppm", ".pnm")
MAX_IMAGE_BYTES = 64 * 1024 * 1024  # a larger texture file is almost certainly a mistake
# a texture becomes one color value a pixel (about 60 bytes each in the reference): 4096x4096
# is about a gigabyte; more is almost certainly a mistake
MAX_IMAGE_PIXELS = 4096 * 4096


def image_path(ctx: Context, node: Node) -> Path:
    """The image file a ``file:`` names, relative to the scene file; it must exist."""
    name = ctx.reader.string(node, "the image's file")
    path = (ctx.reader.path.parent / name).resolve()
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
        size = path.stat().st_size
        if size > MAX_IMAGE_BYTES:
            ctx.reader.fail(
                node,
                f"image file {path} is {size // (1024 * 1024)} MB; textures up to "
                f"{MAX_IMAGE_BYTES // (1024 * 1024)} MB are read",
            )
        data = path.read_bytes()
    except OSError as error:
        ctx.reader.fail(node, f"cannot read image file {path}: {error.strerror or error}")
    if path.suffix.lower() in PLAIN_PPM_SUFFIXES and not data.startswith(b"P6"):
        reader = ctx.need("canvas_from_ppm", node, "a PPM image texture")
        try:
            return reader(data.decode("latin-1"))
        except ValueError as error:
            ctx.reader.fail(node, f"the image file {path} is not a plain PPM image: {error}")
    return _decode_with_pillow(ctx, node, path)


def _too_large(ctx: Context, node: Node, path: Path, width: int, height: int) -> None:
    if width * height > MAX_IMAGE_PIXELS:
        ctx.reader.fail(
            node,
            f"the image file {path} is {width}x{height} = {width * height:,} pixels; textures "
            f"up to {MAX_IMAGE_PIXELS:,} pixels (4096x4096) are read",
        )


def _decode_with_pillow(ctx: Context, node: Node, path: Path) -> Canvas:
    from PIL import Image, UnidentifiedImageError  # only scenes with image textures need it

    try:
        with warnings.catch_warnings():  # Pillow warns of a huge image on stderr; refuse it
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(path) as image:
                _too_large(ctx, node, path, *image.size)  # before its pixels are decoded
                image.load()
                rgb = image.convert("RGB")
    except SceneError:  # a ValueError, from _too_large
        raise
    except UnidentifiedImageError:
        ctx.reader.fail(node, f"the image file {path} is not an image Pillow can read")
    except (Image.DecompressionBombWarning, Image.DecompressionBombError) as error:
        ctx.reader.fail(node, f"the image file {path} is too large to read: {error}")
    except (OSError, SyntaxError, ValueError, EOFError, struct.error) as error:
        ctx.reader.fail(node, f"the image file {path} is broken: {error}")
    width, height = rgb.size
    levels = [i / 255 for i in range(256)]
    data = rgb.tobytes()
    pixels = [
        Color(levels[data[i]], levels[data[i + 1]], levels[data[i + 2]])
        for i in range(0, len(data), 3)
    ]
    try:
        return Canvas(width, height, pixels)
    except ValueError as error:
        ctx.reader.fail(node, f"the image file {path} cannot be a texture: {error}")
