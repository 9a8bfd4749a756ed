"""Kernel template: the torus's quartic (chapter 20 here, beyond the book), solved fast and
right. First in closed form (Ferrari's method, ``certified_roots``), each root polished by
Newton's steps and proved by a sign change across a narrow bracket, and the set proved
complete (four proved roots; two and the other pair certainly complex by Vieta; none and the
quartic certainly positive, Ferrari's factors outweighing what is left): every bound is
relative to the sizes of the terms, so the proof holds at every scale. Where it fails (a
ray grazing the tube, a double root, a thin hole) the roots are found as ``robust`` finds
them (``variants.robust.roots``), compiled: the roots of the derivative cut the line into
stretches where the polynomial is monotone, a stretch whose ends differ in sign holds one
root, refined by Newton's steps kept inside it (halving where a step would leave), and a
turning point where the polynomial is zero to within its evaluation's rounding is a double
root, listed twice (``rtc stability``'s torus rows, where the learner's closed form with its
absolute 1e-9 loses or invents roots).

The isolation is operation by operation ``robust``'s Python, so both give the same roots; a
proved closed-form root is within 4 units in the last place of robust's, or within the
quartic's rounding at it over its slope where Newton's steps end in that noise. In float64
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


# ---- the certified closed form: Ferrari's roots, each proved, or the isolation above ----

C_WIDTH = 2.0**-30  # a root's proving bracket: this much of the largest root's size around it
C_SLACK = 16 * Q_UNIT  # a computed sum's rounding, relative to its terms' sizes (generous)
C_STEPS = 8  # Newton's steps from a closed-form root before it counts as unproved


@njit(**INLINE)
def resolvent_root(p, q, r):
    """The largest real root of Ferrari's resolvent cubic (2z - p)(z² - r) = q²/4 of the
    depressed quartic y⁴ + p y² + q y + r: Cardano's method (the trigonometric form for
    three real roots), then one Newton step on the cubic."""
    big_a = -0.5 * p
    big_c = 0.5 * p * r - 0.125 * q * q
    square_a = big_a * big_a
    pp = (-r - square_a / 3.0) / 3.0
    qq = 0.5 * (2.0 / 27.0 * big_a * square_a + big_a * r / 3.0 + big_c)
    cube_p = pp * pp * pp
    discriminant = qq * qq + cube_p
    if discriminant < 0.0:
        phi = math.acos(max(-1.0, min(1.0, -qq / math.sqrt(-cube_p)))) / 3.0
        z = 2.0 * math.sqrt(-pp) * math.cos(phi)
    else:  # one real root u + v, u³ and v³ the roots of w² + 2 qq w - pp³, u v = -pp
        u = -math.copysign((abs(qq) + math.sqrt(discriminant)) ** (1.0 / 3.0), qq)
        z = u - pp / u if u != 0.0 else 0.0
    z -= big_a / 3.0
    value = ((z + big_a) * z - r) * z + big_c
    slope = (3.0 * z + 2.0 * big_a) * z - r
    if slope != 0.0:
        z -= value / slope
    return z


@njit(**INLINE)
def polished(c, slope, x):
    """Newton's steps on ``c`` from ``x`` until one moves it less than two units in the last
    place (``refine_root``'s test), or until the steps stop shrinking where ``c`` is zero to
    within its evaluation's rounding (they are that rounding's noise): the root, or NaN if
    neither happens within C_STEPS."""
    last = Q_INF
    for _ in range(C_STEPS):
        gradient = poly_at(slope, x)
        value = poly_at(c, x)
        if gradient == 0.0:
            return math.nan
        step = x - value / gradient
        moved = abs(step - x)
        if moved <= 2.0 * Q_UNIT * abs(x):
            return step
        if moved >= last and abs(value) <= poly_rounding(c, x):
            return x
        x, last = step, moved
    return math.nan


@njit(**INLINE)
def proved(c, x, width):
    """Whether ``c`` certainly changes sign across [x - width, x + width]: its values at the
    ends differ in sign by more than their evaluation's rounding (a root inside)."""
    lo, hi = x - width, x + width
    f_lo, f_hi = poly_at(c, lo), poly_at(c, hi)
    rounding = poly_rounding(c, max(abs(lo), abs(hi)))  # the larger end's: the larger bound
    return (
        lo < x < hi and (f_lo < 0.0) != (f_hi < 0.0)
        and abs(f_lo) > rounding and abs(f_hi) > rounding
    )  # fmt: skip


