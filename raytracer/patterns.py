"""Patterns (chapter 10): colors that vary over space: stripes, gradients, rings, checkers.

A pattern is an entity (``set_pattern_transform`` changes it) with its own ``transform``, from
pattern space to the object space of the shape it is on. Naive on purpose: its
``inverse_transform`` inverts ``transform`` on every access.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

from raytracer.colors import Color
from raytracer.matrices import (
    Matrix,
    NotInvertibleError,
    book_name,
    identity_matrix,
    inverse_of,
    is_invertible,
)
from raytracer.space import Placed, world_to_object
from raytracer.tuples import Tuple


@dataclass(slots=True, eq=True)
class Pattern(ABC):
    """Chapter 10: what every pattern has.

    transform: pattern space to the shape's object space (keyword only; default identity).
    """

    transform: Matrix = field(default=identity_matrix, kw_only=True)

    @property
    def inverse_transform(self) -> Matrix:
        """The inverse of ``transform``, computed on every access (the naive baseline)."""
        return inverse_of(self.transform, f"the pattern {book_name(self)}")

    @abstractmethod
    def local_pattern_at(self, point: Tuple) -> Color:
        """The color at a point in pattern space."""


@dataclass(slots=True, eq=True)
class StripePattern(Pattern):
    """Chapter 10: stripes along x, alternating ``a`` and ``b`` every unit."""

    a: Color
    b: Color

    def local_pattern_at(self, point: Tuple) -> Color:
        return self.a if math.floor(point.x) % 2 == 0 else self.b


@dataclass(slots=True, eq=True)
class GradientPattern(Pattern):
    """Chapter 10: a linear blend from ``a`` at x = 0 to ``b`` at x = 1, repeating."""

    a: Color
    b: Color

    def local_pattern_at(self, point: Tuple) -> Color:
        fraction = point.x - math.floor(point.x)
        return self.a + (self.b - self.a) * fraction


@dataclass(slots=True, eq=True)
class RingPattern(Pattern):
    """Chapter 10: concentric rings around the y axis, alternating ``a`` and ``b``."""

    a: Color
    b: Color

    def local_pattern_at(self, point: Tuple) -> Color:
        distance = math.sqrt(point.x * point.x + point.z * point.z)
        return self.a if math.floor(distance) % 2 == 0 else self.b


@dataclass(slots=True, eq=True)
class CheckersPattern(Pattern):
    """Chapter 10: 3D checkers of unit cubes, alternating ``a`` and ``b``."""

    a: Color
    b: Color

    def local_pattern_at(self, point: Tuple) -> Color:
        total = math.floor(point.x) + math.floor(point.y) + math.floor(point.z)
        return self.a if total % 2 == 0 else self.b


@dataclass(slots=True, eq=True)
class TestPattern(Pattern):
    """Chapter 10: the color is the pattern-space point itself: shows which space it sees."""

    __test__ = False  # not a pytest test class, despite the name

    def local_pattern_at(self, point: Tuple) -> Color:
        return Color(point.x, point.y, point.z)


def stripe_pattern(a: Color, b: Color) -> StripePattern:
    """Chapter 10: stripes of ``a`` and ``b``."""
    return StripePattern(a, b)


def gradient_pattern(a: Color, b: Color) -> GradientPattern:
    """Chapter 10: a gradient from ``a`` to ``b``."""
    return GradientPattern(a, b)


def ring_pattern(a: Color, b: Color) -> RingPattern:
    """Chapter 10: rings of ``a`` and ``b``."""
    return RingPattern(a, b)


def checkers_pattern(a: Color, b: Color) -> CheckersPattern:
    """Chapter 10: checkers of ``a`` and ``b``."""
    return CheckersPattern(a, b)


def test_pattern() -> TestPattern:
    """Chapter 10: the test pattern."""
    return TestPattern()


test_pattern.__test__ = False  # type: ignore[attr-defined]  # not a pytest test function


def set_pattern_transform(pattern: Pattern, m: Matrix) -> None:
    """Chapter 10: give ``pattern`` the transformation ``m``; it must be invertible."""
    if not is_invertible(m):
        raise NotInvertibleError(
            f"set_pattern_transform({type(pattern).__name__}): the transform is not "
            "invertible (determinant 0)"
        )
    pattern.transform = m


def pattern_at(pattern: Pattern, point: Tuple) -> Color:
    """Chapter 10: the color of ``pattern`` at a point already in pattern space."""
    return pattern.local_pattern_at(point)


def pattern_at_shape(pattern: Pattern, shape: Placed, world_point: Tuple) -> Color:
    """Chapters 10 and 14: the color of ``pattern`` on ``shape`` at a world-space point."""
    object_point = world_to_object(shape, world_point)
    pattern_point = pattern.inverse_transform * object_point
    return pattern.local_pattern_at(pattern_point)


def stripe_at(pattern: StripePattern, point: Tuple) -> Color:
    """Chapter 10: the stripe color at a pattern-space point."""
    return pattern.local_pattern_at(point)


def stripe_at_object(pattern: StripePattern, obj: Placed, world_point: Tuple) -> Color:
    """Chapter 10: the stripe color on ``obj`` at a world-space point."""
    return pattern_at_shape(pattern, obj, world_point)
