"""Kernel template, part 1: transforms, intersections and normals of every shape kind
(chapters 5, 6, 9, 12, 13 and 15), and bounding boxes (chapter 14).

The object-space tests repeat the reference's arithmetic operation by operation. One shape
takes a shortcut: a sphere whose transform is a similarity (``pack``: rotation, uniform
scale, translation) is a world-space ball, tested without the object-space transform, with
the quadratic solved without cancellation (one root as q / a, the other as c / q), and its
normal taken from its centre. Its t and normal equal the reference's up to rounding (about
1e-15 relative), so a pixel can change only where a ray grazes an edge or a shadow boundary
exactly. Everything is scalar: vectors are passed and returned as separate x, y, z values,
so nothing allocates. Literals are wrapped in ``F`` so the float32 option computes in
float32 throughout.
"""

# ruff: noqa: F401
import math
from typing import Any

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_CONE,
    HAS_CUBE,
    HAS_CYLINDER,
    HAS_PLANE,
    HAS_SMOOTH_TRIANGLE,
    HAS_SPHERE,
    HAS_TEST_SHAPE,
    HAS_TORUS,
    HAS_TRIANGLE,
    INLINE_HELPERS,
    F,
)
from variants.numba.layout import (
    BOUND,
    CLOSED,
    INV,
    K_CONE,
    K_CUBE,
    K_CYLINDER,
    K_PLANE,
    K_SMOOTH_TRIANGLE,
    K_SPHERE,
    K_TEST,
    K_TORUS,
    K_TRIANGLE,
    KIND,
    MAXIMUM,
    MINIMUM,
    NBOX,
    NF,
    NI,
    NRM,
    NTG,
    NTN,
    SPH_CENTER,
    SPH_INV_R,
    SPH_R2,
    TG_E1,
    TG_E2,
    TG_NORMAL,
    TG_P1,
    TN_FIRST,
    TORUS_MAJOR,
    TORUS_MINOR,
    TRI_E1,
    TRI_E2,
    TRI_FIRST,
    TRI_N1,
    TRI_N2,
    TRI_N3,
    TRI_NORMAL,
    TRI_P1,
    WORLD_SPHERE,
)

# ---- kernel template ----

# Helpers: compiled once, then inlined by LLVM into every caller (numba's own inlining,
# inline="always", copies the IR into each caller before typing: several times slower to
# compile). Without the numba runtime (_nrt=False) they do no reference counting of the
# arrays they are passed, and they allocate nothing. ``pf``, ``pi`` ... are flat (see
# ``layout``): numpy arrays in the book-API kernels, raw pointers in the render.
INLINE: dict[str, Any] = {
    "forceinline": INLINE_HELPERS,
    "_nrt": False,
    "fastmath": FASTMATH,
    "error_model": "numpy",
}
INF = F(np.inf)
ZERO = F(0.0)
ONE = F(1.0)
TWO = F(2.0)
THIRD = F(1.0 / 3.0)
PI = F(math.pi)
# the torus's quartic is solved in float64 whatever F is (``torus_intersect``)
EQN_EPS = 1e-9  # ``raytracer.quartic.EQN_EPS``
D_INF, D_ZERO, D_ONE, D_TWO, D_THIRD, D_PI = np.inf, 0.0, 1.0, 2.0, 1.0 / 3.0, math.pi


@njit(**INLINE)
def to_object_point(pf, p, x, y, z):
    """Chapter 5: a world-space point in primitive p's object space (the composed inverse)."""
    m = p * NF + INV
    return (
        pf[m + 0] * x + pf[m + 1] * y + pf[m + 2] * z + pf[m + 3],
        pf[m + 4] * x + pf[m + 5] * y + pf[m + 6] * z + pf[m + 7],
        pf[m + 8] * x + pf[m + 9] * y + pf[m + 10] * z + pf[m + 11],
    )


@njit(**INLINE)
def to_object_vector(pf, p, x, y, z):
    """Chapter 5: a world-space direction in primitive p's object space."""
    m = p * NF + INV
    return (
        pf[m + 0] * x + pf[m + 1] * y + pf[m + 2] * z,
        pf[m + 4] * x + pf[m + 5] * y + pf[m + 6] * z,
        pf[m + 8] * x + pf[m + 9] * y + pf[m + 10] * z,
    )


@njit(**INLINE)
def normalized(x, y, z):
    """Chapter 1: (x, y, z) scaled to length 1 (times 1 / length: one division, not three)."""
    scale = ONE / math.sqrt(x * x + y * y + z * z)
    return x * scale, y * scale, z * scale


@njit(**INLINE)
def to_world_normal(pf, p, x, y, z):
    """Chapter 14: an object-space normal in world space (inverse transpose), normalized;
    a zero normal (a cone's tip) stays zero."""
    m = p * NF + NRM
    nx = pf[m + 0] * x + pf[m + 1] * y + pf[m + 2] * z
    ny = pf[m + 3] * x + pf[m + 4] * y + pf[m + 5] * z
    nz = pf[m + 6] * x + pf[m + 7] * y + pf[m + 8] * z
    if nx != ZERO or ny != ZERO or nz != ZERO:
        return normalized(nx, ny, nz)
    return nx, ny, nz


