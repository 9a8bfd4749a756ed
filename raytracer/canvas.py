"""The canvas (chapter 2): a grid of colors, and its conversion to PPM text and RGB bytes.

The canvas is an entity: ``write_pixel`` changes it in place. Pixels are stored in one flat,
row-major list of ``Color`` values (index ``y * width + x``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.colors import BLACK, Color

MAX_SIDE = 16384  # larger canvases are almost certainly a mistake (and would not fit in memory)
PPM_LINE_LENGTH = 70  # the PPM format's recommended maximum line length


def _whole(value: object) -> int | None:
    """``value`` as an int if it is a whole number (``3`` or ``3.0``), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return value
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return None


@dataclass(slots=True, eq=True)
class Canvas:
    """A ``width`` x ``height`` image; ``pixels`` is row-major, all black when not given."""

    width: int
    height: int
    pixels: list[Color] = field(default_factory=list, repr=False)

    def __post_init__(self) -> None:
        width, height = _whole(self.width), _whole(self.height)
        if (
            width is None
            or height is None
            or not (1 <= width <= MAX_SIDE and 1 <= height <= MAX_SIDE)
        ):
            raise ValueError(
                f"canvas({self.width!r}, {self.height!r}): width and height must be whole "
                f"numbers from 1 to {MAX_SIDE}"
            )
        self.width, self.height = width, height
        if not self.pixels:
            self.pixels = [BLACK] * (width * height)
        elif len(self.pixels) != width * height:
            raise ValueError(
                f"canvas({width}, {height}): expected {width * height} pixels, "
                f"got {len(self.pixels)}"
            )


def canvas(width: int, height: int) -> Canvas:
    """Chapter 2: a new canvas, every pixel black.

    width, height: the size in pixels, 1 to 16384 on a side.
    """
    return Canvas(width, height)


def _index(c: Canvas, x: int, y: int, caller: str) -> int:
    """The list index of pixel (x, y), or a clear error naming the pixel and the canvas size."""
    col, row = _whole(x), _whole(y)
    if col is None or row is None or not (0 <= col < c.width and 0 <= row < c.height):
        raise ValueError(
            f"{caller}: pixel ({x!r}, {y!r}) is outside the {c.width}x{c.height} canvas "
            f"(x from 0 to {c.width - 1}, y from 0 to {c.height - 1})"
        )
    return row * c.width + col


def write_pixel(c: Canvas, x: int, y: int, color: Color) -> None:
    """Chapter 2: set pixel (x, y) of ``c`` to ``color``; (0, 0) is the top left corner."""
    c.pixels[_index(c, x, y, "write_pixel")] = color


def pixel_at(c: Canvas, x: int, y: int) -> Color:
    """Chapter 2: the color of pixel (x, y) of ``c``."""
    return c.pixels[_index(c, x, y, "pixel_at")]


def to_byte(component: float) -> int:
    """A color component as 0..255: clamped to [0, 1], scaled, rounded half up (NaN is 0)."""
    if not component > 0.0:
        return 0
    if component >= 1.0:
        return 255
    return int(component * 255 + 0.5)


def canvas_to_ppm(c: Canvas) -> str:
    """Chapter 2: the canvas as plain PPM (P3) text.

    Header ``P3``, ``width height``, ``255``; then each row of pixels, its values wrapped so
    no line is longer than 70 characters; the text ends with a newline.
    """
    lines = ["P3", f"{c.width} {c.height}", "255"]
    for y in range(c.height):
        line = ""
        for x in range(c.width):
            pixel = c.pixels[y * c.width + x]
            for component in (pixel.red, pixel.green, pixel.blue):
                token = str(to_byte(component))
                if not line:
                    line = token
                elif len(line) + 1 + len(token) <= PPM_LINE_LENGTH:
                    line = line + " " + token
                else:
                    lines.append(line)
                    line = token
        lines.append(line)
    return "\n".join(lines) + "\n"


def canvas_to_rgb8(c: Canvas) -> bytes:
    """The canvas as row-major RGB bytes (3 per pixel), converted as in ``canvas_to_ppm``."""
    out = bytearray()
    for pixel in c.pixels:
        out.append(to_byte(pixel.red))
        out.append(to_byte(pixel.green))
        out.append(to_byte(pixel.blue))
    return bytes(out)