@njit(**INLINE)
def no_real_roots(q, z, v, w, low_p, low_r):
    """Whether y⁴ + p' y² + q y + r' > 0 for every y and every p' >= low_p, r' >= low_r
    (Ferrari's factors, both without real roots, outweigh what the inexact z leaves):
    y⁴ + p' y² + q y + r' = F1 F2 + c2 y² + c1 y + c0, with F1, F2 = y² ∓ v y + z ± w, is an
    identity for any z, v, w; each F is at least k = z - |w| - v²/4, so F1 F2 >= k (y² + z)
    once k > 0, and the quadratic (k + c2) y² + c1 y + (k z + c0) must have no real root.
    Every computed quantity is taken at its worst by C_SLACK of its terms."""
    vv = v * v
    k = z - abs(w) - 0.25 * vv
    k -= C_SLACK * (abs(z) + abs(w) + 0.25 * vv)
    if not k > 0.0:
        return False
    c2 = vv - 2.0 * z + low_p
    c2 -= C_SLACK * (vv + 2.0 * abs(z) + abs(low_p))
    c1 = abs(q - 2.0 * v * w) + C_SLACK * (abs(q) + 2.0 * abs(v * w))
    c0 = w * w - z * z + low_r
    c0 -= C_SLACK * (w * w + z * z + abs(low_r))
    quadratic = k + c2 - C_SLACK * (k + abs(c2))
    constant = k * z + c0 - C_SLACK * (k * z + abs(c0))
    return (
        quadratic > 0.0 and constant > 0.0
        and c1 * c1 * (1.0 + C_SLACK) < 4.0 * quadratic * constant * (1.0 - C_SLACK)
    )  # fmt: skip


@njit(**INLINE)
def pair_is_complex(big_b, big_c, x0, x1, w0, w1):
    """Whether the quartic t⁴ + B t³ + C t² + ... whose roots include one within w0 of x0
    and another within w1 of x1 has its other two complex: by Vieta, their discriminant is
    B² - 2 B S - 3 S² + 4 P - 4 C (S, P: the sum and product of the two known), which must
    be negative by more than the known roots' and the coefficients' uncertainty."""
    s, product = x0 + x1, x0 * x1
    width = w0 + w1
    discriminant = big_b * big_b - 2.0 * big_b * s - 3.0 * s * s + 4.0 * product - 4.0 * big_c
    bound = C_SLACK * (
        big_b * big_b + 2.0 * abs(big_b * s) + 3.0 * s * s + 4.0 * abs(product)
        + 4.0 * abs(big_c) + 4.0 * abs(big_b) * (abs(big_b) + abs(s))
    ) + (2.0 * abs(big_b) + 6.0 * abs(s) + 3.0 * width) * width + 4.0 * (
        abs(x0) * w1 + abs(x1) * w0 + w0 * w1
    )  # fmt: skip
    return discriminant + bound < 0.0


@njit(**INLINE)
def root_bound(big_b, big_c, big_d, big_e):
    """A bound on the size of the roots of t⁴ + B t³ + C t² + D t + E (Fujiwara's, with the
    cube root replaced by the larger (|D| / L² + 2 L) / 3, L > 0; a little widened)."""
    size = max(abs(big_b), math.sqrt(abs(big_c)), math.sqrt(math.sqrt(0.5 * abs(big_e))))
    if size > 0.0:
        size = max(size, (abs(big_d) / (size * size) + 2.0 * size) / 3.0)
    else:
        size = abs(big_d) ** (1.0 / 3.0)
    return 2.0 * size * (1 + 2.0**-20)


