"""Reading plain PPM images (the bonus chapter "Texture mapping"): ``canvas_from_ppm``, the
inverse of chapter 2's ``canvas_to_ppm``, for image textures.

The format (P3, "plain" PPM): the magic number ``P3``, the width, the height and the maximum
value, then width x height pixels of three whole numbers each (red, green, blue from 0 to the
maximum), row by row from the top left. Everything is separated by any whitespace, laid out
on lines any way at all; ``#`` starts a comment that runs to the end of its line, anywhere.
A value is scaled by the maximum (255 of 255 is 1.0; 50 of 100 is 0.5).
"""

from __future__ import annotations

from collections.abc import Iterator

from raytracer.canvas import MAX_SIDE, Canvas
from raytracer.colors import Color

MAGIC = "P3"
MAX_VALUE = 65535  # the format's largest maximum


class PPMError(ValueError):
    """A PPM text that is not a plain PPM image; the message names the line and the problem.

    line: the 1-based line of the text at fault (the last line when values are missing).
    """

    def __init__(self, line: int, message: str) -> None:
        super().__init__(f"PPM line {line}: {message}")
        self.line = line


def _tokens(text: str) -> Iterator[tuple[str, int]]:
    """Every whitespace-separated word outside comments, with its line number."""
    for number, line in enumerate(text.splitlines(), start=1):
        for token in line.split("#", 1)[0].split():
            yield token, number


def _whole(token: str) -> int | None:
    """A token of ASCII digits as its number (None for anything else). The largest value
    the format has is 65535: digits past 20 are only leading zeros or a number too large,
    which is kept as one too large (Python refuses to read thousands of digits)."""
    if not (token.isascii() and token.isdigit()):
        return None
    digits = token.lstrip("0") or "0"
    return int(digits) if len(digits) <= 20 else 10**20


def canvas_from_ppm(text: str) -> Canvas:
    """Texture mapping: the canvas a plain PPM (P3) text describes, colors scaled by its
    maximum value.

    A text that is not one (another magic number, a missing or non-numeric size, a value
    above the maximum, too few or too many values) raises ``PPMError``, a ``ValueError``
    naming the line.
    """
    if isinstance(text, bytes | bytearray):
        text = bytes(text).decode("latin-1")
    tokens = _tokens(text)
    last_line = max(1, len(text.splitlines()))

    magic = next(tokens, None)
    if magic is None:
        raise PPMError(1, f"the text is empty; a PPM image starts with {MAGIC!r}")
    if magic[0] != MAGIC:
        raise PPMError(
            magic[1],
            f"the magic number is {magic[0][:20]!r}, not {MAGIC!r}: only plain PPM images "
            "(P3, numbers as text) are read",
        )

    header: list[int] = []
    for what, low, high in (("width", 1, MAX_SIDE), ("height", 1, MAX_SIDE),
                            ("maximum value", 1, MAX_VALUE)):  # fmt: skip
        found = next(tokens, None)
        if found is None:
            raise PPMError(last_line, f"the text ends before the {what}")
        token, line = found
        number = _whole(token)
        if number is None or not low <= number <= high:
            raise PPMError(
                line, f"the {what} is {token[:20]!r}; expected a whole number from {low} to {high}"
            )
        header.append(number)
    width, height, maximum = header

    count = width * height * 3
    values: list[float] = []
    for token, line in tokens:
        if len(values) == count:
            raise PPMError(
                line,
                f"more values than the {width}x{height} image has ({count}: 3 per pixel), "
                f"starting with {token[:20]!r}",
            )
        number = _whole(token)
        if number is None:
            raise PPMError(
                line, f"{token[:20]!r} is not a color value (a whole number from 0 to {maximum})"
            )
        if number > maximum:
            shown = token if len(token) <= 20 else token[:17] + "..."
            raise PPMError(line, f"the value {shown} is above the maximum value {maximum}")
        values.append(number / maximum)
    if len(values) < count:
        raise PPMError(
            last_line,
            f"the text ends after {len(values)} of the {count} values of the {width}x{height} "
            "image (3 per pixel)",
        )
    pixels = [Color(values[i], values[i + 1], values[i + 2]) for i in range(0, count, 3)]
    return Canvas(width, height, pixels)
