"""Kernel template, part 1: transforms, intersections and normals of every shape kind
(chapters 5, 6, 9, 12, 13 and 15), and bounding boxes (chapter 14).

Each function mirrors the reference's arithmetic (same operations in the same order), so the
kernels and the reference agree to the last bit wherever the reference is exact. Everything
is scalar: vectors are passed and returned as separate x, y, z values, so nothing allocates.
Literals are wrapped in ``F`` so the float32 option computes in float32 throughout.
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
    HAS_TRIANGLE,
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
    K_TRIANGLE,
    KIND,
    MAXIMUM,
    MINIMUM,
    NRM,
    TRI_E1,
    TRI_E2,
    TRI_N1,
    TRI_N2,
    TRI_N3,
    TRI_NORMAL,
    TRI_P1,
)

# ---- kernel template ----

# Helpers: compiled once, then inlined by LLVM into every caller (numba's own inlining,
# inline="always", copies the IR into each caller before typing: several times slower to
# compile). Without the numba runtime (_nrt=False) they do no reference counting of the
# arrays they are passed: otherwise every call increments and decrements the shared
# arrays' counts atomically, and threads fight over them. They allocate nothing.
INLINE: dict[str, Any] = {
    "forceinline": True,
    "_nrt": False,
    "fastmath": FASTMATH,
    "error_model": "numpy",
}
INF = F(np.inf)
ZERO = F(0.0)
ONE = F(1.0)
TWO = F(2.0)


@njit(**INLINE)
def to_object_point(pf, p, x, y, z):
    """Chapter 5: a world-space point in primitive p's object space (the composed inverse)."""
    return (
        pf[p, INV + 0] * x + pf[p, INV + 1] * y + pf[p, INV + 2] * z + pf[p, INV + 3],
        pf[p, INV + 4] * x + pf[p, INV + 5] * y + pf[p, INV + 6] * z + pf[p, INV + 7],
        pf[p, INV + 8] * x + pf[p, INV + 9] * y + pf[p, INV + 10] * z + pf[p, INV + 11],
    )


@njit(**INLINE)
def to_object_vector(pf, p, x, y, z):
    """Chapter 5: a world-space direction in primitive p's object space."""
    return (
        pf[p, INV + 0] * x + pf[p, INV + 1] * y + pf[p, INV + 2] * z,
        pf[p, INV + 4] * x + pf[p, INV + 5] * y + pf[p, INV + 6] * z,
        pf[p, INV + 8] * x + pf[p, INV + 9] * y + pf[p, INV + 10] * z,
    )


@njit(**INLINE)
def normalized(x, y, z):
    """Chapter 1: (x, y, z) scaled to length 1, dividing as the reference does."""
    m = math.sqrt(x * x + y * y + z * z)
    return x / m, y / m, z / m


@njit(**INLINE)
def to_world_normal(pf, p, x, y, z):
    """Chapter 14: an object-space normal in world space (inverse transpose), normalized;
    a zero normal (a cone's tip) stays zero."""
    nx = pf[p, NRM + 0] * x + pf[p, NRM + 1] * y + pf[p, NRM + 2] * z
    ny = pf[p, NRM + 3] * x + pf[p, NRM + 4] * y + pf[p, NRM + 5] * z
    nz = pf[p, NRM + 6] * x + pf[p, NRM + 7] * y + pf[p, NRM + 8] * z
    if nx != ZERO or ny != ZERO or nz != ZERO:
        return normalized(nx, ny, nz)
    return nx, ny, nz


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
    lo = pf[p, MINIMUM]
    hi = pf[p, MAXIMUM]
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
    if pi[p, CLOSED] != 0 and not abs(dy) < eps:
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
    if distance < ONE and y >= pf[p, MAXIMUM] - eps:
        return ZERO, ONE, ZERO
    if distance < ONE and y <= pf[p, MINIMUM] + eps:
        return ZERO, -ONE, ZERO
    return x, ZERO, z


