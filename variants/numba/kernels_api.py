"""Kernel template, part 4: the book's functions as compiled entry points, so the scenarios
run through the same code as the render (``variants.numba.api`` packs the arguments, calls
these and converts the results back to the reference's values).

Vectors travel as separate floats; flat arrays hold a packed world or shape (``layout``,
``Packed.flat``).
"""

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    HAS_BOXES,
    HAS_CSG,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    ONE,
    ZERO,
    box_range,
    nth,
    to_object_point,
    to_object_vector,
    to_world_normal,
)
from variants.numba.kernels_hits import (
    csg_allowed,
    csg_collect,
    scratch,
    shadowed,
)
from variants.numba.kernels_prims import (
    intersect_prim,
    local_normal,
    world_normal,
)
from variants.numba.kernels_shading import (
    light_jitter,
    lighting_at,
    local_pattern,
    pattern_point,
    refraction,
    schlick_at,
)
from variants.numba.kernels_trace import (
    ENTRY,
    camera_ray,
    drain,
    light_intensity,
    prepare,
    push,
    shade_and_push,
)
from variants.numba.layout import (
    B_PRIM,
    CS_P,
    CS_T,
    CS_U,
    CS_V,
    I_BOX,
    I_CSG,
    I_PRIM,
    INV,
    ITEM_A,
    ITEM_C,
    ITEM_D,
    ITEM_TYPE,
    NF,
    NITEM,
    NLIGHT,
    NSF,
    NSI,
    REFLECTIVE,
    STACK_WIDTH,
    TRANSPARENCY,
)

# ---- kernel template ----

# the book's API packs every triangle in a row of its own: no compact triangles (``tg``, ``tn``)
NONE = (np.zeros(1, F), np.zeros(1, F))


