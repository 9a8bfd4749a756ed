"""Kernel template, part 3: rays through the packed world (chapters 7, 8, 11, 14, 16), the
explicit stack that replaces the book's recursion, camera rays and samples, and the render.

- ``nearest_hit`` tracks the closest non-negative t instead of building a sorted list; ties go
  to the earlier primitive, as the reference's stable sort does.
- ``refractive_indices`` finds n1 and n2 without a sorted list: an object is in the book's
  ``containers`` when an odd number of its intersections come before the hit, and the last
  of them entered is the one whose latest such intersection comes last.
- ``trace`` is ``color_at`` without recursion: a stack of (ray, weight, remaining), where the
  weight is the product of the reflective / transparency / Schlick factors on the way.
- ``render_parallel`` hands thread k the rows k, k + T, k + 2T ... (the top and bottom of an
  image cost very different amounts, so contiguous blocks would leave one thread idle).

Every traversal takes the same per-thread scratch arrays ``sf`` and ``si`` (rows CS_*, see
``layout``): one CSG tree's intersection list, and per primitive of the tree where its
entries start and, for n1/n2, how many come before the hit.

No function takes more than 30 arguments: Python compiles longer calls through a tuple,
which numba's inliner refuses.
"""

# ruff: noqa: E501
import math
from typing import Any

import numpy as np
from numba import njit, prange

from variants.numba.kernel_flags import (
    COUNT_RAYS,
    FASTMATH,
    HAS_BOXES,
    HAS_CSG,
    HAS_REFLECTION,
    HAS_REFRACTION,
    HAS_SCHLICK,
    HAS_SHADOWS,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    ZERO,
    box_range,
    first_hit_in,
    intersect_prim,
    nth,
    starts_after,
    world_normal,
)
from variants.numba.kernels_shading import phong, refraction, schlick_at, towards_light
from variants.numba.layout import (
    CAM_HALF_HEIGHT,
    CAM_HALF_WIDTH,
    CAM_INV,
    CAM_PIXEL_SIZE,
    CASTS_SHADOW,
    CS_COUNT,
    CS_L,
    CS_LAST_L,
    CS_LAST_T,
    CS_P,
    CS_START,
    CS_T,
    CS_U,
    CS_V,
    CSG_END,
    CSG_MID,
    CSG_OP,
    CSG_START,
    I_BOX,
    I_CSG,
    I_PRIM,
    ITEM_A,
    ITEM_B,
    ITEM_C,
    ITEM_D,
    ITEM_TYPE,
    MEMO,
    NSF,
    NSI,
    OP_DIFFERENCE,
    OP_INTERSECTION,
    OP_UNION,
    RAYS,
    REFLECTIVE,
    REFRACTIVE_INDEX,
    STACK_WIDTH,
    TRANSPARENCY,
)

# ---- kernel template ----

