"""The torus's quartic over arrays of rays (chapter 20 here, beyond the book), solved as
``robust`` solves it (``variants.robust.roots``): the roots of the derivative cut each ray's
line into stretches where the polynomial is monotone, a stretch whose ends differ in sign
holds one root, refined by Newton's steps kept inside it (halving where a step would leave),
and a turning point where the polynomial is zero to within its evaluation's rounding is a
double root, listed twice. Every decision is relative to the sizes of the terms: the answer
does not depend on the torus's scale or on how far the ray starts (``rtc stability``'s
torus rows, where the learner's closed form with its absolute 1e-9 loses or invents roots).

Element by element the same operations as ``robust``'s Python, so both give the same roots.
A polynomial is a list of coefficient arrays, highest power first; a list of roots is a
list of arrays, increasing, ``inf`` where a ray has fewer (at most four are kept: rounding
can make three turning points of a flat quartic "double roots").
"""

from __future__ import annotations

from typing import Any

import numpy as np

INF = np.inf
UNIT = 2.0**-53  # ``roots.UNIT``
STEPS = 2000  # a bound on a refinement's steps (halving a float64 bracket takes < 2100)
KEPT = 4


def value_at(c: list[Any], s: Any) -> Any:
    """``roots.value_at``: Horner's scheme."""
    total = np.zeros_like(s)
    for coefficient in c:
        total = total * s + coefficient
    return total


def rounding_at(c: list[Any], s: Any) -> Any:
    """``roots.rounding_at``: a bound on the rounding error of ``value_at(c, s)``."""
    size, power = np.zeros_like(s), np.ones_like(s)
    for coefficient in reversed(c):
        size = size + np.abs(coefficient) * power
        power = power * np.abs(s)
    return 4 * len(c) * UNIT * size


def reach_of(c: list[Any]) -> Any:
    """Fujiwara's bound on the roots' size, a little widened (``roots.real_roots``)."""
    n = len(c) - 1
    largest = np.abs(c[1] / c[0])  # k = 1
    for k in range(2, n + 1):
        ratio = np.abs(c[k] / c[0])
        if k == n:
            ratio = ratio * 0.5
        largest = np.maximum(largest, ratio ** (1.0 / k))
    return np.maximum(2.0 * largest * (1 + 2.0**-20), 2.0**-1000)


def derivative(c: list[Any]) -> list[Any]:
    n = len(c) - 1
    return [coefficient * (n - i) for i, coefficient in enumerate(c[:-1])]


def quadratic_roots(a: Any, b: Any, c: Any) -> list[Any]:
    """``roots._quadratic``: without cancellation; a double root twice; none: ``inf``."""
    discriminant = b * b - 4.0 * a * c
    none = discriminant < 0.0
    q = -0.5 * (b + np.copysign(np.sqrt(np.where(none, 0.0, discriminant)), b))
    zero = q == 0.0
    safe = np.where(zero, 1.0, q)
    x = np.where(zero, 0.0, q / a)
    y = np.where(zero, 0.0, c / safe)
    return [np.where(none, INF, np.minimum(x, y)), np.where(none, INF, np.maximum(x, y))]


