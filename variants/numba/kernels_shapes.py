"""Kernel template: each shape kind's intersection and normal in object space (chapters 5,
9, 12, 13, 15, and the torus's quartic), repeating the reference's arithmetic operation by
operation; a kind's code is compiled in only for a scene that has the kind
(``kernel_flags``). Triangles come one per row or as compact runs (``layout``: ``tg``,
``tn``).
"""

import math

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    TWO,
    ZERO,
    to_object_point,
    to_object_vector,
)
from variants.numba.kernels_quartic import push_root, quartic_roots
from variants.numba.layout import (
    CLOSED,
    MAXIMUM,
    MINIMUM,
    NF,
    NI,
    NTG,
    TG_E1,
    TG_E2,
    TG_P1,
    TORUS_MAJOR,
    TORUS_MINOR,
    TRI_E1,
    TRI_E2,
    TRI_P1,
)

# ---- kernel template ----

# the torus's quartic is solved in float64 whatever F is (``torus_intersect``)
D_INF = np.inf


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
def torus_missed(ox, oy, oz, dx, dy, dz, big, small):
    """Whether the line (from its closest approach to the centre) certainly misses the
    torus: outside its sphere, or across its slab |y| <= r only farther from the axis than
    R + r or nearer than R - r (a hole's ray). Margins of 2**-19 of the radii keep every ray
    that rounding could bring to the tube (the quartic decides those)."""
    outer = (big + small) * (big + small) * (1 + 2.0**-19)
    if ox * ox + oy * oy + oz * oz > outer:
        return True
    top = small * (1 + 2.0**-20)
    if dy == 0.0:
        return abs(oy) > top
    t0, t1 = (-top - oy) / dy, (top - oy) / dy
    if t1 < t0:
        t0, t1 = t1, t0
    across = dx * dx + dz * dz
    nearest = t0
    if across > 0.0:
        nearest = min(max(-(ox * dx + oz * dz) / across, t0), t1)
    x, z = ox + nearest * dx, oz + nearest * dz
    if x * x + z * z > outer:
        return True
    hole = (big - small) * (big - small) * (1 - 2.0**-19)
    if big <= small:
        return False
    x0, z0, x1, z1 = ox + t0 * dx, oz + t0 * dz, ox + t1 * dx, oz + t1 * dz
    return x0 * x0 + z0 * z0 < hole and x1 * x1 + z1 * z1 < hole


@njit(**INLINE)
def torus_intersect(pf, p, ox, oy, oz, dx, dy, dz):
    """Chapter 20: the quartic's real roots (``raytracer.shapes.torus``) as ``robust`` finds
    them (``variants.robust.geometry.torus_roots``): the ray's origin moved to its closest
    approach to the centre, the roots by the certified closed form, else isolated and
    refined (``kernels_quartic.quartic_roots``): (count,
    t0, t1, t2, t3), increasing, a double root (a grazing ray) twice. In float64 under the
    float32 option too (in float32 whole stretches of tube are lost)."""
    big = np.float64(pf[p * NF + TORUS_MAJOR])
    small = np.float64(pf[p * NF + TORUS_MINOR])
    ox, oy, oz = np.float64(ox), np.float64(oy), np.float64(oz)
    dx, dy, dz = np.float64(dx), np.float64(dy), np.float64(dz)
    dd = dx * dx + dy * dy + dz * dz
    if dd == 0.0 or not math.isfinite(dd):
        return 0, INF, INF, INF, INF
    shift = -(ox * dx + oy * dy + oz * dz) / dd  # the closest approach to the centre
    ox, oy, oz = ox + shift * dx, oy + shift * dy, oz + shift * dz
    if torus_missed(ox, oy, oz, dx, dy, dz, big, small):
        return 0, INF, INF, INF, INF
    od = ox * dx + oy * dy + oz * dz
    oo = ox * ox + oy * oy + oz * oz
    k = oo + big * big - small * small
    four_r2 = 4 * big * big
    a = dd * dd
    b = 4 * dd * od
    c = 2 * dd * k + 4 * od * od - four_r2 * (dx * dx + dz * dz)
    d = 4 * od * k - 2 * four_r2 * (ox * dx + oz * dz)
    e = k * k - four_r2 * (ox * ox + oz * oz)
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c) and math.isfinite(d)
            and math.isfinite(e)):  # fmt: skip
        return 0, INF, INF, INF, INF
    n, t0, t1, t2, t3 = quartic_roots(a, b, c, d, e)
    m, s0, s1, s2, s3 = 0, D_INF, D_INF, D_INF, D_INF
    roots = (t0, t1, t2, t3)
    for i in range(n):
        m, s0, s1, s2, s3 = push_root(m, s0, s1, s2, s3, roots[i] + shift)
    return m, F(s0), F(s1), F(s2), F(s3)


@njit(**INLINE)
def torus_normal(pf, p, x, y, z):
    """Chapter 20: from the tube's centre circle (``Torus.local_normal_at``)."""
    across = math.sqrt(x * x + z * z)
    if across == ZERO:
        return ZERO, ONE if y >= ZERO else -ONE, ZERO
    scale = pf[p * NF + TORUS_MAJOR] / across
    return x - x * scale, y, z - z * scale
