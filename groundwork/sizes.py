"""A canvas size: ``Size`` and the one parser of ``WIDTHxHEIGHT`` that every command uses.

The largest side is the book canvas's own limit (``raytracer.canvas.MAX_SIDE``); the bench's
budget rule, which shrinks a size to fit a time budget, is the harness's
(``harness.engine.budget``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from raytracer.canvas import MAX_SIDE

__all__ = ["MAX_SIDE", "Size", "parse_size"]


@dataclass(frozen=True, order=True)
class Size:
    """A canvas size in pixels."""

    width: int
    height: int

    @property
    def pixels(self) -> int:
        return self.width * self.height

    def __str__(self) -> str:
        return f"{self.width}x{self.height}"


def parse_size(text: str, option: str = "size") -> Size:
    """``"160x120"`` -> ``Size(160, 120)``; a ``ValueError`` naming ``option`` (``--size``)
    and the text otherwise, a side out of 1 to ``MAX_SIDE`` included."""
    match = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text)
    if not match:
        raise ValueError(f"bad {option} {text!r}: expected WIDTHxHEIGHT, e.g. 160x120")
    size = Size(int(match.group(1)), int(match.group(2)))
    if not (1 <= size.width <= MAX_SIDE and 1 <= size.height <= MAX_SIDE):
        raise ValueError(f"bad {option} {text!r}: width and height must be 1 to {MAX_SIDE}")
    return size
