"""Colors (chapter 2): red, green and blue as floats, 0 to 1 for visible values."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Color:
    """The book's color. ``Color * Color`` is the Hadamard (component-wise) product."""

    red: float
    green: float
    blue: float

    def __add__(self, other: Color) -> Color:
        return Color(self.red + other.red, self.green + other.green, self.blue + other.blue)

    def __sub__(self, other: Color) -> Color:
        return Color(self.red - other.red, self.green - other.green, self.blue - other.blue)

    def __mul__(self, other: Color | float) -> Color:
        if isinstance(other, Color):
            return Color(self.red * other.red, self.green * other.green, self.blue * other.blue)
        return Color(self.red * other, self.green * other, self.blue * other)

    def __rmul__(self, k: float) -> Color:
        return Color(self.red * k, self.green * k, self.blue * k)


def color(red: float, green: float, blue: float) -> Color:
    """Chapter 2: a color."""
    return Color(red, green, blue)


BLACK = Color(0.0, 0.0, 0.0)
WHITE = Color(1.0, 1.0, 1.0)
