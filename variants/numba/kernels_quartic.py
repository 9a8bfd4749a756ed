"""Kernel template: the torus's quartic (chapter 20 here, beyond the book) solved as ``robust``
solves it (``variants.robust.roots``), compiled: the roots of the derivative cut the line
into stretches where the polynomial is monotone, a stretch whose ends differ in sign holds
one root, refined by Newton's steps kept inside it (halving where a step would leave), and a
turning point where the polynomial is zero to within its evaluation's rounding is a double
root, listed twice. Every decision is relative to the sizes of the terms, so the answer does
not depend on the torus's scale or on how far the ray starts (``rtc stability``'s torus
rows, where the learner's closed form with its absolute 1e-9 loses or invents roots).

Operation by operation as ``robust``'s Python, so both give the same roots; in float64
whatever ``F`` is. Tuples instead of lists: nothing is allocated. A list of more than four
roots (rounding can make three turning points of a flat quartic "double roots") keeps its
four smallest.
"""

import math

from numba import njit

from variants.numba.kernels_geometry import INLINE

# ---- kernel template ----

# The solver's two outer steps are called, not inlined: a torus's roots take hundreds of
# nanoseconds, a call a few, and inlined into every caller of a shape's intersection the
# solver's code was compiled once per caller (the generic kernel's compile about doubled).
CALLED = {**INLINE, "forceinline": False}

Q_UNIT = 2.0**-53  # ``roots.UNIT``
Q_INF = math.inf
Q_STEPS = 2000  # a bound on a refinement's steps (halving a float64 bracket takes < 2100)


@njit(**INLINE)
def poly_at(c, s):
    """``roots.value_at``: the polynomial ``c`` (a tuple, highest power first) at ``s``."""
    total = 0.0
    for i in range(len(c)):
        total = total * s + c[i]
    return total


@njit(**INLINE)
def poly_rounding(c, s):
    """``roots.rounding_at``: a bound on the rounding error of ``poly_at(c, s)``."""
    size = 0.0
    power = 1.0
    for i in range(len(c) - 1, -1, -1):
        size += abs(c[i]) * power
        power *= abs(s)
    return 4 * len(c) * Q_UNIT * size


@njit(**INLINE)
def root_reach(c):
    """Fujiwara's bound on the roots' size, a little widened (``roots.real_roots``)."""
    n = len(c) - 1
    largest = abs(c[1] / c[0])  # k = 1 (r ** 1.0 is r); the coefficients are finite
    for k in range(2, n + 1):
        ratio = abs(c[k] / c[0])
        if k == n:
            ratio *= 0.5
        size = ratio ** (1.0 / k)
        if size > largest:
            largest = size
    return max(2.0 * largest * (1 + 2.0**-20), 2.0**-1000)


@njit(**INLINE)
def refine_root(c, slope, lo, hi, f_lo, f_hi):
    """``roots._refine``: the root in [lo, hi], whose ends' values differ in sign."""
    x = lo - f_lo * (hi - lo) / (f_hi - f_lo)
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    for _ in range(Q_STEPS):
        f = poly_at(c, x)
        if f == 0.0:
            return x
        if (f < 0.0) == (f_lo < 0.0):
            lo, f_lo = x, f
        else:
            hi = x
        gradient = poly_at(slope, x)
        step = x - f / gradient if gradient != 0.0 else math.nan
        if abs(step - x) <= 2.0 * Q_UNIT * abs(x):
            return step if lo <= step <= hi else x
        if not lo < step < hi:
            step = 0.5 * (lo + hi)
            if step in (lo, hi):
                return lo if abs(f_lo) <= abs(poly_at(c, hi)) else hi
        x = step
    return x


@njit(**INLINE)
def push_root(n, r0, r1, r2, r3, x):
    """The four smallest of the sorted roots (r0 ... r3, the first n of them) and a finite
    ``x``: (count, r0, r1, r2, r3); a non-finite x is left out."""
    if not math.isfinite(x):
        return n, r0, r1, r2, r3
    if x < r3 or n < 4:
        r3 = x
        if r3 < r2:
            r2, r3 = r3, r2
            if r2 < r1:
                r1, r2 = r2, r1
                if r1 < r0:
                    r0, r1 = r1, r0
    return min(n + 1, 4), r0, r1, r2, r3


