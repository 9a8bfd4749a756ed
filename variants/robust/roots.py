"""Real roots of a polynomial without a closed form or a fixed tolerance: robust's way to the
torus's quartic (chapter 20 here, beyond the book).

The roots of the derivative (found the same way, down to a line) cut the real line into
stretches where the polynomial is monotone; a stretch whose ends differ in sign holds one
root, found by bisection to the last bit of a float. A turning point where the polynomial
is zero to within the rounding of its evaluation is a double root, listed twice (a ray
grazing the tube). Every decision is relative to the sizes of the terms, so a polynomial
scaled by 1e-12 or 1e12 has the same roots.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

UNIT = 2.0**-53


def value_at(c: Sequence[float], s: float) -> float:
    """The polynomial with coefficients ``c`` (highest power first) at ``s`` (Horner)."""
    total = 0.0
    for coefficient in c:
        total = total * s + coefficient
    return total


def rounding_at(c: Sequence[float], s: float) -> float:
    """A bound on the rounding error of ``value_at(c, s)``: 2n units of the sum of the
    terms' sizes (Higham's bound for Horner's scheme, with room for the inputs' own)."""
    size, power = 0.0, 1.0
    for coefficient in reversed(c):
        size += abs(coefficient) * power
        power *= abs(s)
    return 4 * len(c) * UNIT * size


def _bisect(c: Sequence[float], lo: float, hi: float, f_lo: float) -> float:
    """The root in [lo, hi] (the values at the ends of opposite signs) to the last bit."""
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return lo if abs(f_lo) <= abs(value_at(c, hi)) else hi
        f_mid = value_at(c, mid)
        if f_mid == 0.0:
            return mid
        if (f_mid < 0.0) == (f_lo < 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid


def derivative(c: Sequence[float]) -> list[float]:
    n = len(c) - 1
    return [coefficient * (n - i) for i, coefficient in enumerate(c[:-1])]


def real_roots(c: Sequence[float]) -> list[float]:
    """The real roots of ``c`` (highest power first, leading coefficient not 0), increasing,
    a double root twice. Roots beyond the Cauchy bound (1 + the largest ratio of a
    coefficient to the leading one) do not exist."""
    lead = c[0]
    if len(c) == 2:
        return [-c[1] / lead]
    reach = 1.0 + max(abs(v / lead) for v in c[1:])
    turning = [t for t in real_roots(derivative(c)) if -reach < t < reach]
    turning = sorted(set(turning))
    points = [-reach, *turning, reach]
    values = [value_at(c, s) for s in points]
    roots: list[float] = []
    for i, t in enumerate(turning, start=1):
        if abs(values[i]) <= rounding_at(c, t):  # touching zero here: a double root
            values[i] = 0.0
            roots += [t, t]
    for (lo, f_lo), (hi, f_hi) in itertools.pairwise(zip(points, values, strict=True)):
        if f_lo != 0.0 and f_hi != 0.0 and (f_lo < 0.0) != (f_hi < 0.0):
            roots.append(_bisect(c, lo, hi, f_lo))
    return sorted(r for r in roots if math.isfinite(r))