ENTRY: dict[str, Any] = {"fastmath": FASTMATH, "error_model": "numpy", "cache": True}
HOT: dict[str, Any] = {"_nrt": False, "fastmath": FASTMATH, "error_model": "numpy", "cache": True}
GAMMA = np.uint64(0x9E3779B97F4A7C15)  # raytracer.sampling.GAMMA
GAMMA2 = np.uint64((2 * 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF)
MIX1 = np.uint64(0xBF58476D1CE4E5B9)
MIX2 = np.uint64(0x94D049BB133111EB)
UNIT53 = 2.0**-53


@njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def scratch(cs_size, cs_prims):
    """One thread's CSG scratch (allocated once per thread per render, or per API call)."""
    size = max(cs_size, cs_prims, 3)
    si = np.empty((NSI, size), np.int64)
    si[MEMO, 0] = -1
    return np.empty((NSF, size), F), si


@njit(**INLINE)
def csg_allowed(op, lhit, inl, inr):
    """Chapter 16: ``intersection_allowed(op, lhit, inl, inr)``."""
    if op == OP_UNION:
        return (lhit and not inr) or (not lhit and not inl)
    if op == OP_INTERSECTION:
        return (lhit and inr) or (not lhit and inl)
    if op == OP_DIFFERENCE:
        return (lhit and not inr) or (not lhit and inl)
    return False


@njit(**INLINE)
def csg_collect(pf, pi, items, csg, i, ox, oy, oz, dx, dy, dz, eps, sf, si):
    """Chapter 16: the intersection list of CSG item i, sorted and filtered, in cs_*; returns
    its length. Operations are applied in post-order, each to the stretch of the list its
    primitives occupy, so nested CSG trees need no recursion."""
    node = items[i, ITEM_A]
    last_node = items[i, ITEM_B]
    first = items[i, ITEM_C]
    n = 0
    for q in range(first, items[i, ITEM_D]):
        si[CS_START, q - first] = n
        m, t0, t1, t2, t3, u, v = intersect_prim(pf, pi, q, ox, oy, oz, dx, dy, dz, eps, INF)
        for local in range(m):
            sf[CS_T, n] = nth(t0, t1, t2, t3, local)
            si[CS_P, n] = q
            si[CS_L, n] = local
            sf[CS_U, n] = u
            sf[CS_V, n] = v
            n += 1
        while node < last_node and csg[node, CSG_END] == q + 1:
            start = si[CS_START, csg[node, CSG_START] - first]
            for j in range(start + 1, n):  # stable insertion sort by t
                t = sf[CS_T, j]
                p = si[CS_P, j]
                local = si[CS_L, j]
                u = sf[CS_U, j]
                v = sf[CS_V, j]
                k = j - 1
                while k >= start and sf[CS_T, k] > t:
                    sf[CS_T, k + 1] = sf[CS_T, k]
                    si[CS_P, k + 1] = si[CS_P, k]
                    si[CS_L, k + 1] = si[CS_L, k]
                    sf[CS_U, k + 1] = sf[CS_U, k]
                    sf[CS_V, k + 1] = sf[CS_V, k]
                    k -= 1
                sf[CS_T, k + 1] = t
                si[CS_P, k + 1] = p
                si[CS_L, k + 1] = local
                sf[CS_U, k + 1] = u
                sf[CS_V, k + 1] = v
            mid = csg[node, CSG_MID]
            op = csg[node, CSG_OP]
            inl = False
            inr = False
            kept = start
            for j in range(start, n):
                lhit = si[CS_P, j] < mid
                if csg_allowed(op, lhit, inl, inr):
                    sf[CS_T, kept] = sf[CS_T, j]
                    si[CS_P, kept] = si[CS_P, j]
                    si[CS_L, kept] = si[CS_L, j]
                    sf[CS_U, kept] = sf[CS_U, j]
                    sf[CS_V, kept] = sf[CS_V, j]
                    kept += 1
                if lhit:
                    inl = not inl
                else:
                    inr = not inr
            n = kept
            node += 1
    return n


@njit(**INLINE)
def nearest_hit(pf, pi, items, boxes, csg, ox, oy, oz, dx, dy, dz, eps, sf, si):
    """Chapters 5 and 7: the hit: (t, primitive, index in its list, u, v); primitive -1
    when the ray hits nothing."""
    best_t = INF
    best_p = -1
    best_l = 0
    best_u = ZERO
    best_v = ZERO
    i = 0
    n_items = items.shape[0]
    while i < n_items:
        kind = items[i, ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i, ITEM_A]
            found, t, local, u, v = first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, best_t)
            if found:
                best_t, best_p, best_l, best_u, best_v = t, p, local, u, v
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, i, ox, oy, oz, ONE / dx, ONE / dy, ONE / dz, ZERO, best_t):
                i += 1
            else:
                i = items[i, ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            m = csg_collect(pf, pi, items, csg, i, ox, oy, oz, dx, dy, dz, eps, sf, si)
            for j in range(m):
                t = sf[CS_T, j]
                if t >= ZERO:
                    if t < best_t:
                        best_t, best_p, best_l, best_u, best_v = (
                            t,
                            si[CS_P, j],
                            si[CS_L, j],
                            sf[CS_U, j],
                            sf[CS_V, j],
                        )
                    break  # the list is sorted: its first non-negative t is its hit
            i += 1
        else:
            i += 1
    return best_t, best_p, best_l, best_u, best_v


@njit(**INLINE)
def shadowed(pf, pi, items, boxes, csg, ox, oy, oz, dx, dy, dz, distance, eps, sf, si):
    """Chapter 8: does a shadow-casting object meet the ray at some t in [0, distance)?
    The primitive that answered yes last time (on this thread) is asked first: neighbouring
    pixels usually share their occluder. (Any occluder gives the same answer.)"""
    last = si[MEMO, 0]
    if last >= 0:
        found, _, _, _, _ = first_hit_in(pf, pi, last, ox, oy, oz, dx, dy, dz, eps, distance)
        if found:
            return True
    i = 0
    n_items = items.shape[0]
    while i < n_items:
        kind = items[i, ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i, ITEM_A]
            if pi[p, CASTS_SHADOW] != 0 and p != last:
                found, _, _, _, _ = first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, distance)
                if found:
                    si[MEMO, 0] = p
                    return True
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, i, ox, oy, oz, ONE / dx, ONE / dy, ONE / dz, ZERO, distance):
                i += 1
            else:
                i = items[i, ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            m = csg_collect(pf, pi, items, csg, i, ox, oy, oz, dx, dy, dz, eps, sf, si)
            for j in range(m):
                t = sf[CS_T, j]
                if t >= ZERO and t < distance and pi[si[CS_P, j], CASTS_SHADOW] != 0:
                    return True
            i += 1
        else:
            i += 1
    return False


@njit(**INLINE)
def before(t, p, local, t_hit, p_hit, l_hit):
    """Does intersection (t, p, local) come before the hit in the sorted list? The hit's
    own entry never does, even if this pass computed its t a little differently (fastmath
    may compile the two passes' arithmetic differently)."""
    if p == p_hit:
        if local == l_hit:
            return False
        if t != t_hit:
            return t < t_hit
        return local < l_hit
    if t != t_hit:
        return t < t_hit
    return p < p_hit


@njit(**INLINE)
def later(t, p, local, bt, bp, bl):
    """Does intersection (t, p, local) come after (bt, bp, bl) in the sorted list?"""
    if t != bt:
        return t > bt
    if p != bp:
        return p > bp
    return local > bl


@njit(**INLINE)
def refractive_indices(
    pf, pi, items, boxes, csg, ox, oy, oz, dx, dy, dz, eps, t_hit, p_hit, l_hit, sf, si
):
    """Chapter 11: (n1, n2) at the hit (t_hit, p_hit, l_hit), from every intersection along
    the ray (negative t included, as in the reference's list)."""
    other_t = -INF  # the latest-entered container other than the hit's object
    other_p = -1
    other_l = -1
    hit_inside = False  # is the hit's object a container just before the hit?
    hit_t = -INF
    hit_l = -1
    i = 0
    n_items = items.shape[0]
    while i < n_items:
        kind = items[i, ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i, ITEM_A]
            if starts_after(pf, p, ox, oy, oz, dx, dy, dz, t_hit):
                i += 1
                continue
            n, t0, t1, t2, t3, _, _ = intersect_prim(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, INF)
            count = 0
            last_t = -INF
            last_l = -1
            for local in range(n):
                t = nth(t0, t1, t2, t3, local)
                if before(t, p, local, t_hit, p_hit, l_hit):
                    count += 1
                    if later(t, p, local, last_t, p, last_l):
                        last_t = t
                        last_l = local
            if count % 2 == 1:
                if p == p_hit:
                    hit_inside = True
                    hit_t = last_t
                    hit_l = last_l
                elif later(last_t, p, last_l, other_t, other_p, other_l):
                    other_t, other_p, other_l = last_t, p, last_l
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, i, ox, oy, oz, ONE / dx, ONE / dy, ONE / dz, -INF, t_hit):
                i += 1
            else:
                i = items[i, ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            m = csg_collect(pf, pi, items, csg, i, ox, oy, oz, dx, dy, dz, eps, sf, si)
            first = items[i, ITEM_C]
            for q in range(first, items[i, ITEM_D]):
                si[CS_COUNT, q - first] = 0
            for j in range(m):
                q = si[CS_P, j]
                if before(sf[CS_T, j], q, si[CS_L, j], t_hit, p_hit, l_hit):
                    si[CS_COUNT, q - first] += 1
                    sf[CS_LAST_T, q - first] = sf[CS_T, j]  # the list is sorted: the latest is last
                    si[CS_LAST_L, q - first] = si[CS_L, j]
            for q in range(first, items[i, ITEM_D]):
                if si[CS_COUNT, q - first] % 2 == 1:
                    last_t = sf[CS_LAST_T, q - first]
                    last_l = si[CS_LAST_L, q - first]
                    if q == p_hit:
                        hit_inside = True
                        hit_t = last_t
                        hit_l = last_l
                    elif later(last_t, q, last_l, other_t, other_p, other_l):
                        other_t, other_p, other_l = last_t, q, last_l
            i += 1
        else:
            i += 1
    outside = pf[other_p, REFRACTIVE_INDEX] if other_p >= 0 else ONE
    if hit_inside:
        if other_p >= 0 and later(other_t, other_p, other_l, hit_t, p_hit, hit_l):
            return outside, outside
        return pf[p_hit, REFRACTIVE_INDEX], outside
    return outside, pf[p_hit, REFRACTIVE_INDEX]


@njit(**INLINE)
def push(stack, top, ox, oy, oz, dx, dy, dz, weight, remaining):
    stack[top, 0] = ox
    stack[top, 1] = oy
    stack[top, 2] = oz
    stack[top, 3] = dx
    stack[top, 4] = dy
    stack[top, 5] = dz
    stack[top, 6] = weight
    stack[top, 7] = remaining
    return top + 1


@njit(**INLINE)
def shade_and_push(
    pf,
    pi,
    items,
    boxes,
    csg,
    light,
    p,
    eyev,
    normalv,
    over,
    under,
    reflectv,
    n1,
    n2,
    weight,
    remaining,
    eps,
    stack,
    top,
    sf,
    si,
):
    """Chapters 7, 8 and 11 (``shade_hit``): the surface color at a prepared hit, times
    ``weight``; the reflected and refracted rays it spawns are pushed on the stack with
    their weights. Returns (r, g, b, new top)."""
    ex, ey, ez = eyev
    nx, ny, nz = normalv
    over_x, over_y, over_z = over
    under_x, under_y, under_z = under
    rx, ry, rz = reflectv
    lx, ly, lz, distance = towards_light(light, over_x, over_y, over_z)
    light_dot_normal = lx * nx + ly * ny + lz * nz
    lit = True
    if HAS_SHADOWS and light_dot_normal >= ZERO:  # the light is in front of the surface
        if COUNT_RAYS:
            si[RAYS, 1] += 1
        lit = not shadowed(
            pf, pi, items, boxes, csg, over_x, over_y, over_z, lx, ly, lz, distance, eps, sf, si
        )
    sr, sg, sb = phong(
        pf,
        pi,
        p,
        light,
        over_x,
        over_y,
        over_z,
        ex,
        ey,
        ez,
        nx,
        ny,
        nz,
        lx,
        ly,
        lz,
        light_dot_normal,
        lit,
    )
    if remaining > 0 and (HAS_REFLECTION or HAS_REFRACTION):
        reflective = pf[p, REFLECTIVE]
        transparency = pf[p, TRANSPARENCY]
        reflected_weight = weight * reflective
        refracted_weight = weight * transparency
        if HAS_SCHLICK and reflective > ZERO and transparency > ZERO:
            reflectance = schlick_at(ex, ey, ez, nx, ny, nz, n1, n2)
            reflected_weight = reflected_weight * reflectance
            refracted_weight = refracted_weight * (ONE - reflectance)
        if HAS_REFLECTION and reflective != ZERO and reflected_weight != ZERO:
            top = push(
                stack, top, over_x, over_y, over_z, rx, ry, rz, reflected_weight, remaining - 1
            )
        if HAS_REFRACTION and transparency != ZERO and refracted_weight != ZERO:
            ok, tx, ty, tz = refraction(ex, ey, ez, nx, ny, nz, n1, n2)
            if ok:
                top = push(
                    stack,
                    top,
                    under_x,
                    under_y,
                    under_z,
                    tx,
                    ty,
                    tz,
                    refracted_weight,
                    remaining - 1,
                )
    return sr * weight, sg * weight, sb * weight, top


@njit(**INLINE)
def prepare(pf, pi, p, ox, oy, oz, dx, dy, dz, t, u, v, eps):
    """Chapters 7, 8 and 11 (``prepare_computations`` without n1/n2): point, eyev, normalv,
    inside, over_point, under_point, reflectv."""
    px = ox + dx * t
    py = oy + dy * t
    pz = oz + dz * t
    ex = -dx
    ey = -dy
    ez = -dz
    nx, ny, nz = world_normal(pf, pi, p, px, py, pz, u, v, eps)
    inside = nx * ex + ny * ey + nz * ez < ZERO
    if inside:
        nx = -nx
        ny = -ny
        nz = -nz
    ox_ = nx * eps
    oy_ = ny * eps
    oz_ = nz * eps
    twice = dx * nx + dy * ny + dz * nz
    return (
        px, py, pz, ex, ey, ez, nx, ny, nz, inside,
        px + ox_, py + oy_, pz + oz_, px - ox_, py - oy_, pz - oz_,
        dx - nx * F(2.0) * twice, dy - ny * F(2.0) * twice, dz - nz * F(2.0) * twice,
    )  # fmt: skip


@njit(**INLINE)
def drain(pf, pi, items, boxes, csg, light, eps, stack, top, r, g, b, sf, si):
    """Chapter 7 (``color_at``, iteratively): trace every ray on the stack and everything it
    spawns; returns the sum of their weighted surface colors added to (r, g, b)."""
    while top > 0:
        top -= 1
        ox = stack[top, 0]
        oy = stack[top, 1]
        oz = stack[top, 2]
        dx = stack[top, 3]
        dy = stack[top, 4]
        dz = stack[top, 5]
        weight = stack[top, 6]
        remaining = int(stack[top, 7])
        if COUNT_RAYS:
            si[RAYS, 0] += 1
        t, p, local, u, v = nearest_hit(
            pf, pi, items, boxes, csg, ox, oy, oz, dx, dy, dz, eps, sf, si
        )
        if p < 0:
            continue
        (_px, _py, _pz, ex, ey, ez, nx, ny, nz, _inside, over_x, over_y, over_z, under_x, under_y,
         under_z, rx, ry, rz) = prepare(pf, pi, p, ox, oy, oz, dx, dy, dz, t, u, v, eps)  # fmt: skip
        n1 = ONE
        n2 = ONE
        if HAS_REFRACTION and remaining > 0 and pf[p, TRANSPARENCY] > ZERO:
            if COUNT_RAYS:
                si[RAYS, 2] += 1
            n1, n2 = refractive_indices(
                pf, pi, items, boxes, csg, ox, oy, oz, dx, dy, dz, eps, t, p, local, sf, si
            )
        sr, sg, sb, top = shade_and_push(
            pf,
            pi,
            items,
            boxes,
            csg,
            light,
            p,
            (ex, ey, ez),
            (nx, ny, nz),
            (over_x, over_y, over_z),
            (under_x, under_y, under_z),
            (rx, ry, rz),
            n1,
            n2,
            weight,
            remaining,
            eps,
            stack,
            top,
            sf,
            si,
        )
        r += sr
        g += sg
        b += sb
    return r, g, b


@njit(**INLINE)
def camera_ray(cam, px, py):
    """Chapter 7: ``ray_for_pixel``: the ray from the camera through (px, py)."""
    xoffset = (px + F(0.5)) * cam[CAM_PIXEL_SIZE]
    yoffset = (py + F(0.5)) * cam[CAM_PIXEL_SIZE]
    wx = cam[CAM_HALF_WIDTH] - xoffset
    wy = cam[CAM_HALF_HEIGHT] - yoffset
    m = CAM_INV
    zero = ZERO
    pixel_x = cam[m + 0] * wx + cam[m + 1] * wy + cam[m + 2] * -ONE + cam[m + 3]
    pixel_y = cam[m + 4] * wx + cam[m + 5] * wy + cam[m + 6] * -ONE + cam[m + 7]
    pixel_z = cam[m + 8] * wx + cam[m + 9] * wy + cam[m + 10] * -ONE + cam[m + 11]
    ox = cam[m + 0] * zero + cam[m + 1] * zero + cam[m + 2] * zero + cam[m + 3]
    oy = cam[m + 4] * zero + cam[m + 5] * zero + cam[m + 6] * zero + cam[m + 7]
    oz = cam[m + 8] * zero + cam[m + 9] * zero + cam[m + 10] * zero + cam[m + 11]
    vx = pixel_x - ox
    vy = pixel_y - oy
    vz = pixel_z - oz
    length = math.sqrt(vx * vx + vy * vy + vz * vz)
    return ox, oy, oz, vx / length, vy / length, vz / length


@njit(**INLINE)
def mix64(z):
    """splitmix64's output function (``raytracer.sampling.mix64``)."""
    z = (z ^ (z >> np.uint64(30))) * MIX1
    z = (z ^ (z >> np.uint64(27))) * MIX2
    return z ^ (z >> np.uint64(31))


@njit(**INLINE)
def sample_offset(seed_key, x, y, i):
    """``raytracer.sampling.sample_offset`` bit for bit; ``seed_key`` is seed * GAMMA
    mod 2**64, computed once per render."""
    key = seed_key ^ (
        (np.uint64(y) << np.uint64(34)) | (np.uint64(x) << np.uint64(20)) | np.uint64(i)
    )
    first = mix64(key + GAMMA)
    second = mix64(key + GAMMA2)
    return np.float64(first >> np.uint64(11)) * UNIT53, np.float64(second >> np.uint64(11)) * UNIT53


@njit(**HOT)
def render_rows(
    out,
    k,
    step,
    cam,
    pf,
    pi,
    items,
    boxes,
    csg,
    light,
    depth,
    samples,
    seed_key,
    eps,
    stack,
    sf,
    si,
):
    """Chapter 7: render rows k, k + step, k + 2 step ... of ``out`` (height, width, 3), with
    one thread's scratch: ``stack`` (depth + 2, STACK_WIDTH), ``sf`` and ``si``."""
    eps = F(eps)
    height = out.shape[0]
    width = out.shape[1]
    scale = ONE / F(samples)
    if COUNT_RAYS:
        si[RAYS, 0] = 0
        si[RAYS, 1] = 0
        si[RAYS, 2] = 0
    for y in range(k, height, step):
        for x in range(width):
            r = ZERO
            g = ZERO
            b = ZERO
            for i in range(samples):
                if samples == 1:
                    px = F(x)
                    py = F(y)
                else:
                    sx, sy = sample_offset(seed_key, x, y, i)
                    px = F(np.float64(x) + sx - 0.5)
                    py = F(np.float64(y) + sy - 0.5)
                ox, oy, oz, dx, dy, dz = camera_ray(cam, px, py)
                top = push(stack, 0, ox, oy, oz, dx, dy, dz, ONE, depth)
                cr, cg, cb = drain(
                    pf, pi, items, boxes, csg, light, eps, stack, top, ZERO, ZERO, ZERO, sf, si
                )
                r += cr
                g += cg
                b += cb
            if samples == 1:
                out[y, x, 0] = r
                out[y, x, 1] = g
                out[y, x, 2] = b
            else:
                out[y, x, 0] = r * scale
                out[y, x, 1] = g * scale
                out[y, x, 2] = b * scale
    return 0


@njit(**ENTRY)
def render_serial(
    out,
    cam,
    pf,
    pi,
    items,
    boxes,
    csg,
    light,
    depth,
    samples,
    seed_key,
    eps,
    cs_size,
    cs_prims,
    counts,
):
    """Chapter 7: render on the calling thread (its scratch allocated once); with
    COUNT_RAYS, ``counts[0]`` gets (rays traced, shadow rays)."""
    stack = np.empty((depth + 2, STACK_WIDTH), F)
    sf, si = scratch(cs_size, cs_prims)
    render_rows(
        out,
        0,
        1,
        cam,
        pf,
        pi,
        items,
        boxes,
        csg,
        light,
        depth,
        samples,
        seed_key,
        eps,
        stack,
        sf,
        si,
    )
    if COUNT_RAYS:
        counts[0, 0] = si[RAYS, 0]
        counts[0, 1] = si[RAYS, 1]
        counts[0, 2] = si[RAYS, 2]
    return 0


@njit(parallel=True, **ENTRY)
def render_parallel(
    out,
    step,
    cam,
    pf,
    pi,
    items,
    boxes,
    csg,
    light,
    depth,
    samples,
    seed_key,
    eps,
    cs_size,
    cs_prims,
    counts,
):
    """Chapter 7: render on ``step`` threads, thread k taking rows k, k + step, ...; each
    thread allocates its scratch once. With COUNT_RAYS, ``counts[k]`` gets thread k's
    (rays traced, shadow rays)."""
    for k in prange(step):
        stack = np.empty((depth + 2, STACK_WIDTH), F)
        sf, si = scratch(cs_size, cs_prims)
        render_rows(
            out,
            k,
            step,
            cam,
            pf,
            pi,
            items,
            boxes,
            csg,
            light,
            depth,
            samples,
            seed_key,
            eps,
            stack,
            sf,
            si,
        )
        if COUNT_RAYS:
            counts[k, 0] = si[RAYS, 0]
            counts[k, 1] = si[RAYS, 1]
            counts[k, 2] = si[RAYS, 2]
    return 0