def _refine(c: list[Any], slope: list[Any], lo: Any, hi: Any, f_lo: Any, f_hi: Any) -> Any:
    """``roots._refine`` for each bracket (``lo``, ``hi``: 1-d arrays whose ends' values
    ``f_lo``, ``f_hi`` differ in sign; ``c`` and ``slope``: coefficient arrays alike)."""
    x = lo - f_lo * (hi - lo) / (f_hi - f_lo)
    x = np.where((lo < x) & (x < hi), x, 0.5 * (lo + hi))
    result = np.full_like(lo, np.nan)
    left = np.arange(lo.size)  # the brackets still refined (indices into result)
    for _ in range(STEPS):
        if not left.size:
            break
        f = value_at(c, x)
        zero = f == 0.0
        same = (f < 0.0) == (f_lo < 0.0)
        lo, f_lo = np.where(same, x, lo), np.where(same, f, f_lo)
        hi = np.where(same, hi, x)
        gradient = value_at(slope, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(gradient != 0.0, x - f / np.where(gradient != 0.0, gradient, 1.0),
                            np.nan)  # fmt: skip
        converged = ~zero & (np.abs(step - x) <= 2.0 * UNIT * np.abs(x))
        inside = (lo <= step) & (step <= hi)
        outside = ~zero & ~converged & ~((lo < step) & (step < hi))
        middle = 0.5 * (lo + hi)
        stuck = outside & ((middle == lo) | (middle == hi))
        ends = np.where(np.abs(f_lo) <= np.abs(value_at(c, hi)), lo, hi)
        done = zero | converged | stuck
        result[left] = np.where(zero, x, np.where(converged, np.where(inside, step, x), ends))
        x = np.where(outside, middle, step)
        keep = ~done
        left, x, lo, hi, f_lo = left[keep], x[keep], lo[keep], hi[keep], f_lo[keep]
        c, slope = [v[keep] for v in c], [v[keep] for v in slope]
    result[left] = x
    return result


def _kept(candidates: list[Any]) -> list[Any]:
    """The ``KEPT`` smallest finite candidates of each ray, increasing (``inf``: none)."""
    stacked = np.sort(np.where(np.isfinite(np.stack(candidates)), np.stack(candidates), INF), 0)
    rows = list(stacked[:KEPT])
    while len(rows) < KEPT:
        rows.append(np.full_like(stacked[0], INF))
    return rows


def isolated_roots(c: list[Any], slope: list[Any], turning: list[Any]) -> list[Any]:
    """``roots.real_roots`` past its derivative: the real roots of ``c`` (coefficient arrays
    of one shape) between its turning points (``turning``: increasing, ``inf``: none; the
    first deg - 1 distinct ones inside the reach are used)."""
    reach = reach_of(c)
    inside = [(-reach < t) & (t < reach) for t in turning]
    distinct = [inside[0], *(inside[i] & ~(inside[i - 1] & (turning[i] == turning[i - 1]))
                             for i in range(1, len(turning)))]  # fmt: skip
    kept = [np.where(ok, t, INF) for ok, t in zip(distinct, turning, strict=True)]
    keys = np.sort(np.stack(kept), axis=0)
    keys = keys[: len(c) - 2]  # a quartic has at most three turning points
    valid = [k < INF for k in keys]
    points = [-reach, *(np.where(ok, k, reach) for ok, k in zip(valid, keys, strict=True)), reach]
    values = [value_at(c, p) for p in points]
    candidates = []
    for i, ok in enumerate(valid, start=1):
        touching = ok & (np.abs(values[i]) <= rounding_at(c, points[i]))
        values[i] = np.where(touching, 0.0, values[i])
        candidates += [np.where(touching, points[i], INF)] * 2
    for i in range(len(points) - 1):
        f_lo, f_hi = values[i], values[i + 1]
        crossing = (f_lo != 0.0) & (f_hi != 0.0) & ((f_lo < 0.0) != (f_hi < 0.0))
        where = np.nonzero(crossing)
        root = np.full(reach.shape, INF)
        if where[0].size:
            root[where] = _refine(
                [v[where] for v in c], [v[where] for v in slope],
                points[i][where], points[i + 1][where], f_lo[where], f_hi[where],
            )  # fmt: skip
        candidates.append(root)
    return _kept(candidates)


def quartic_roots(c: list[Any]) -> list[Any]:
    """The real roots of the quartics ``c`` (five coefficient arrays of one shape, the first
    never 0), as ``roots.real_roots`` finds them: four arrays, increasing, ``inf``: none."""
    cubic = derivative(c)
    quadratic = derivative(cubic)
    turning = quadratic_roots(*quadratic)
    return isolated_roots(c, cubic, isolated_roots(cubic, quadratic, turning))