@njit(**INLINE)
def cone_intersect(pf, pi, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 13: the double cone x² + z² = y² between minimum and maximum (one crossing
    when the ray runs parallel to one half), then the caps: (count, t0, t1, t2, t3)."""
    lo = pf[p, MINIMUM]
    hi = pf[p, MAXIMUM]
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
    if pi[p, CLOSED] != 0 and not abs(dy) < eps:
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
    hi = pf[p, MAXIMUM]
    lo = pf[p, MINIMUM]
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
    """Chapter 15: Möller-Trumbore: (count, t, u, v)."""
    e1x = pf[p, TRI_E1]
    e1y = pf[p, TRI_E1 + 1]
    e1z = pf[p, TRI_E1 + 2]
    e2x = pf[p, TRI_E2]
    e2y = pf[p, TRI_E2 + 1]
    e2z = pf[p, TRI_E2 + 2]
    cx = dy * e2z - dz * e2y
    cy = dz * e2x - dx * e2z
    cz = dx * e2y - dy * e2x
    det = e1x * cx + e1y * cy + e1z * cz
    if abs(det) < eps:
        return 0, INF, ZERO, ZERO
    f = ONE / det
    px = ox - pf[p, TRI_P1]
    py = oy - pf[p, TRI_P1 + 1]
    pz = oz - pf[p, TRI_P1 + 2]
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
def smooth_normal(pf, p, u, v):
    """Chapter 15: the corner normals blended by the hit's u and v."""
    w = ONE - u - v
    return (
        pf[p, TRI_N2] * u + pf[p, TRI_N3] * v + pf[p, TRI_N1] * w,
        pf[p, TRI_N2 + 1] * u + pf[p, TRI_N3 + 1] * v + pf[p, TRI_N1 + 1] * w,
        pf[p, TRI_N2 + 2] * u + pf[p, TRI_N3 + 2] * v + pf[p, TRI_N1 + 2] * w,
    )


@njit(**INLINE)
def intersect_local(pf, pi, p, ox, oy, oz, dx, dy, dz, eps):
    """Chapters 5-15: primitive p's intersections with an object-space ray, in the
    reference's order: (count, t0, t1, t2, t3, u, v); u and v only for triangles."""
    kind = pi[p, KIND]
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
    if (HAS_TRIANGLE and kind == K_TRIANGLE) or (HAS_SMOOTH_TRIANGLE and kind == K_SMOOTH_TRIANGLE):
        n, a, u, v = triangle_intersect(pf, p, ox, oy, oz, dx, dy, dz, eps)
        return n, a, INF, INF, INF, u, v
    return 0, INF, INF, INF, INF, ZERO, ZERO  # the test shape: never hit


@njit(**INLINE)
def misses_bound(pf, p, ox, oy, oz, dx, dy, dz):
    """Does the ray's line miss primitive p's world-space bounding sphere? (A cheap test
    that skips the exact one; it never changes a result.)"""
    radius = pf[p, BOUND + 3]
    if radius == INF:
        return False
    cx = pf[p, BOUND] - ox
    cy = pf[p, BOUND + 1] - oy
    cz = pf[p, BOUND + 2] - oz
    b = cx * dx + cy * dy + cz * dz
    c = cx * cx + cy * cy + cz * cz - radius * radius
    a = dx * dx + dy * dy + dz * dz
    return b * b - a * c < ZERO


@njit(**INLINE)
def outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
    """Is primitive p's bounding sphere certainly missed by the ray for t in [0, tmax]?
    (The line misses it, it lies behind the origin, or the ray enters it after tmax; no
    square root, no division. Its radius is padded, so this never drops a real hit.)"""
    radius = pf[p, BOUND + 3]
    if radius == INF:
        return False
    cx = pf[p, BOUND] - ox
    cy = pf[p, BOUND + 1] - oy
    cz = pf[p, BOUND + 2] - oz
    b = cx * dx + cy * dy + cz * dz
    c = cx * cx + cy * cy + cz * cz - radius * radius
    a = dx * dx + dy * dy + dz * dz
    discriminant = b * b - a * c  # a/4 of the quadratic's: its sign says if the line hits
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
    radius = pf[p, BOUND + 3]
    if radius == INF:
        return False
    cx = pf[p, BOUND] - ox
    cy = pf[p, BOUND + 1] - oy
    cz = pf[p, BOUND + 2] - oz
    b = cx * dx + cy * dy + cz * dz
    c = cx * cx + cy * cy + cz * cz - radius * radius
    a = dx * dx + dy * dy + dz * dz
    discriminant = b * b - a * c
    if discriminant < ZERO:
        return True
    late = b - a * t
    return c > ZERO and late > ZERO and late * late > discriminant


@njit(**INLINE)
def intersect_prim(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, tmax):
    """Chapter 5: primitive p's intersections with a world-space ray: all of them (any t)
    when ``tmax`` is INF, else possibly none when none can lie in [0, tmax] (for the hit
    and shadow rays). A plane needs only the y row of its transform."""
    if HAS_PLANE and pi[p, KIND] == K_PLANE:
        loy = pf[p, INV + 4] * ox + pf[p, INV + 5] * oy + pf[p, INV + 6] * oz + pf[p, INV + 7]
        ldy = pf[p, INV + 4] * dx + pf[p, INV + 5] * dy + pf[p, INV + 6] * dz
        n, a = plane_intersect(loy, ldy, eps)
        return n, a, INF, INF, INF, ZERO, ZERO
    if tmax == INF:
        if misses_bound(pf, p, ox, oy, oz, dx, dy, dz):
            return 0, INF, INF, INF, INF, ZERO, ZERO
    elif outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
        return 0, INF, INF, INF, INF, ZERO, ZERO
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    return intersect_local(pf, pi, p, lox, loy, loz, ldx, ldy, ldz, eps)


@njit(**INLINE)
def first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, tmax):
    """Chapters 5-15, for the hit and shadow rays: primitive p's first intersection with t
    in [0, tmax): (found, t, index in its list, u, v). The same t as ``intersect_prim``
    computes, but divisions are skipped where the answer is already known: a plane behind
    the origin or certainly beyond tmax, a sphere's second root when the first is taken."""
    kind = pi[p, KIND]
    if HAS_PLANE and kind == K_PLANE:
        loy = pf[p, INV + 4] * ox + pf[p, INV + 5] * oy + pf[p, INV + 6] * oz + pf[p, INV + 7]
        ldy = pf[p, INV + 4] * dx + pf[p, INV + 5] * dy + pf[p, INV + 6] * dz
        if abs(ldy) < eps or loy * ldy > ZERO:  # parallel, or t = -loy / ldy < 0
            return False, INF, 0, ZERO, ZERO
        if abs(loy) > tmax * abs(ldy) * F(1.000001):  # certainly t > tmax
            return False, INF, 0, ZERO, ZERO
        t = -loy / ldy
        return t >= ZERO and t < tmax, t, 0, ZERO, ZERO
    if outside_bound(pf, p, ox, oy, oz, dx, dy, dz, tmax):
        return False, INF, 0, ZERO, ZERO
    lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
    ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
    if HAS_SPHERE and kind == K_SPHERE:
        a = ldx * ldx + ldy * ldy + ldz * ldz
        b = TWO * (ldx * lox + ldy * loy + ldz * loz)
        c = (lox * lox + loy * loy + loz * loz) - ONE
        discriminant = b * b - F(4.0) * a * c
        if discriminant < ZERO:
            return False, INF, 0, ZERO, ZERO
        root = math.sqrt(discriminant)
        t = (-b - root) / (TWO * a)
        if t >= ZERO:
            return t < tmax, t, 0, ZERO, ZERO
        t = (-b + root) / (TWO * a)
        return t >= ZERO and t < tmax, t, 1, ZERO, ZERO
    n, t0, t1, t2, t3, u, v = intersect_local(pf, pi, p, lox, loy, loz, ldx, ldy, ldz, eps)
    best = tmax
    local = -1
    for j in range(n):
        t = nth(t0, t1, t2, t3, j)
        if t >= ZERO and t < best:
            best = t
            local = j
    return local >= 0, best, max(local, 0), u, v


