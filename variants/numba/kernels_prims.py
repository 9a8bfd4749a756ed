"""Kernel template: a primitive's intersections and normal whatever its kind (chapters
5-15): the dispatch on its kind, after the shortcuts a world-space ray takes first (a
plane's one row of its transform, a world-space ball, the bounding sphere), and the first
hit among a primitive's (or a compact run's) intersections.
"""

import math

from numba import njit

from variants.numba.kernel_flags import (
    HAS_CONE,
    HAS_CUBE,
    HAS_CYLINDER,
    HAS_PLANE,
    HAS_SMOOTH_TRIANGLE,
    HAS_SPHERE,
    HAS_TORUS,
    HAS_TRIANGLE,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    TWO,
    ZERO,
    ball_first_hit,
    ball_intersect,
    is_world_sphere,
    misses_bound,
    normalized,
    nth,
    outside_bound,
    to_object_point,
    to_object_vector,
    to_world_normal,
)
from variants.numba.kernels_shapes import (
    cone_intersect,
    cone_normal,
    cube_intersect,
    cube_normal,
    cylinder_intersect,
    cylinder_normal,
    plane_intersect,
    smooth_normal,
    sphere_intersect,
    torus_intersect,
    torus_normal,
    triangle_intersect,
)
from variants.numba.layout import (
    INV,
    K_CONE,
    K_CUBE,
    K_CYLINDER,
    K_PLANE,
    K_SMOOTH_TRIANGLE,
    K_SPHERE,
    K_TORUS,
    K_TRIANGLE,
    KIND,
    NF,
    NI,
    NTG,
    NTN,
    SPH_CENTER,
    SPH_INV_R,
    TG_NORMAL,
    TN_FIRST,
    TRI_FIRST,
    TRI_N1,
    TRI_N2,
    TRI_N3,
    TRI_NORMAL,
)

# ---- kernel template ----


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