@njit(**INLINE)
def certainly_positive(big_b, big_c, big_d, big_e, s, p, q, r, z, v, w):
    """Whether t⁴ + B t³ + C t² + D t + E has no real root, shown on its depressed form
    y⁴ + p y² + q y + r (y = t + s, computed) by ``no_real_roots``: the roots lie within
    ``size`` of y = 0 (``root_bound``), and there the exact depressed quartic is at least
    y⁴ + low_p y² + q y + low_r, the rounding of p, q and r taken at its worst, the y³ term
    the division by a leaves (at most C_SLACK |B|) at most that times size y², and q's
    error dq |y| at most dq (y² / size + size) / 2."""
    size = root_bound(big_b, big_c, big_d, big_e) + abs(s)
    if not size > 0.0:
        return False
    s2 = s * s
    dp = C_SLACK * (abs(big_c) + 12.0 * s2)
    dq = C_SLACK * (abs(big_d) + 2.0 * abs(big_c * s) + 12.0 * abs(s2 * s))
    dr = C_SLACK * (abs(big_e) + abs(big_d * s) + abs(big_c) * s2 + 4.0 * s2 * s2)
    low_p = p - dp - C_SLACK * abs(big_b) * size - 0.5 * dq / size
    low_r = r - dr - 0.5 * dq * size
    return no_real_roots(q, z, v, w, low_p, low_r)


@njit(**CALLED)
def certified_roots(a, b, c, d, e):
    """The real roots of a t⁴ + b t³ + c t² + d t + e from Ferrari's closed form, each
    polished by Newton's steps and proved by a sign change across a bracket of C_WIDTH of
    the largest root's size, the set proved complete (four proved roots; two and the
    other pair's Vieta discriminant certainly negative; none and the quartic certainly
    positive): (proved, count, r0, r1, r2, r3), increasing; not proved: count 0."""
    quartic = (a, b, c, d, e)
    cubic = (4.0 * a, 3.0 * b, 2.0 * c, d)
    big_b, big_c, big_d, big_e = b / a, c / a, d / a, e / a
    s = 0.25 * big_b  # t = y - s: y⁴ + p y² + q y + r
    s2 = s * s
    p = big_c - 6.0 * s2
    q = big_d - 2.0 * big_c * s + 8.0 * s2 * s
    r = big_e - big_d * s + big_c * s2 - 3.0 * s2 * s2
    z = resolvent_root(p, q, r)
    vv = 2.0 * z - p
    if not (vv > 0.0 and math.isfinite(vv)):
        return False, 0, Q_INF, Q_INF, Q_INF, Q_INF
    v = math.sqrt(vv)
    w = q / (2.0 * v)
    n0, x0, x1 = quadratic_pair(1.0, -v, z + w)
    n1, x2, x3 = quadratic_pair(1.0, v, z - w)
    if n0 + n1 == 0:
        done = certainly_positive(big_b, big_c, big_d, big_e, s, p, q, r, z, v, w)
        return done, 0, Q_INF, Q_INF, Q_INF, Q_INF
    n, t0, t1, t2, t3 = 0, Q_INF, Q_INF, Q_INF, Q_INF
    seeds = (x0, x1, x2, x3)
    for i in range(4):
        if (i < 2 and n0 == 2) or (i >= 2 and n1 == 2):
            n, t0, t1, t2, t3 = push_root(n, t0, t1, t2, t3, polished(quartic, cubic, seeds[i] - s))
    if n != n0 + n1:
        return False, 0, Q_INF, Q_INF, Q_INF, Q_INF
    largest = max(abs(t0), abs(t1 if n > 1 else t0), abs(t2 if n > 2 else t0),
                  abs(t3 if n > 3 else t0))  # fmt: skip
    roots = (t0, t1, t2, t3)
    last = -Q_INF
    for i in range(n):
        width = C_WIDTH * (abs(roots[i]) + largest)
        if not (roots[i] - width > last and proved(quartic, roots[i], width)):
            return False, 0, Q_INF, Q_INF, Q_INF, Q_INF
        last = roots[i] + width
    if n == 2 and not pair_is_complex(
        big_b, big_c, t0, t1, C_WIDTH * (abs(t0) + largest), C_WIDTH * (abs(t1) + largest)
    ):  # fmt: skip
        return False, 0, Q_INF, Q_INF, Q_INF, Q_INF
    return True, n, t0, t1, t2, t3


@njit(**CALLED)
def quartic_roots(a, b, c, d, e):
    """The real roots of a x⁴ + b x³ + c x² + d x + e (a != 0), as ``quartic_real_roots``
    finds them: the certified closed form (``certified_roots``) where it proves its
    answer, the isolation where it does not (a grazing ray, a thin hole, a double root)."""
    done, n, r0, r1, r2, r3 = certified_roots(a, b, c, d, e)
    if done:
        return n, r0, r1, r2, r3
    return quartic_real_roots(a, b, c, d, e)