@njit(**INLINE)
def is_world_sphere(pi, p):
    """Is primitive p a sphere tested in world space (``pack``: its transform is a
    similarity)?"""
    return HAS_SPHERE and pi[p * NI + KIND] == K_SPHERE and pi[p * NI + WORLD_SPHERE] != 0


@njit(**INLINE)
def ball_terms(pf, p, ox, oy, oz, dx, dy, dz):
    """Chapter 5, in world space: with oc = origin - centre, the ray meets the ball where
    a t² + 2 hb t + cc = 0: returns (hb, cc) = (oc · direction, oc · oc - radius²)."""
    m = p * NF + SPH_CENTER
    cx = ox - pf[m]
    cy = oy - pf[m + 1]
    cz = oz - pf[m + 2]
    return cx * dx + cy * dy + cz * dz, cx * cx + cy * cy + cz * cz - pf[p * NF + SPH_R2]


@njit(**INLINE)
def ball_roots(hb, cc, a, discriminant):
    """The two roots of a t² + 2 hb t + cc = 0, smaller first, without cancellation: one is
    q / a, the other cc / q, with q = -(hb + sign(hb) sqrt(discriminant))."""
    root = math.sqrt(discriminant)
    q = -(hb + root) if hb >= ZERO else root - hb
    if q == ZERO:  # hb = 0 and a tangent line: both roots are 0
        return ZERO, ZERO
    first = q / a
    second = cc / q
    if first <= second:
        return first, second
    return second, first


@njit(**INLINE)
def ball_intersect(pf, p, ox, oy, oz, dx, dy, dz, a):
    """Chapter 5: a world-space ball's intersections (count, t1, t2), ``a`` = direction ·
    direction. The same t as the reference's object-space test up to rounding."""
    hb, cc = ball_terms(pf, p, ox, oy, oz, dx, dy, dz)
    discriminant = hb * hb - a * cc
    if discriminant < ZERO:
        return 0, INF, INF
    t0, t1 = ball_roots(hb, cc, a, discriminant)
    return 2, t0, t1


@njit(**INLINE)
def ball_first(hb, cc, a, tmax):
    """Chapter 5, for the hit and shadow rays: a ball's first intersection in [0, tmax),
    given its ``ball_terms``: (found, t, index in its list); t is its first t >= 0 (or INF)
    even when that is not below tmax, unless it is certainly beyond tmax. From outside
    (cc > 0) a ray moving away (hb >= 0) cannot hit; one moving closer hits first at
    cc / q (the smaller root), divided only when it may be nearer than tmax."""
    if cc > ZERO:
        if hb >= ZERO:
            return False, INF, 0
        discriminant = hb * hb - a * cc
        if discriminant < ZERO:
            return False, INF, 0
        q = math.sqrt(discriminant) - hb  # > 0
        if cc > tmax * q * F(1.000001):  # certainly t = cc / q > tmax
            return False, INF, 0
        t = cc / q
        return t < tmax, t, 0
    discriminant = hb * hb - a * cc
    if discriminant < ZERO:
        return False, INF, 0
    t0, t1 = ball_roots(hb, cc, a, discriminant)
    if t0 >= ZERO:
        return t0 < tmax, t0, 0
    if t1 >= ZERO:
        return t1 < tmax, t1, 1
    return False, INF, 0


@njit(**INLINE)
def ball_first_hit(pf, p, ox, oy, oz, dx, dy, dz, a, tmax):
    """``ball_first`` for primitive p, a world-space ball."""
    hb, cc = ball_terms(pf, p, ox, oy, oz, dx, dy, dz)
    return ball_first(hb, cc, a, tmax)


@njit(**INLINE)
def sphere_intersect(ox, oy, oz, dx, dy, dz):
    """Chapter 5: the unit sphere: (count, t1, t2)."""
    a = dx * dx + dy * dy + dz * dz
    b = TWO * (dx * ox + dy * oy + dz * oz)
    c = (ox * ox + oy * oy + oz * oz) - ONE
    discriminant = b * b - F(4.0) * a * c
    if discriminant < ZERO:
        return 0, INF, INF
    root = math.sqrt(discriminant)
    return 2, (-b - root) / (TWO * a), (-b + root) / (TWO * a)


@njit(**INLINE)
def plane_intersect(oy, dy, eps):
    """Chapter 9: the xz plane: (count, t)."""
    if abs(dy) < eps:
        return 0, INF
    return 1, -oy / dy