@njit(**INLINE)
def quadratic_pair(a, b, c):
    """``roots._quadratic``: a x² + b x + c = 0 without cancellation: (count, r0, r1)."""
    discriminant = b * b - 4.0 * a * c
    if discriminant < 0.0:
        return 0, Q_INF, Q_INF
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    if q == 0.0:
        return 2, 0.0, 0.0
    x, y = q / a, c / q
    if y < x:
        return 2, y, x
    return 2, x, y


@njit(**CALLED)
def isolated_roots(c, slope, nt, t0, t1, t2, t3):
    """``roots.real_roots`` past its derivative: the real roots of ``c`` between its
    turning points (the first ``nt`` of t0 ... t3, increasing; the first three distinct
    ones inside the reach are used): (count, r0 ... r3)."""
    reach = root_reach(c)
    m = 0  # the turning points inside the reach, without repeats
    u0, u1, u2 = Q_INF, Q_INF, Q_INF
    for i in range(nt):
        t = t0 if i == 0 else (t1 if i == 1 else (t2 if i == 2 else t3))
        if m < 3 and -reach < t < reach and (m == 0 or t != (u0 if m == 1 else u1)):
            if m == 0:
                u0 = t
            elif m == 1:
                u1 = t
            else:
                u2 = t
            m += 1
    points = (-reach, u0, u1, u2, reach) if m == 3 else (
        (-reach, u0, u1, reach, Q_INF) if m == 2 else (
            (-reach, u0, reach, Q_INF, Q_INF) if m == 1 else (-reach, reach, Q_INF, Q_INF, Q_INF)
        )
    )  # fmt: skip
    v0 = poly_at(c, points[0])
    v1 = poly_at(c, points[1])
    v2 = poly_at(c, points[2])
    v3 = poly_at(c, points[3])
    v4 = poly_at(c, points[4])
    values = (v0, v1, v2, v3, v4)
    n, r0, r1, r2, r3 = 0, Q_INF, Q_INF, Q_INF, Q_INF
    double = (False, False, False, False, False)
    for i in range(1, m + 1):
        if abs(values[i]) <= poly_rounding(c, points[i]):  # touching zero: a double root
            double = (
                double[0], double[1] or i == 1, double[2] or i == 2, double[3] or i == 3, False
            )  # fmt: skip
            n, r0, r1, r2, r3 = push_root(n, r0, r1, r2, r3, points[i])
            n, r0, r1, r2, r3 = push_root(n, r0, r1, r2, r3, points[i])
    for i in range(m + 1):
        lo, hi, f_lo, f_hi = points[i], points[i + 1], values[i], values[i + 1]
        if double[i] or double[i + 1] or f_lo == 0.0 or f_hi == 0.0:
            continue
        if (f_lo < 0.0) != (f_hi < 0.0):
            x = refine_root(c, slope, lo, hi, f_lo, f_hi)
            n, r0, r1, r2, r3 = push_root(n, r0, r1, r2, r3, x)
    return n, r0, r1, r2, r3


@njit(**CALLED)
def quartic_real_roots(a, b, c, d, e):
    """``roots.real_roots`` of a x⁴ + b x³ + c x² + d x + e (a != 0): (count, r0, r1, r2,
    r3), increasing, a double root twice; the cubic's turning points from its derivative's
    quadratic, the quartic's from the cubic."""
    quartic = (a, b, c, d, e)
    cubic = (4.0 * a, 3.0 * b, 2.0 * c, d)
    quadratic = (3.0 * cubic[0], 2.0 * cubic[1], cubic[2])
    nq, q0, q1 = quadratic_pair(quadratic[0], quadratic[1], quadratic[2])
    nc, c0, c1, c2, c3 = isolated_roots(cubic, quadratic, nq, q0, q1, Q_INF, Q_INF)
    return isolated_roots(quartic, cubic, nc, c0, c1, c2, c3)