@njit(**ENTRY)
def api_intersections(
    pf, pi, items, n_items, boxes, csg, balls, n_balls, ray, eps, sort, capacity, cs_size,
    cs_prims,
):  # fmt: skip
    """Chapters 5, 7, 14, 16 (``intersect``, ``local_intersect``, ``intersect_world``): every
    intersection of ``ray`` with the packed shapes (the items', then the balls'), sorted
    by t (stably) when ``sort``; returns (count, t, primitive, u, v, reached): reached[p]
    is 1 when the ray got past every box around primitive p (the test shape's saved ray)."""
    eps = F(eps)
    out_t = np.empty(capacity, F)
    out_u = np.empty(capacity, F)
    out_v = np.empty(capacity, F)
    out_p = np.empty(capacity, np.int64)
    reached = np.zeros(max(pf.shape[0] // NF, 1), np.int8)
    s = scratch(cs_size, cs_prims, n_balls)
    sf, si, _ = s
    tex = (np.zeros(1, np.int64), np.zeros(1, F))
    w = (pf, pi, items, n_items, boxes, csg, balls, n_balls, np.zeros(NLIGHT, F), 0, tex, NONE)
    ox, oy, oz, dx, dy, dz = F(ray[0]), F(ray[1]), F(ray[2]), F(ray[3]), F(ray[4]), F(ray[5])
    n = 0
    i = 0
    while i < n_items:
        kind = items[i * NITEM + ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i * NITEM + ITEM_A]
            reached[p] = 1
            m, t0, t1, t2, t3, u, v = intersect_prim(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, INF)
            for local in range(m):
                out_t[n] = nth(t0, t1, t2, t3, local)
                out_p[n] = p
                out_u[n] = u
                out_v[n] = v
                n += 1
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            b = items[i * NITEM + ITEM_D]
            if box_range(boxes, b, ox, oy, oz, ONE / dx, ONE / dy, ONE / dz, -INF, INF):
                i += 1
            else:
                i = items[i * NITEM + ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            for q in range(items[i * NITEM + ITEM_C], items[i * NITEM + ITEM_D]):
                reached[q] = 1
            m = csg_collect(w, s, i, ox, oy, oz, dx, dy, dz, eps)
            for j in range(m):
                out_t[n] = sf[j * NSF + CS_T]
                out_p[n] = si[j * NSI + CS_P]
                out_u[n] = sf[j * NSF + CS_U]
                out_v[n] = sf[j * NSF + CS_V]
                n += 1
            i += 1
        else:
            i += 1
    for j in range(n_balls):
        p = int(balls[B_PRIM * n_balls + j])
        reached[p] = 1
        m, t0, t1, _, _, _, _ = intersect_prim(pf, pi, p, ox, oy, oz, dx, dy, dz, eps, INF)
        for local in range(m):
            out_t[n] = t0 if local == 0 else t1
            out_p[n] = p
            out_u[n] = ZERO
            out_v[n] = ZERO
            n += 1
    if sort:
        # insertion sort by t, then primitive row (the reference's order for ties: rows
        # follow the world's order), then the order found (a primitive's own list)
        for j in range(1, n):
            t = out_t[j]
            p = out_p[j]
            u = out_u[j]
            v = out_v[j]
            k = j - 1
            while k >= 0 and (out_t[k] > t or (out_t[k] == t and out_p[k] > p)):
                out_t[k + 1] = out_t[k]
                out_p[k + 1] = out_p[k]
                out_u[k + 1] = out_u[k]
                out_v[k + 1] = out_v[k]
                k -= 1
            out_t[k + 1] = t
            out_p[k + 1] = p
            out_u[k + 1] = u
            out_v[k + 1] = v
    return n, out_t, out_p, out_u, out_v, reached


@njit(**ENTRY)
def api_local_ray(pf, p, ray):
    """Chapter 5 (``transform(ray, inverse)``): the ray in primitive p's object space."""
    ox, oy, oz = to_object_point(pf, p, F(ray[0]), F(ray[1]), F(ray[2]))
    dx, dy, dz = to_object_vector(pf, p, F(ray[3]), F(ray[4]), F(ray[5]))
    return ox, oy, oz, dx, dy, dz


@njit(**ENTRY)
def api_normal(pf, pi, p, x, y, z, u, v, eps, in_world):
    """Chapters 6, 9, 14, 15 (``normal_at`` when ``in_world``, else ``local_normal_at``)."""
    if in_world:
        return world_normal(pf, pi, p, F(x), F(y), F(z), F(u), F(v), F(eps), NONE, 0)
    return local_normal(pf, pi, p, F(x), F(y), F(z), F(u), F(v), F(eps), NONE, 0)


@njit(**ENTRY)
def api_world_to_object(pf, p, x, y, z, w):
    """Chapter 14: ``world_to_object`` of the tuple (x, y, z, w) (w is 1 for a point)."""
    vx, vy, vz = to_object_vector(pf, p, F(x), F(y), F(z))
    w = F(w)
    m = p * NF + INV
    return vx + pf[m + 3] * w, vy + pf[m + 7] * w, vz + pf[m + 11] * w


@njit(**ENTRY)
def api_normal_to_world(pf, p, x, y, z):
    """Chapter 14: ``normal_to_world``."""
    return to_world_normal(pf, p, F(x), F(y), F(z))


@njit(**ENTRY)
def api_lighting(pf, pi, ti, tf, p, lights, n_lights, k, key, point, eyev, normalv, intensity,
                 ambient_on):  # fmt: skip
    """Chapters 6, 8, 10 and the bonus chapter on soft shadows: ``lighting`` with light k
    of the packed ``lights`` and the fraction ``intensity`` of it that arrives (1: lit, 0:
    in shadow; ``ambient_on`` False: without the ambient term); ``key``: the sample's, for
    a jittered area light."""
    return lighting_at(
        pf, pi, (ti, tf), p, lights, k * NLIGHT, n_lights * NLIGHT, k, key, F(point[0]),
        F(point[1]), F(point[2]), F(eyev[0]), F(eyev[1]), F(eyev[2]), F(normalv[0]),
        F(normalv[1]), F(normalv[2]), F(intensity), ambient_on,
    )  # fmt: skip


@njit(**ENTRY)
def api_pattern(pf, pi, ti, tf, p, x, y, z, on_shape):
    """Chapter 10: ``pattern_at`` (a pattern-space point), or ``pattern_at_shape`` (a
    world-space point, through the shape's and the pattern's transforms) when
    ``on_shape``."""
    x = F(x)
    y = F(y)
    z = F(z)
    if on_shape:
        ox, oy, oz = to_object_point(pf, p, x, y, z)
        x, y, z = pattern_point(pf, p, ox, oy, oz)
    return local_pattern(pf, pi, (ti, tf), p, x, y, z)


@njit(**ENTRY)
def api_prepare(pf, pi, p, ray, t, u, v, eps):
    """Chapters 7, 8, 11: ``prepare_computations`` without n1 and n2."""
    return prepare(
        pf, pi, p, F(ray[0]), F(ray[1]), F(ray[2]), F(ray[3]), F(ray[4]), F(ray[5]), F(t),
        F(u), F(v), F(eps), NONE, 0,
    )  # fmt: skip


@njit(**ENTRY)
def api_schlick(eyev, normalv, n1, n2):
    """Chapter 11: ``schlick``."""
    return schlick_at(
        F(eyev[0]), F(eyev[1]), F(eyev[2]), F(normalv[0]), F(normalv[1]), F(normalv[2]),
        F(n1), F(n2),
    )  # fmt: skip


@njit(**ENTRY)
def api_shade(
    pf, pi, items, n_items, boxes, csg, balls, n_balls, lights, n_lights, ti, tf, p, comps,
    mode, remaining, eps, cs_size, cs_prims, key,
):  # fmt: skip
    """Chapters 7, 8, 11, with a prepared hit ``comps`` (eyev, normalv, over_point,
    under_point, reflectv, n1, n2 of the hit on primitive p):

    mode 0: ``shade_hit``; 1: ``reflected_color``; 2: ``refracted_color``;
    3: ``color_at`` (comps holds the ray's origin and direction); 4: ``is_shadowed`` (comps
    holds the point and the light's position; the result is 1 or 0 in red); 5: the bonus
    chapter's ``intensity_at`` (comps holds the point; p is the light's index; the result
    in red). ``key``: the sample's (``sample_key``), for jittered area lights.
    """
    eps = F(eps)
    stack = np.empty((max(remaining, 0) + 3) * STACK_WIDTH, F)
    s = scratch(cs_size, cs_prims, n_balls)
    w = (pf, pi, items, n_items, boxes, csg, balls, n_balls, lights, n_lights, (ti, tf), NONE)
    c = np.empty(comps.shape[0], F)
    for j in range(comps.shape[0]):
        c[j] = F(comps[j])
    r = ZERO
    g = ZERO
    b = ZERO
    top = 0
    if mode == 0:
        r, g, b, top = shade_and_push(
            w, s, p, (c[0], c[1], c[2]), (c[3], c[4], c[5]), (c[6], c[7], c[8]),
            (c[9], c[10], c[11]), (c[12], c[13], c[14]), c[15], c[16], ONE, remaining, eps,
            stack, top, key,
        )  # fmt: skip
    elif mode == 1:
        reflective = pf[p * NF + REFLECTIVE]
        if reflective != ZERO and remaining > 0:
            top = push(stack, top, c[6], c[7], c[8], c[12], c[13], c[14], reflective, remaining - 1)
    elif mode == 2:
        transparency = pf[p * NF + TRANSPARENCY]
        if transparency != ZERO and remaining > 0:
            ok, tx, ty, tz = refraction(c[0], c[1], c[2], c[3], c[4], c[5], c[15], c[16])
            if ok:
                top = push(stack, top, c[9], c[10], c[11], tx, ty, tz, transparency, remaining - 1)
    elif mode == 3:
        top = push(stack, top, c[0], c[1], c[2], c[3], c[4], c[5], ONE, remaining)
    elif mode == 4:
        hit = shadowed(w, s, c[0], c[1], c[2], c[3] - c[0], c[4] - c[1], c[5] - c[2], eps, 0)
        return ONE if hit else ZERO, ZERO, ZERO
    else:
        return light_intensity(w, s, p, c[0], c[1], c[2], eps, key), ZERO, ZERO
    return drain(w, s, eps, stack, top, r, g, b, key)


@njit(**ENTRY)
def api_camera_ray(cam, px, py):
    """Chapter 7: ``ray_for_pixel``."""
    return camera_ray(cam, F(px), F(py))


@njit(**ENTRY)
def api_filter(op, lhits):
    """Chapter 16: ``filter_intersections``: which entries of a sorted list survive
    operation ``op``, given for each whether it hit the left operand."""
    keep = np.zeros(lhits.shape[0], np.bool_)
    inl = False
    inr = False
    for j in range(lhits.shape[0]):
        lhit = lhits[j]
        keep[j] = csg_allowed(op, lhit, inl, inr)
        if lhit:
            inl = not inl
        else:
            inr = not inr
    return keep


@njit(**ENTRY)
def api_allowed(op, lhit, inl, inr):
    """Chapter 16: ``intersection_allowed``."""
    return csg_allowed(op, lhit, inl, inr)


@njit(**ENTRY)
def api_light_jitter(keys, lights, us, vs):
    """The bonus chapter on soft shadows: ``light_jitter`` as the render computes it, for
    each (sample key, light index, u, v): an n x 2 array of (ju, jv)."""
    n = keys.shape[0]
    out = np.empty((n, 2), np.float64)
    for j in range(n):
        ju, jv = light_jitter(keys[j], lights[j], us[j], vs[j])
        out[j, 0] = ju
        out[j, 1] = jv
    return out