@njit(**INLINE)
def local_normal(pf, pi, p, x, y, z, u, v, eps):
    """Chapters 6-15: primitive p's object-space normal at an object-space point."""
    kind = pi[p, KIND]
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
    if HAS_TRIANGLE and kind == K_TRIANGLE:
        return pf[p, TRI_NORMAL], pf[p, TRI_NORMAL + 1], pf[p, TRI_NORMAL + 2]
    if HAS_SMOOTH_TRIANGLE and kind == K_SMOOTH_TRIANGLE:
        return smooth_normal(pf, p, u, v)
    return x, y, z  # the test shape: the point as a vector


@njit(**INLINE)
def world_normal(pf, pi, p, x, y, z, u, v, eps):
    """Chapters 6 and 14: primitive p's world-space normal at a world-space point."""
    lx, ly, lz = to_object_point(pf, p, x, y, z)
    nx, ny, nz = local_normal(pf, pi, p, lx, ly, lz, u, v, eps)
    return to_world_normal(pf, p, nx, ny, nz)


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
def box_range(boxes, i, ox, oy, oz, ix, iy, iz, tlo, thi):
    """Chapter 14 (bounding boxes): does the ray (origin, 1 / direction) meet item i's
    world-space box for some t in [tlo, thi]? The boxes are padded: rounding in the
    reciprocal never loses a hit."""
    tlo, thi = slab(ox, ix, boxes[i, 0], boxes[i, 3], tlo, thi)
    if tlo > thi:
        return False
    tlo, thi = slab(oy, iy, boxes[i, 1], boxes[i, 4], tlo, thi)
    if tlo > thi:
        return False
    tlo, thi = slab(oz, iz, boxes[i, 2], boxes[i, 5], tlo, thi)
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