@njit(**INLINE)
def check_axis(origin, direction, eps):
    """Chapter 12: where the ray crosses the faces at -1 and 1 on one axis, nearest first."""
    tmin_numerator = -ONE - origin
    tmax_numerator = ONE - origin
    if abs(direction) >= eps:
        tmin = tmin_numerator / direction
        tmax = tmax_numerator / direction
    else:
        tmin = math.copysign(INF, tmin_numerator)
        tmax = math.copysign(INF, tmax_numerator)
    if tmin > tmax:
        return tmax, tmin
    return tmin, tmax


@njit(**INLINE)
def cube_intersect(ox, oy, oz, dx, dy, dz, eps):
    """Chapter 12: the slab test on the cube from -1 to 1: (count, tmin, tmax)."""
    xtmin, xtmax = check_axis(ox, dx, eps)
    ytmin, ytmax = check_axis(oy, dy, eps)
    ztmin, ztmax = check_axis(oz, dz, eps)
    tmin = max(xtmin, ytmin, ztmin)
    tmax = min(xtmax, ytmax, ztmax)
    if tmin > tmax:
        return 0, INF, INF
    return 2, tmin, tmax


@njit(**INLINE)
def cube_normal(x, y, z):
    """Chapter 12: along the axis of the largest coordinate (x, then y, wins a tie)."""
    ax = abs(x)
    ay = abs(y)
    az = abs(z)
    largest = max(ax, ay, az)
    if largest == ax:
        return x, ZERO, ZERO
    if largest == ay:
        return ZERO, y, ZERO
    return ZERO, ZERO, z


@njit(**INLINE)
def check_cap(ox, oz, dx, dz, t, radius):
    """Chapter 13: is the point at t within ``radius`` of the y axis?"""
    x = ox + t * dx
    z = oz + t * dz
    return x * x + z * z <= radius * radius


