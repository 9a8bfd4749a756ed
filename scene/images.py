"""Image files for image textures (the bonus chapter "Texture mapping"), read once per load.

``- file: NAME`` in a ``type: image`` UV pattern is read relative to the scene file's folder:
a plain PPM (P3) through the variant's ``canvas_from_ppm``, a PNG or a binary PPM through
Pillow, opened as those formats only (``PILLOW_FORMATS``: never another format Pillow would
recognize by content, such as EPS, which it hands to Ghostscript), its 8-bit values
divided by 255 like the PPM reader's (no gamma curve, as chapter 2's ``canvas_to_ppm``
writes them). A decoded image is kept for the rest
of the load (``Context.images``): a cube may show one picture on six faces.
"""

from __future__ import annotations

import functools
import io
import re
import struct
import warnings
from array import array
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, overload

import numpy as np
from yaml.nodes import Node

from groundwork.files import describe, read_bytes, resolved
from groundwork.memory import NotEnoughMemory, check
from raytracer.canvas import Canvas
from raytracer.colors import Color
from scene.context import Context
from scene.errors import SceneError

PLAIN_PPM_SUFFIXES = (".ppm", ".pnm")
# the formats the scene format documents, and no other: Pillow would otherwise open any
# format it knows by its content (an EPS file named .png starts Ghostscript on it)
PILLOW_FORMATS = ("PNG", "PPM")
MAX_IMAGE_BYTES = 64 * 1024 * 1024  # a larger texture file is almost certainly a mistake
# a texture becomes one color value a pixel (about 60 bytes each in the reference): 4096x4096
# is about a gigabyte; more is almost certainly a mistake
MAX_IMAGE_PIXELS = 4096 * 4096
# what a texture's pixel costs while it is read, at the peak (measured): a plain PPM's text
# split into numbers, then colors; an image Pillow decodes, its channel values (``Texels``)
PPM_BYTES_PER_PIXEL = 300
IMAGE_BYTES_PER_PIXEL = 24


def image_path(ctx: Context, node: Node) -> Path:
    """The image file a ``file:`` names, relative to the scene file; it must exist."""
    name = ctx.reader.string(node, "the image's file")
    try:
        path = resolved(ctx.reader.path.parent / name)
    except OSError as error:
        ctx.reader.fail(node, f"cannot read image file {error.filename}: {error.strerror}")
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


_PPM_HEADER = re.compile(rb"P3(?:\s|#[^\n]*\n)+(\d{1,12})(?:\s|#[^\n]*\n)+(\d{1,12})\s")


def _plain_ppm_size(data: bytes) -> tuple[int, int] | None:
    """A plain PPM's width and height from its header, read without the pixels (any size:
    ``_too_large`` judges it), or None when there is no such header (the reader then says
    what is wrong)."""
    header = _PPM_HEADER.match(data[:4096])
    return None if header is None else (int(header[1]), int(header[2]))


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


class Texels(Sequence[Color]):
    """An image texture's pixels as ``Color`` values, made when they are read from the
    channel values Pillow decoded (``channels``: bytes of ``bits`` 8, three a pixel, or of
    16, one grey value a pixel): 8-bit values divided by 255, 16-bit grey ones by 65535
    (Pillow's conversion to RGB would clip those at 255: 25% grey would turn white). A
    4096x4096 texture is 50 MB of bytes here, not millions of objects to build, keep and
    pickle (a pooled render sends it to every worker)."""

    __slots__ = ("_count", "_table", "bits", "channels")

    def __init__(self, channels: bytes, bits: int) -> None:
        self.channels = channels
        self.bits = bits
        self._count = len(channels) // 3 if bits == 8 else len(channels) // 2
        self._table = _levels(bits)
        if bits == 16:
            grey = array("H")
            grey.frombytes(channels)
            self.channels = grey  # type: ignore[assignment]

    def __len__(self) -> int:
        return self._count

    @overload
    def __getitem__(self, index: int) -> Color: ...

    @overload
    def __getitem__(self, index: slice) -> list[Color]: ...

    def __getitem__(self, index: int | slice) -> Color | list[Color]:
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(self._count))]
        if index < 0:
            index += self._count
        if not 0 <= index < self._count:
            raise IndexError("texture pixel index out of range")
        table, values = self._table, self.channels
        if self.bits == 16:
            level = table[values[index]]
            return Color(level, level, level)
        i = 3 * index
        return Color(table[values[i]], table[values[i + 1]], table[values[i + 2]])

    def __iter__(self) -> Iterator[Color]:
        return (self[i] for i in range(self._count))

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Texels):
            return self.bits == other.bits and bytes(self.channels) == bytes(other.channels)
        return list(self) == other if isinstance(other, list) else NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def levels(self) -> Any:
        """Every channel level as a numpy array (height x width x 3 once reshaped)."""
        if self.bits == 16:
            grey = np.asarray(self.channels, dtype=np.float64) / 65535.0
            return np.repeat(grey[:, None], 3, axis=1)
        return np.frombuffer(bytes(self.channels), dtype=np.uint8).reshape(-1, 3) / 255.0


