"""Patterns (chapter 10) writing their colour into a caller-owned ``[r, g, b]``.

One record class per reference pattern, with the pattern's inverse transform as a flat
list and its two colours as ``[r, g, b]`` lists; ``pattern_at_into`` is the twin of the
reference's ``local_pattern_at``, the same arithmetic in the same order.
"""

from __future__ import annotations

import math

from raytracer.patterns import (
    CheckersPattern,
    GradientPattern,
    Pattern,
    RingPattern,
    StripePattern,
    TestPattern,
)
from variants.prealloc.buffers import Vec
from variants.prealloc.geometry import flat_matrix
from variants.prealloc.records import PreallocUnsupported, check_reimplemented, color_buffer


class PatternRecord:
    """Chapter 10: what every pattern has: ``inverse`` (flat), and ``a``/``b`` colours."""

    __slots__ = ("a", "b", "inverse", "pattern")

    def __init__(self, pattern: Pattern) -> None:
        self.pattern = pattern
        self.inverse = flat_matrix(pattern.inverse_transform)
        name = type(pattern).__name__
        self.a = color_buffer(pattern.a, f"{name}.a") if hasattr(pattern, "a") else None
        self.b = color_buffer(pattern.b, f"{name}.b") if hasattr(pattern, "b") else None

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        """The colour at a pattern-space point (naive twin: ``local_pattern_at``)."""
        raise NotImplementedError


def _copy_color(c: Vec | None, out: Vec) -> None:
    assert c is not None
    out[0] = c[0]
    out[1] = c[1]
    out[2] = c[2]


class StripeRecord(PatternRecord):
    """Chapter 10: ``StripePattern.local_pattern_at``: a if floor(x) is even, else b."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        _copy_color(self.a if math.floor(point[0]) % 2 == 0 else self.b, out)


class GradientRecord(PatternRecord):
    """Chapter 10: ``GradientPattern.local_pattern_at``: a + (b - a) * fraction of x."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        a, b = self.a, self.b
        assert a is not None and b is not None
        x = point[0]
        fraction = x - math.floor(x)
        out[0] = a[0] + (b[0] - a[0]) * fraction
        out[1] = a[1] + (b[1] - a[1]) * fraction
        out[2] = a[2] + (b[2] - a[2]) * fraction


class RingRecord(PatternRecord):
    """Chapter 10: ``RingPattern.local_pattern_at``: by floor of the distance from y."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        x, z = point[0], point[2]
        distance = math.sqrt(x * x + z * z)
        _copy_color(self.a if math.floor(distance) % 2 == 0 else self.b, out)


class CheckersRecord(PatternRecord):
    """Chapter 10: ``CheckersPattern.local_pattern_at``: by floor(x) + floor(y) + floor(z)."""

    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        total = math.floor(point[0]) + math.floor(point[1]) + math.floor(point[2])
        _copy_color(self.a if total % 2 == 0 else self.b, out)


class TestPatternRecord(PatternRecord):
    """Chapter 10: ``TestPattern.local_pattern_at``: the point itself as a colour."""

    __test__ = False  # not a pytest test class, despite the name
    __slots__ = ()

    def pattern_at_into(self, point: Vec, out: Vec) -> None:
        out[0] = point[0]
        out[1] = point[1]
        out[2] = point[2]


PATTERN_RECORDS: dict[type[Pattern], type[PatternRecord]] = {
    StripePattern: StripeRecord,
    GradientPattern: GradientRecord,
    RingPattern: RingRecord,
    CheckersPattern: CheckersRecord,
    TestPattern: TestPatternRecord,
}


def pattern_record(pattern: Pattern) -> PatternRecord:
    """The record of a reference pattern (or a subclass that only caches, like ``cached``'s);
    ``PreallocUnsupported`` naming the type for any other pattern."""
    for cls in type(pattern).__mro__:
        record_class = PATTERN_RECORDS.get(cls)
        if record_class is not None:
            check_reimplemented(pattern, cls, ("local_pattern_at",))
            return record_class(pattern)
    raise PreallocUnsupported(
        f"prealloc: no implementation for pattern type {type(pattern).__name__}; it runs "
        f"{', '.join(cls.__name__ for cls in PATTERN_RECORDS)}"
    )
