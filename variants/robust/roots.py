"""Real roots of a polynomial without a closed form or a fixed tolerance: robust's way to the
torus's quartic (chapter 20 here, beyond the book).

The roots of the derivative (found the same way, down to a quadratic, solved in the form
that does not cancel) cut the real line into stretches where the polynomial is monotone; a
stretch whose ends differ in sign holds exactly one root, found by Newton's method kept
inside the stretch (a step that would leave it bisects instead: rtsafe) until a step moves
less than a unit in the last place. A turning point where the polynomial is zero to within
the rounding of its evaluation is a double root, listed twice (a ray grazing the tube).
Every decision is relative to the sizes of the terms, so a polynomial scaled by 1e-12 or
1e12 has the same roots.
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


def _refine(
    c: Sequence[float], slope: Sequence[float], lo: float, hi: float, f_lo: float, f_hi: float
) -> float:
    """The root in [lo, hi] (``f_lo`` and ``f_hi``, the values at the ends, of opposite
    signs): Newton's steps from where the chord between the ends crosses zero, until a step
    moves less than two units in the last place; a step that would leave the shrinking
    bracket is replaced by halving it."""
    x = lo - f_lo * (hi - lo) / (f_hi - f_lo)
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    while True:
        f = value_at(c, x)
        if f == 0.0:
            return x
        if (f < 0.0) == (f_lo < 0.0):
            lo, f_lo = x, f
        else:
            hi = x
        gradient = value_at(slope, x)
        step = x - f / gradient if gradient != 0.0 else math.nan
        if abs(step - x) <= 2.0 * UNIT * abs(x):  # converged (never for NaN)
            return step if lo <= step <= hi else x
        if not lo < step < hi:  # NaN too
            step = 0.5 * (lo + hi)
            if step in (lo, hi):  # the bracket is two neighbouring floats
                return lo if abs(f_lo) <= abs(value_at(c, hi)) else hi
        x = step


def _quadratic(a: float, b: float, c: float) -> list[float]:
    """a x² + b x + c = 0 without cancellation (the larger root from the formula, the other
    from the product of the roots, c / a); a double root twice."""
    discriminant = b * b - 4.0 * a * c
    if discriminant < 0.0:
        return []
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    if q == 0.0:  # b = 0 and c = 0
        return [0.0, 0.0]
    return sorted((q / a, c / q))


def derivative(c: Sequence[float]) -> list[float]:
    n = len(c) - 1
    return [coefficient * (n - i) for i, coefficient in enumerate(c[:-1])]


def real_roots(c: Sequence[float]) -> list[float]:
    """The real roots of ``c`` (highest power first, leading coefficient not 0), increasing,
    a double root twice. No root is further from 0 than Fujiwara's bound (twice the largest
    of |a_(n-k) / a_n|^(1/k), the constant term's halved), a little widened."""
    lead = c[0]
    if len(c) == 2:
        return [-c[1] / lead]
    if len(c) == 3:
        return _quadratic(*c)
    # Fujiwara's bound on the roots' size
    ratios = [abs(v / lead) for v in c[1:]]
    ratios[-1] *= 0.5
    reach = 2.0 * max(r ** (1.0 / k) for k, r in enumerate(ratios, start=1)) * (1 + 2**-20)
    reach = max(reach, 2.0**-1000)
    slope = derivative(c)
    turning = [t for t in real_roots(slope) if -reach < t < reach]
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
            roots.append(_refine(c, slope, lo, hi, f_lo, f_hi))
    return sorted(r for r in roots if math.isfinite(r))