@njit(**INLINE)
def cylinder_intersect(pf, pi, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 13: the sides between minimum and maximum, then the caps when closed:
    (count, t0, t1, t2, t3)."""
    lo = pf[p * NF + MINIMUM]
    hi = pf[p * NF + MAXIMUM]
    n = 0
    t0 = INF
    t1 = INF
    t2 = INF
    t3 = INF
    a = dx * dx + dz * dz
    if not abs(a) < eps:
        b = TWO * ox * dx + TWO * oz * dz
        c = ox * ox + oz * oz - ONE
        discriminant = b * b - F(4.0) * a * c
        if discriminant < ZERO:
            return 0, t0, t1, t2, t3
        root = math.sqrt(discriminant)
        s0 = (-b - root) / (TWO * a)
        s1 = (-b + root) / (TWO * a)
        if s0 > s1:
            s0, s1 = s1, s0
        y0 = oy + s0 * dy
        if lo < y0 and y0 < hi:
            t0 = s0
            n = 1
        y1 = oy + s1 * dy
        if lo < y1 and y1 < hi:
            if n == 0:
                t0 = s1
            else:
                t1 = s1
            n += 1
    if pi[p * NI + CLOSED] != 0 and not abs(dy) < eps:
        for cap in (lo, hi):
            t = (cap - oy) / dy
            if check_cap(ox, oz, dx, dz, t, ONE):
                if n == 0:
                    t0 = t
                elif n == 1:
                    t1 = t
                elif n == 2:
                    t2 = t
                else:
                    t3 = t
                n += 1
    return n, t0, t1, t2, t3


@njit(**INLINE)
def cylinder_normal(pf, p, x, y, z, eps):
    """Chapter 13: the caps' normals point along y, the side's away from the axis."""
    distance = x * x + z * z
    if distance < ONE and y >= pf[p * NF + MAXIMUM] - eps:
        return ZERO, ONE, ZERO
    if distance < ONE and y <= pf[p * NF + MINIMUM] + eps:
        return ZERO, -ONE, ZERO
    return x, ZERO, z


@njit(**INLINE)
def cone_intersect(pf, pi, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 13: the double cone x² + z² = y² between minimum and maximum (one crossing
    when the ray runs parallel to one half), then the caps: (count, t0, t1, t2, t3)."""
    lo = pf[p * NF + MINIMUM]
    hi = pf[p * NF + MAXIMUM]
    n = 0
    t0 = INF
    t1 = INF
    t2 = INF
    t3 = INF
    a = dx * dx - dy * dy + dz * dz
    b = TWO * (ox * dx - oy * dy + oz * dz)
    c = ox * ox - oy * oy + oz * oz
    sides = 0
    s0 = INF
    s1 = INF
    if abs(a) < eps:
        if abs(b) >= eps:
            s0 = -c / (TWO * b)
            sides = 1
    else:
        discriminant = b * b - F(4.0) * a * c
        if discriminant >= ZERO:
            root = math.sqrt(discriminant)
            s0 = (-b - root) / (TWO * a)
            s1 = (-b + root) / (TWO * a)
            if s0 > s1:
                s0, s1 = s1, s0
            sides = 2
    for side in range(sides):
        s = s0 if side == 0 else s1
        y = oy + s * dy
        if lo < y and y < hi:
            if n == 0:
                t0 = s
            else:
                t1 = s
            n += 1
    if pi[p * NI + CLOSED] != 0 and not abs(dy) < eps:
        for cap in (lo, hi):
            t = (cap - oy) / dy
            if check_cap(ox, oz, dx, dz, t, abs(cap)):
                if n == 0:
                    t0 = t
                elif n == 1:
                    t1 = t
                elif n == 2:
                    t2 = t
                else:
                    t3 = t
                n += 1
    return n, t0, t1, t2, t3


@njit(**INLINE)
def cone_normal(pf, p, x, y, z, eps):
    """Chapter 13: the caps' normals point along y; the sides' slope outwards (zero at the
    tip)."""
    distance = x * x + z * z
    hi = pf[p * NF + MAXIMUM]
    lo = pf[p * NF + MINIMUM]
    if distance < hi * hi and y >= hi - eps:
        return ZERO, ONE, ZERO
    if distance < lo * lo and y <= lo + eps:
        return ZERO, -ONE, ZERO
    side = math.sqrt(distance)
    if y > ZERO:
        side = -side
    return x, side, z


@njit(**INLINE)
def triangle_intersect(pf, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 15: Möller-Trumbore for a triangle of its own row: (count, t, u, v)."""
    m = p * NF
    return moller_trumbore(pf, m + TRI_P1, m + TRI_E1, m + TRI_E2, ox, oy, oz, dx, dy, dz, eps)


@njit(**INLINE)
def compact_intersect(tg, t, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 15: Möller-Trumbore for compact triangle t (``tg``): (count, t, u, v)."""
    m = t * NTG
    return moller_trumbore(tg, m + TG_P1, m + TG_E1, m + TG_E2, ox, oy, oz, dx, dy, dz, eps)


@njit(**INLINE)
def moller_trumbore(table, at_p1, at_e1, at_e2, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 15's intersection of a triangle whose p1, e1 and e2 are in ``table`` at
    those offsets: (count, t, u, v), the reference's arithmetic step by step."""
    e1x = table[at_e1]
    e1y = table[at_e1 + 1]
    e1z = table[at_e1 + 2]
    e2x = table[at_e2]
    e2y = table[at_e2 + 1]
    e2z = table[at_e2 + 2]
    cx = dy * e2z - dz * e2y
    cy = dz * e2x - dx * e2z
    cz = dx * e2y - dy * e2x
    det = e1x * cx + e1y * cy + e1z * cz
    if abs(det) < eps:
        return 0, INF, ZERO, ZERO
    f = ONE / det
    px = ox - table[at_p1]
    py = oy - table[at_p1 + 1]
    pz = oz - table[at_p1 + 2]
    u = f * (px * cx + py * cy + pz * cz)
    if u < ZERO or u > ONE:
        return 0, INF, ZERO, ZERO
    qx = py * e1z - pz * e1y
    qy = pz * e1x - px * e1z
    qz = px * e1y - py * e1x
    v = f * (dx * qx + dy * qy + dz * qz)
    if v < ZERO or u + v > ONE:
        return 0, INF, ZERO, ZERO
    return 1, f * (e2x * qx + e2y * qy + e2z * qz), u, v


@njit(**INLINE)
def smooth_normal(table, n1, n2, n3, u, v):
    """Chapter 15: the corner normals (in ``table`` at offsets n1, n2, n3) blended by the
    hit's u and v."""
    w = ONE - u - v
    return (
        table[n2] * u + table[n3] * v + table[n1] * w,
        table[n2 + 1] * u + table[n3 + 1] * v + table[n1 + 1] * w,
        table[n2 + 2] * u + table[n3 + 2] * v + table[n1 + 2] * w,
    )


@njit(**INLINE)
def compact_first_hit(pf, p, tg, t, ox, oy, oz, dx, dy, dz, eps, tmax):
    """``first_hit_in`` for compact triangle t of run row p: (found, t, u, v)."""
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    n, hit, u, v = compact_intersect(tg, t, lox, loy, loz, ldx, ldy, ldz, eps)
    best = hit if n > 0 and hit >= ZERO else INF
    return best < tmax, best, u, v


@njit(**INLINE)
def compact_all(pf, p, tg, t, ox, oy, oz, dx, dy, dz, eps):
    """``intersect_prim`` (every t) for compact triangle t of run row p: (count, t)."""
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    n, hit, _, _ = compact_intersect(tg, t, lox, loy, loz, ldx, ldy, ldz, eps)
    return n, hit


@njit(**INLINE)
def is_zero(x):
    """``raytracer.quartic.is_zero``: within EQN_EPS of zero."""
    return -EQN_EPS < x < EQN_EPS


@njit(**INLINE)
def cube_root(x):
    """The real cube root, sign kept (``raytracer.quartic.cube_root``)."""
    return math.copysign(abs(x) ** D_THIRD, x)


@njit(**INLINE)
def sort4(n, a, b, c, d):
    """The first n of (a, b, c, d) in increasing order (the rest infinite)."""
    if n < 4:
        d = D_INF
    if n < 3:
        c = D_INF
    if n < 2:
        b = D_INF
    if n < 1:
        a = D_INF
    if a > b:
        a, b = b, a
    if c > d:
        c, d = d, c
    if a > c:
        a, c = c, a
    if b > d:
        b, d = d, b
    if b > c:
        b, c = c, b
    return a, b, c, d


@njit(**INLINE)
def quadratic_roots(b, c):
    """``raytracer.quartic.solve_quadratic(1, b, c)``: (count, r0, r1)."""
    p = b / D_TWO
    discriminant = p * p - c
    if is_zero(discriminant):
        return 1, -p, D_INF
    if discriminant < D_ZERO:
        return 0, D_INF, D_INF
    root = math.sqrt(discriminant)
    return 2, -root - p, root - p


@njit(**INLINE)
def cubic_roots(big_a, big_b, big_c):
    """``raytracer.quartic.solve_cubic(1, A, B, C)`` step by step: (count, r0, r1, r2),
    increasing."""
    square_a = big_a * big_a
    p = D_THIRD * (-D_THIRD * square_a + big_b)
    q = 0.5 * (2.0 / 27.0 * big_a * square_a - D_THIRD * big_a * big_b + big_c)
    cube_p = p * p * p
    discriminant = q * q + cube_p
    shift = D_THIRD * big_a
    if is_zero(discriminant):
        if is_zero(q):
            return 1, D_ZERO - shift, D_INF, D_INF
        u = cube_root(-q)
        r0, r1, _, _ = sort4(2, D_TWO * u - shift, -u - shift, D_INF, D_INF)
        return 2, r0, r1, D_INF
    if discriminant < D_ZERO:
        phi = D_THIRD * math.acos(max(-D_ONE, min(D_ONE, -q / math.sqrt(-cube_p))))
        t = D_TWO * math.sqrt(-p)
        r0, r1, r2, _ = sort4(
            3, t * math.cos(phi) - shift, -t * math.cos(phi + D_PI / 3.0) - shift,
            -t * math.cos(phi - D_PI / 3.0) - shift, D_INF,
        )  # fmt: skip
        return 3, r0, r1, r2
    root = math.sqrt(discriminant)
    return 1, cube_root(root - q) - cube_root(root + q) - shift, D_INF, D_INF


@njit(**INLINE)
def quartic_roots(a, b, c, d, e):
    """``raytracer.quartic.solve_quartic`` step by step (Ferrari's method): (count, r0, r1,
    r2, r3), increasing."""
    big_a = b / a
    big_b = c / a
    big_c = d / a
    big_d = e / a
    square_a = big_a * big_a
    p = -3.0 / 8.0 * square_a + big_b
    q = 1.0 / 8.0 * square_a * big_a - 0.5 * big_a * big_b + big_c
    r = (
        -3.0 / 256.0 * square_a * square_a + 1.0 / 16.0 * square_a * big_b
        - 0.25 * big_a * big_c + big_d
    )  # fmt: skip
    shift = 0.25 * big_a
    if is_zero(r):
        n, c0, c1, c2 = cubic_roots(D_ZERO, p, q)
        r0, r1, r2, r3 = sort4(4, D_ZERO - shift, c0 - shift, c1 - shift, c2 - shift)
        return n + 1, r0, r1, r2, r3
    n, z0, z1, z2 = cubic_roots(-0.5 * p, -r, 0.5 * r * p - 1.0 / 8.0 * q * q)
    z = z0 if n == 1 else (z1 if n == 2 else z2)  # the largest
    u = z * z - r
    v = D_TWO * z - p
    if (u < D_ZERO and not is_zero(u)) or (v < D_ZERO and not is_zero(v)):
        return 0, D_INF, D_INF, D_INF, D_INF
    u = D_ZERO if is_zero(u) else math.sqrt(u)
    v = D_ZERO if is_zero(v) else math.sqrt(v)
    n1, a0, a1 = quadratic_roots(-v if q < D_ZERO else v, z - u)
    n2, b0, b1 = quadratic_roots(v if q < D_ZERO else -v, z + u)
    # a missing root is D_INF (D_INF - shift too): sorted, they come last
    r0, r1, r2, r3 = sort4(4, a0 - shift, a1 - shift, b0 - shift, b1 - shift)
    return n1 + n2, r0, r1, r2, r3


@njit(**INLINE)
def torus_intersect(pf, p, ox, oy, oz, dx, dy, dz):
    """Chapter 20: the quartic's real roots (``raytracer.shapes.torus``): (count, t0, t1,
    t2, t3), increasing. Solved in float64 under the float32 option too: in float32 the
    closed form loses whole stretches of tube (``rtc stability``'s torus rows)."""
    big = np.float64(pf[p * NF + TORUS_MAJOR])
    small = np.float64(pf[p * NF + TORUS_MINOR])
    ox, oy, oz = np.float64(ox), np.float64(oy), np.float64(oz)
    dx, dy, dz = np.float64(dx), np.float64(dy), np.float64(dz)
    dd = dx * dx + dy * dy + dz * dz
    od = ox * dx + oy * dy + oz * dz
    oo = ox * ox + oy * oy + oz * oz
    k = oo + big * big - small * small
    four_r2 = 4.0 * big * big
    a = dd * dd
    if a == 0.0:
        return 0, INF, INF, INF, INF
    b = 4.0 * dd * od
    c = 2.0 * dd * k + 4.0 * od * od - four_r2 * (dx * dx + dz * dz)
    d = 4.0 * od * k - 2.0 * four_r2 * (ox * dx + oz * dz)
    e = k * k - four_r2 * (ox * ox + oz * oz)
    n, t0, t1, t2, t3 = quartic_roots(a, b, c, d, e)
    return n, F(t0), F(t1), F(t2), F(t3)


@njit(**INLINE)
def torus_normal(pf, p, x, y, z):
    """Chapter 20: from the tube's centre circle (``Torus.local_normal_at``)."""
    across = math.sqrt(x * x + z * z)
    if across == ZERO:
        return ZERO, ONE if y >= ZERO else -ONE, ZERO
    scale = pf[p * NF + TORUS_MAJOR] / across
    return x - x * scale, y, z - z * scale


@njit(**INLINE)
def intersect_local(pf, pi, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapters 5-15: primitive p's intersections with an object-space ray, in the
    reference's order: (count, t0, t1, t2, t3, u, v); u and v only for triangles."""
    kind = pi[p * NI + KIND]
    if HAS_SPHERE and kind == K_SPHERE:
        n, a, b = sphere_intersect(ox, oy, oz, dx, dy, dz)
        return n, a, b, INF, INF, ZERO, ZERO
    if HAS_PLANE and kind == K_PLANE:
        n, a = plane_intersect(oy, dy, eps)
        return n, a, INF, INF, INF, ZERO, ZERO
    if HAS_CUBE and kind == K_CUBE:
        n, a, b = cube_intersect(ox, oy, oz, dx, dy, dz, eps)
        return n, a, b, INF, INF, ZERO, ZERO
    if HAS_CYLINDER and kind == K_CYLINDER:
        n, a, b, c, d = cylinder_intersect(pf, pi, p, ox, oy, oz, dx, dy, dz, eps)
        return n, a, b, c, d, ZERO, ZERO
    if HAS_CONE and kind == K_CONE:
        n, a, b, c, d = cone_intersect(pf, pi, p, ox, oy, oz, dx, dy, dz, eps)
        return n, a, b, c, d, ZERO, ZERO
    if HAS_TORUS and kind == K_TORUS:
        n, a, b, c, d = torus_intersect(pf, p, ox, oy, oz, dx, dy, dz)
        return n, a, b, c, d, ZERO, ZERO
    if (HAS_TRIANGLE and kind == K_TRIANGLE) or (HAS_SMOOTH_TRIANGLE and kind == K_SMOOTH_TRIANGLE):
        n, a, u, v = triangle_intersect(pf, p, ox, oy, oz, dx, dy, dz, eps)
        return n, a, INF, INF, INF, u, v
    return 0, INF, INF, INF, INF, ZERO, ZERO  # the test shape: never hit


@njit(**INLINE)
def bound_terms(pf, p, ox, oy, oz, dx, dy, dz):
    """Primitive p's world-space bounding sphere against the ray: (radius, b, c, a, b² - a c)
    with oc = centre - origin, b = oc · d, c = oc · oc - radius², a = d · d."""
    m = p * NF + BOUND
    radius = pf[m + 3]
    cx = pf[m] - ox
    cy = pf[m + 1] - oy
    cz = pf[m + 2] - oz
    b = cx * dx + cy * dy + cz * dz
    c = cx * cx + cy * cy + cz * cz - radius * radius
    a = dx * dx + dy * dy + dz * dz
    return radius, b, c, a, b * b - a * c


@njit(**INLINE)
def misses_bound(pf, p, ox, oy, oz, dx, dy, dz):
    """Does the ray's line miss primitive p's world-space bounding sphere? (A cheap test
    that skips the exact one; it never changes a result.)"""
    radius, _, _, _, discriminant = bound_terms(pf, p, ox, oy, oz, dx, dy, dz)
    return radius != INF and discriminant < ZERO


@njit(**INLINE)
def outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
    """Is primitive p's bounding sphere certainly missed by the ray for t in [0, tmax]?
    (The line misses it, it lies behind the origin, or the ray enters it after tmax; no
    square root, no division. Its radius is padded, so this never drops a real hit.)"""
    radius, b, c, a, discriminant = bound_terms(pf, p, ox, oy, oz, dx, dy, dz)
    if radius == INF:
        return False
    if discriminant < ZERO:
        return True
    if c > ZERO:  # the origin is outside the sphere
        if b < ZERO:  # ... and the sphere is behind it
            return True
        late = b - a * tmax  # the ray enters after tmax: (b - sqrt(disc)) / a > tmax
        if late > ZERO and late * late > discriminant:
            return True
    return False


@njit(**INLINE)
def starts_after(pf, p, ox, oy, oz, dx, dy, dz, t):
    """Does the ray enter primitive p's bounding sphere only after ``t`` (or never)? Then
    none of its intersections comes before t (for n1/n2)."""
    radius, b, c, a, discriminant = bound_terms(pf, p, ox, oy, oz, dx, dy, dz)
    if radius == INF:
        return False
    if discriminant < ZERO:
        return True
    late = b - a * t
    return c > ZERO and late > ZERO and late * late > discriminant


@njit(**INLINE)
def intersect_prim(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, tmax):
    """Chapter 5: primitive p's intersections with a world-space ray: all of them (any t)
    when ``tmax`` is INF, else possibly none when none can lie in [0, tmax] (for the hit
    and shadow rays). A plane needs only the y row of its transform; a similarity-
    transformed sphere is tested in world space."""
    kind = pi[p * NI + KIND]
    if HAS_PLANE and kind == K_PLANE:
        m = p * NF + INV
        loy = pf[m + 4] * ox + pf[m + 5] * oy + pf[m + 6] * oz + pf[m + 7]
        ldy = pf[m + 4] * dx + pf[m + 5] * dy + pf[m + 6] * dz
        n, a = plane_intersect(loy, ldy, eps)
        return n, a, INF, INF, INF, ZERO, ZERO
    if is_world_sphere(pi, p):
        n, a, b = ball_intersect(pf, p, ox, oy, oz, dx, dy, dz, dx * dx + dy * dy + dz * dz)
        return n, a, b, INF, INF, ZERO, ZERO
    if tmax == INF:
        if misses_bound(pf, p, ox, oy, oz, dx, dy, dz):
            return 0, INF, INF, INF, INF, ZERO, ZERO
    elif outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
        return 0, INF, INF, INF, INF, ZERO, ZERO
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    return intersect_local(pf, pi, p, lox, loy, loz, ldx, ldy, ldz, eps)


@njit(**INLINE)
def first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, a, eps, tmax):
    """Chapters 5-15, for the hit and shadow rays: primitive p's first intersection with t
    in [0, tmax): (found, t, index in its list, u, v); ``a`` = direction · direction. When
    none is found, t is still the first t >= 0 (or INF) unless it is certainly beyond tmax
    (so that a caller can tell a tie at tmax).
    Divisions are skipped where the answer is already known: a plane behind the origin or
    certainly beyond tmax, a ball the ray leaves or meets beyond tmax."""
    kind = pi[p * NI + KIND]
    if HAS_PLANE and kind == K_PLANE:
        m = p * NF + INV
        loy = pf[m + 4] * ox + pf[m + 5] * oy + pf[m + 6] * oz + pf[m + 7]
        ldy = pf[m + 4] * dx + pf[m + 5] * dy + pf[m + 6] * dz
        if abs(ldy) < eps or loy * ldy > ZERO:  # parallel, or t = -loy / ldy < 0
            return False, INF, 0, ZERO, ZERO
        if abs(loy) > tmax * abs(ldy) * F(1.000001):  # certainly t > tmax
            return False, INF, 0, ZERO, ZERO
        t = -loy / ldy
        return t >= ZERO and t < tmax, t, 0, ZERO, ZERO
    if is_world_sphere(pi, p):
        found, t, local = ball_first_hit(pf, p, ox, oy, oz, dx, dy, dz, a, tmax)
        return found, t, local, ZERO, ZERO
    if outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
        return False, INF, 0, ZERO, ZERO
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    if HAS_SPHERE and kind == K_SPHERE:
        la = ldx * ldx + ldy * ldy + ldz * ldz
        b = TWO * (ldx * lox + ldy * loy + ldz * loz)
        c = (lox * lox + loy * loy + loz * loz) - ONE
        discriminant = b * b - F(4.0) * la * c
        if discriminant < ZERO:
            return False, INF, 0, ZERO, ZERO
        root = math.sqrt(discriminant)
        t = (-b - root) / (TWO * la)
        if t >= ZERO:
            return t < tmax, t, 0, ZERO, ZERO
        t = (-b + root) / (TWO * la)
        return t >= ZERO and t < tmax, t, 1, ZERO, ZERO
    n, t0, t1, t2, t3, u, v = intersect_local(pf, pi, p, lox, loy, loz, ldx, ldy, ldz, eps)
    best = INF
    local = 0
    for j in range(n):
        t = nth(t0, t1, t2, t3, j)
        if t >= ZERO and t < best:
            best = t
            local = j
    return best < tmax, best, local, u, v


@njit(**INLINE)
def local_normal(pf, pi, p, x, y, z, u, v, eps, g, local):
    """Chapters 6-15: primitive p's object-space normal at an object-space point; for a run
    of compact triangles (``g`` = (tg, tn)), triangle ``local``'s."""
    m = p * NF
    kind = pi[p * NI + KIND]
    first = pi[p * NI + TRI_FIRST]
    if (HAS_TRIANGLE or HAS_SMOOTH_TRIANGLE) and first >= 0:
        tg, tn = g
        if HAS_SMOOTH_TRIANGLE and kind == K_SMOOTH_TRIANGLE:
            n = (pi[p * NI + TN_FIRST] + local - first) * NTN
            return smooth_normal(tn, n, n + 3, n + 6, u, v)
        n = local * NTG + TG_NORMAL
        return tg[n], tg[n + 1], tg[n + 2]
    if HAS_SPHERE and kind == K_SPHERE:
        return x, y, z
    if HAS_PLANE and kind == K_PLANE:
        return ZERO, ONE, ZERO
    if HAS_CUBE and kind == K_CUBE:
        return cube_normal(x, y, z)
    if HAS_CYLINDER and kind == K_CYLINDER:
        return cylinder_normal(pf, p, x, y, z, eps)
    if HAS_CONE and kind == K_CONE:
        return cone_normal(pf, p, x, y, z, eps)
    if HAS_TORUS and kind == K_TORUS:
        return torus_normal(pf, p, x, y, z)
    if HAS_TRIANGLE and kind == K_TRIANGLE:
        return pf[m + TRI_NORMAL], pf[m + TRI_NORMAL + 1], pf[m + TRI_NORMAL + 2]
    if HAS_SMOOTH_TRIANGLE and kind == K_SMOOTH_TRIANGLE:
        return smooth_normal(pf, m + TRI_N1, m + TRI_N2, m + TRI_N3, u, v)
    return x, y, z  # the test shape: the point as a vector


@njit(**INLINE)
def world_normal(pf, pi, p, x, y, z, u, v, eps, g, local):
    """Chapters 6 and 14: primitive p's world-space normal at a world-space point; for a
    ball, from its centre (the reference's direction, rounded differently)."""
    if is_world_sphere(pi, p):
        m = p * NF + SPH_CENTER
        return normalized(x - pf[m], y - pf[m + 1], z - pf[m + 2])
    lx, ly, lz = to_object_point(pf, p, x, y, z)
    nx, ny, nz = local_normal(pf, pi, p, lx, ly, lz, u, v, eps, g, local)
    return to_world_normal(pf, p, nx, ny, nz)


@njit(**INLINE)
def hit_normal(pf, pi, p, x, y, z, u, v, eps, g, local):
    """Chapters 6 and 14, at a hit: ``world_normal``, but a ball's is (point - centre) /
    radius, with no square root: the hit lies on the ball up to rounding, so its length is
    1 to about 1e-15."""
    if is_world_sphere(pi, p):
        m = p * NF
        k = pf[m + SPH_INV_R]
        c = m + SPH_CENTER
        return (x - pf[c]) * k, (y - pf[c + 1]) * k, (z - pf[c + 2]) * k
    return world_normal(pf, pi, p, x, y, z, u, v, eps, g, local)


@njit(**INLINE)
def slab(o, inverse_d, lo, hi, tlo, thi):
    """Chapter 14 (bounding boxes): narrow [tlo, thi] to where the ray is between lo and hi
    on one axis, given 1 / the direction (infinite when the ray is parallel to the slab)."""
    if abs(inverse_d) == INF:
        if o < lo or o > hi:
            return INF, -INF
        return tlo, thi
    t1 = (lo - o) * inverse_d
    t2 = (hi - o) * inverse_d
    if t1 > t2:
        t1, t2 = t2, t1
    return max(tlo, t1), min(thi, t2)


@njit(**INLINE)
def box_range(boxes, b, ox, oy, oz, ix, iy, iz, tlo, thi):
    """Chapter 14 (bounding boxes): does the ray (origin, 1 / direction) meet world-space
    box b (a box item's ITEM_D) for some t in [tlo, thi]? The boxes are padded: rounding in
    the reciprocal never loses a hit."""
    m = b * NBOX
    tlo, thi = slab(ox, ix, boxes[m], boxes[m + 3], tlo, thi)
    if tlo > thi:
        return False
    tlo, thi = slab(oy, iy, boxes[m + 1], boxes[m + 4], tlo, thi)
    if tlo > thi:
        return False
    tlo, thi = slab(oz, iz, boxes[m + 2], boxes[m + 5], tlo, thi)
    return tlo <= thi


@njit(**INLINE)
def nth(t0, t1, t2, t3, j):
    """The j-th of four values (tuples indexed by a variable go through memory)."""
    if j == 0:
        return t0
    if j == 1:
        return t1
    if j == 2:
        return t2
    return t3