@functools.cache
def _levels(bits: int) -> list[float]:
    """Each channel value's level (value / 255, or / 65535 for 16 bits), made when a texture
    first needs it: the 16-bit one is 65,536 divisions, a few milliseconds of every start."""
    top = 65535 if bits == 16 else 255
    return [i / top for i in range(top + 1)]


class TextureCanvas(Canvas):
    """An image texture: a ``Canvas`` whose pixels are ``Texels``; pickled as its channel
    values; ``array`` (height x width x 3 levels) for a tracer that packs it (numba)."""

    __slots__ = ()

    def __reduce__(self) -> tuple[Any, tuple[int, int, bytes, int]]:
        texels = self.pixels
        assert isinstance(texels, Texels)
        return texture_canvas, (self.width, self.height, bytes(texels.channels), texels.bits)

    @property
    def array(self) -> Any:
        texels = self.pixels
        assert isinstance(texels, Texels)
        return texels.levels().reshape(self.height, self.width, 3)


def texture_canvas(width: int, height: int, channels: bytes, bits: int) -> TextureCanvas:
    """The texture of ``channels`` (see ``Texels``)."""
    return TextureCanvas(width, height, Texels(channels, bits))  # type: ignore[arg-type]


def _channels(ctx: Context, node: Node, path: Path, image: Any) -> tuple[bytes, int]:
    """The decoded ``image``'s channel values and their bits (``TextureCanvas``)."""
    mode = image.mode
    if mode.startswith("I;16") or mode == "I":
        grey = np.asarray(image, dtype=np.int64).reshape(-1)
        if grey.size and (grey.min() < 0 or grey.max() > 65535):
            ctx.reader.fail(
                node, f"the image file {path} has 32-bit pixels; textures are 8 or 16 bits "
                "a channel: save it as an 8- or 16-bit PNG",
            )  # fmt: skip
        return grey.astype(np.uint16).tobytes(), 16
    if mode == "F":
        ctx.reader.fail(
            node, f"the image file {path} has floating-point pixels (mode F); textures are 8 "
            "or 16 bits a channel: save it as an 8- or 16-bit PNG",
        )  # fmt: skip
    return image.convert("RGB").tobytes(), 8


def _found(data: bytes) -> str:
    """What a texture that is no PNG or PPM holds, in words, for its error."""
    if not data:
        return "the file is empty"
    if data.startswith(b"\x89PNG"):
        return "it starts as a PNG but its header is broken or cut short"
    return "it starts with neither a PNG's signature nor a PPM's"


def _decode_with_pillow(ctx: Context, node: Node, path: Path, data: bytes) -> Canvas:
    # deferred: saves ~25 ms (Pillow) of every scene load without an image texture
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():  # Pillow warns of a huge image on stderr; refuse it
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(data), formats=PILLOW_FORMATS) as image:
                _too_large(ctx, node, path, *image.size, IMAGE_BYTES_PER_PIXEL)  # before
                image.load()  # its pixels are decoded
                channels, bits = _channels(ctx, node, path, image)
    except SceneError:  # a ValueError, from _too_large
        raise
    except UnidentifiedImageError:
        ctx.reader.fail(node, f"the image file {path} is not a PNG or PPM image: {_found(data)}")
    except (Image.DecompressionBombWarning, Image.DecompressionBombError) as error:
        ctx.reader.fail(node, f"the image file {path} is too large to read: {error}")
    except (OSError, SyntaxError, ValueError, EOFError, struct.error) as error:
        ctx.reader.fail(node, f"the image file {path} is broken: {error}")
    width, height = image.size
    try:
        return texture_canvas(width, height, channels, bits)
    except ValueError as error:
        ctx.reader.fail(node, f"the image file {path} cannot be a texture: {error}")
