"""Kernel template, part 3: rays through the packed world (chapters 7, 8, 11, 14, 16), the
explicit stack that replaces the book's recursion, camera rays and samples, and the render.

- ``nearest_hit`` tracks the closest non-negative t instead of building a sorted list; ties go
  to the earlier primitive, as the reference's stable sort does. The items are a flat list,
  a group's boxes or a bounding-volume hierarchy (``variants.numba.bvh``), all walked by
  one loop without recursion (a box's item says where to go when the ray misses it). The
  balls (``layout``) come after the items: one vectorized pass says which ones the ray can
  reach at all (``ball_reach``), then those get the exact test.
- ``shadowed`` counts, in one vectorized pass, the shadow-casting balls the ray can reach,
  and tests them exactly only when there are any; then the items. Its shadow ray is the
  book's, a unit vector and the distance to the light (along the unnormalized vector the
  book's EPSILON parallel tests would see a direction |v| times too long).
- ``refractive_indices`` finds n1 and n2 without a sorted list: an object is in the book's
  ``containers`` when an odd number of its intersections come before the hit, and the last
  of them entered is the one whose latest such intersection comes last. A ball other than
  the hit's is skipped when the hit point is well outside it (it cannot be a container).
- ``drain`` is ``color_at`` without recursion: a stack of (ray, weight, remaining), where the
  weight is the product of the reflective / transparency / Schlick factors on the way.
- ``render_rows`` renders rows k, k + T, k + 2T ... of a region (x0, y0, x1, y1) of the
  image for thread k of T (the top and bottom of an image cost very different amounts, so
  contiguous blocks would leave one thread idle), making each sample's camera ray before
  tracing the previous one (the processor overlaps them); ``make_render_entry`` compiles it
  as a C function over raw pointers, which ``variants.numba.specialize`` links into a
  shared library and ``render`` calls from T Python threads through ctypes (which lets go
  of the GIL).

- ``light_intensity`` is the soft shadows chapter's ``intensity_at`` for an area light: a
  shadow ray to every cell's point (jittered by the sample's key, which ``render_rows``
  computes once per sample and every bounce of it shares, or placed by the light's
  sequence); ``shade_and_push`` then lights the point from every cell (``area_phong``).

A world travels as one tuple ``w`` = (pf, pi, items, n_items, boxes, csg, balls, n_balls,
lights, n_lights, (ti, tf), (tg, tn)) and a thread's scratch as ``s`` = (sf, si, tb) (see
``layout``). A compact triangle's hit is (its run's row, its number in ``tg``), which
sorts ties as the world's order does. The scratch holds one CSG
tree's intersection list and per primitive of the tree where its entries start and, for
n1/n2, how many come before the hit; the shadow memos (one per light) and ray counters;
the hit ray's stack of item ranges; one value per ball.

No function takes more than 30 arguments: Python compiles longer calls through a tuple,
which numba's inliner refuses.
"""

# ruff: noqa: E501
import math
from typing import Any

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    COUNT_RAYS,
    FASTMATH,
    HAS_AREA_LIGHTS,
    HAS_BOXES,
    HAS_CSG,
    HAS_REFLECTION,
    HAS_REFRACTION,
    HAS_SCHLICK,
    HAS_SHADOWS,
    HAS_SPHERE,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    ZERO,
    ball_first,
    ball_roots,
    box_range,
    compact_all,
    compact_first_hit,
    first_hit_in,
    hit_normal,
    intersect_prim,
    nth,
    starts_after,
)
from variants.numba.kernels_shading import (
    GAMMA,
    UNIT53,
    area_phong,
    cell_point,
    mix64,
    phong,
    refraction,
    schlick_at,
    surface_color,
)
from variants.numba.layout import (
    B_PRIM,
    B_R2,
    B_SHADOW,
    B_X,
    B_Y,
    B_Z,
    BV_FROM,
    BV_TO,
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
    I_TRI,
    ITEM_A,
    ITEM_B,
    ITEM_C,
    ITEM_D,
    ITEM_TYPE,
    LIGHT_USTEPS,
    LIGHT_VSTEPS,
    MEMO,
    MIN_SCRATCH,
    NCSG,
    NF,
    NI,
    NITEM,
    NLIGHT,
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
GAMMA2 = np.uint64((2 * 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF)


@njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def scratch(cs_size, cs_prims, n_balls):
    """One thread's scratch (sf, si, tb) for a book-API call (the render's come from
    Python): CSG lists, the shadow memo and ray counters, and one t per ball."""
    size = max(cs_size, cs_prims, MIN_SCRATCH)
    si = np.zeros(size * NSI, np.int64)
    for j in range(size):
        si[j * NSI + MEMO] = -1
    return np.zeros(size * NSF, F), si, np.zeros(max(n_balls, 1), F)


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
def move_entry(sf, si, source, target):
    """Copy entry ``source`` of a CSG list to ``target`` (t, u, v, primitive, index)."""
    sf[target * NSF + CS_T] = sf[source * NSF + CS_T]
    sf[target * NSF + CS_U] = sf[source * NSF + CS_U]
    sf[target * NSF + CS_V] = sf[source * NSF + CS_V]
    si[target * NSI + CS_P] = si[source * NSI + CS_P]
    si[target * NSI + CS_L] = si[source * NSI + CS_L]


@njit(**INLINE)
def csg_collect(w, s, i, ox, oy, oz, dx, dy, dz, eps):
    """Chapter 16: the intersection list of CSG item i, sorted and filtered, in cs_*; returns
    its length. Operations are applied in post-order, each to the stretch of the list its
    primitives occupy, so nested CSG trees need no recursion."""
    pf, pi, items, _, _, csg, _, _, _, _, _, _ = w
    sf, si, _ = s
    node = items[i * NITEM + ITEM_A]
    last_node = items[i * NITEM + ITEM_B]
    first = items[i * NITEM + ITEM_C]
    n = 0
    for q in range(first, items[i * NITEM + ITEM_D]):
        si[(q - first) * NSI + CS_START] = n
        m, t0, t1, t2, t3, u, v = intersect_prim(pf, pi, q, ox, oy, oz, dx, dy, dz, eps, INF)
        for local in range(m):
            sf[n * NSF + CS_T] = nth(t0, t1, t2, t3, local)
            sf[n * NSF + CS_U] = u
            sf[n * NSF + CS_V] = v
            si[n * NSI + CS_P] = q
            si[n * NSI + CS_L] = local
            n += 1
        while node < last_node and csg[node * NCSG + CSG_END] == q + 1:
            start = si[(csg[node * NCSG + CSG_START] - first) * NSI + CS_START]
            for j in range(start + 1, n):  # stable insertion sort by t
                t = sf[j * NSF + CS_T]
                u = sf[j * NSF + CS_U]
                v = sf[j * NSF + CS_V]
                p = si[j * NSI + CS_P]
                local = si[j * NSI + CS_L]
                k = j - 1
                while k >= start and sf[k * NSF + CS_T] > t:
                    move_entry(sf, si, k, k + 1)
                    k -= 1
                sf[(k + 1) * NSF + CS_T] = t
                sf[(k + 1) * NSF + CS_U] = u
                sf[(k + 1) * NSF + CS_V] = v
                si[(k + 1) * NSI + CS_P] = p
                si[(k + 1) * NSI + CS_L] = local
            mid = csg[node * NCSG + CSG_MID]
            op = csg[node * NCSG + CSG_OP]
            inl = False
            inr = False
            kept = start
            for j in range(start, n):
                lhit = si[j * NSI + CS_P] < mid
                if csg_allowed(op, lhit, inl, inr):
                    move_entry(sf, si, j, kept)
                    kept += 1
                if lhit:
                    inl = not inl
                else:
                    inr = not inr
            n = kept
            node += 1
    return n


@njit(**INLINE)
def ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz):
    """``ball_terms`` (hb, cc) of ball j of the ball list."""
    cx = ox - balls[B_X * n_balls + j]
    cy = oy - balls[B_Y * n_balls + j]
    cz = oz - balls[B_Z * n_balls + j]
    return cx * dx + cy * dy + cz * dz, cx * cx + cy * cy + cz * cz - balls[B_R2 * n_balls + j]


@njit(**INLINE)
def ball_reach(balls, n_balls, j, ox, oy, oz, dx, dy, dz, a):
    """Chapter 5: can the ray meet ball j at some t >= 0? Returns the discriminant
    (hb² - a cc, see ``ball_terms``) when it can, else -1: the line misses the ball, or its
    origin is outside and the ball behind. Written without branches (selects), so that a
    loop over the balls becomes vector instructions; most balls stop here."""
    hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
    discriminant = hb * hb - a * cc
    ahead = discriminant >= ZERO and (cc <= ZERO or hb < ZERO)
    return discriminant if ahead else -ONE


@njit(**INLINE)
def nearest_hit(w, s, ox, oy, oz, dx, dy, dz, eps):
    """Chapters 5 and 7: the hit: (t, primitive, index in its list, u, v); primitive -1
    when the ray hits nothing. Items first, then the balls: every ball's ``ball_reach``
    at once (in ``tb``), then the exact test of those the ray can reach; ties go to the
    earlier primitive, as in the reference's stable sort, in whatever order the items
    come. A box the ray misses, or enters only beyond the nearest hit so far, sends it
    past its contents; at a hierarchy's node split along an axis the ray travels down,
    the second child is visited first (the first child and what follows the node wait
    on the range stack in ``si``), so that near hits come early and cut boxes short."""
    pf, pi, items, n_items, boxes, _, balls, n_balls, _, _, _, geo = w
    sf, si, tb = s
    a = dx * dx + dy * dy + dz * dz
    ix = ONE / dx
    iy = ONE / dy
    iz = ONE / dz
    best_t = INF
    best_p = -1
    best_l = 0
    best_u = ZERO
    best_v = ZERO
    i = 0
    end = n_items  # the items [i, end) come next; then the ranges on the stack
    top = 0
    while True:
        if i >= end:
            if not HAS_BOXES or top == 0:
                break
            top -= 1
            i = si[top * NSI + BV_FROM]
            end = si[top * NSI + BV_TO]
            continue
        kind = items[i * NITEM + ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i * NITEM + ITEM_A]
            found, t, local, u, v = first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, a, eps, best_t)
            # a tie goes to the earlier primitive, whatever order the items are in
            if found or (t == best_t and p < best_p):
                best_t, best_p, best_l, best_u, best_v = t, p, local, u, v
            i += 1
        elif kind == I_TRI:
            p = items[i * NITEM + ITEM_A]
            q = items[i * NITEM + ITEM_B]
            found, t, u, v = compact_first_hit(pf, p, geo[0], q, ox, oy, oz, dx, dy, dz, eps, best_t)
            # a tie: the earlier run's row, then the earlier triangle of the run
            if found or (t == best_t and (p < best_p or (p == best_p and q < best_l))):
                best_t, best_p, best_l, best_u, best_v = t, p, q, u, v
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, items[i * NITEM + ITEM_D], ox, oy, oz, ix, iy, iz, ZERO, best_t):
                axis = items[i * NITEM + ITEM_C]
                if axis != 0 and (dx if axis == 1 else (dy if axis == 2 else dz)) < ZERO:
                    # a hierarchy's node split along an axis the ray goes down: its second
                    # child first, then its first, then what follows the node
                    skip = items[i * NITEM + ITEM_A]
                    second = items[i * NITEM + ITEM_B]
                    if skip < end:
                        si[top * NSI + BV_FROM] = skip
                        si[top * NSI + BV_TO] = end
                        top += 1
                    si[top * NSI + BV_FROM] = i + 1
                    si[top * NSI + BV_TO] = second
                    top += 1
                    i = second
                    end = skip
                else:
                    i += 1
            else:
                i = items[i * NITEM + ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            m = csg_collect(w, s, i, ox, oy, oz, dx, dy, dz, eps)
            for j in range(m):
                t = sf[j * NSF + CS_T]
                if t >= ZERO:
                    if t < best_t or (t == best_t and si[j * NSI + CS_P] < best_p):
                        best_t = t
                        best_p = si[j * NSI + CS_P]
                        best_l = si[j * NSI + CS_L]
                        best_u = sf[j * NSF + CS_U]
                        best_v = sf[j * NSF + CS_V]
                    break  # the list is sorted: its first non-negative t is its hit
            i += 1
        else:
            i += 1
    if HAS_SPHERE and n_balls > 0:
        reached = 0
        for j in range(n_balls):
            reach = ball_reach(balls, n_balls, j, ox, oy, oz, dx, dy, dz, a)
            tb[j] = reach
            reached += 1 if reach >= ZERO else 0
        nearest = -1
        for j in range(n_balls if reached > 0 else 0):
            if tb[j] >= ZERO:
                hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
                found, t, local = ball_first(hb, cc, a, best_t)
                # a tie goes to the earlier primitive: best_p follows every ball taken, so a
                # ball ties with the nearest so far, not with the item found before the balls
                if found or (
                    t == best_t and t != INF and int(balls[B_PRIM * n_balls + j]) < best_p
                ):
                    best_t = t
                    best_l = local
                    best_p = int(balls[B_PRIM * n_balls + j])
                    nearest = j
        if nearest >= 0:
            best_u = ZERO
            best_v = ZERO
    return best_t, best_p, best_l, best_u, best_v


@njit(**INLINE)
def occludes(pf, pi, items, geo, i, ox, oy, oz, dx, dy, dz, a, eps, distance):
    """Does item i (a primitive or a compact triangle) meet the ray before ``distance``?"""
    p = items[i * NITEM + ITEM_A]
    if items[i * NITEM + ITEM_TYPE] == I_TRI:
        q = items[i * NITEM + ITEM_B]
        found, _, _, _ = compact_first_hit(pf, p, geo[0], q, ox, oy, oz, dx, dy, dz, eps, distance)
        return found
    found, _, _, _, _ = first_hit_in(pf, pi, p, ox, oy, oz, dx, dy, dz, a, eps, distance)
    return found


@njit(**INLINE)
def shadowed(w, s, ox, oy, oz, vx, vy, vz, eps, slot):
    """Chapter 8 (``is_shadowed``): does a shadow-casting object lie between (ox, oy, oz)
    and the light at the end of (vx, vy, vz)? The shadow ray is the book's: the unit
    vector and the distance (the EPSILON parallel tests of planes, cubes, cylinders and
    cones assume a unit direction: along the unnormalized vector they would meet a plane
    |v| times sooner). Every ball at once first; then the primitive that answered yes last
    time (on this thread, for this light: memo ``slot``), since neighbouring pixels usually
    share their occluder; then the items. (Any occluder gives the same answer.)"""
    pf, pi, items, n_items, boxes, _, balls, n_balls, _, _, _, geo = w
    sf, si, _ = s
    distance = math.sqrt(vx * vx + vy * vy + vz * vz)
    if distance == ZERO:
        return False
    dx = vx / distance
    dy = vy / distance
    dz = vz / distance
    a = dx * dx + dy * dy + dz * dz
    ix = ONE / dx
    iy = ONE / dy
    iz = ONE / dz
    if HAS_SPHERE and n_balls > 0:
        reached = 0
        for j in range(n_balls):  # counts only: no stores, so no overlap checks
            reach = ball_reach(balls, n_balls, j, ox, oy, oz, dx, dy, dz, a)
            reached += 1 if reach >= ZERO and balls[B_SHADOW * n_balls + j] != ZERO else 0
        for j in range(n_balls if reached > 0 else 0):
            if balls[B_SHADOW * n_balls + j] != ZERO:
                hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
                found, _, _ = ball_first(hb, cc, a, distance)
                if found:
                    return True
    last = si[slot * NSI + MEMO]
    if last >= 0 and occludes(pf, pi, items, geo, last, ox, oy, oz, dx, dy, dz, a, eps, distance):
        return True
    i = 0
    while i < n_items:
        kind = items[i * NITEM + ITEM_TYPE]
        if kind in (I_PRIM, I_TRI):
            p = items[i * NITEM + ITEM_A]
            if (
                pi[p * NI + CASTS_SHADOW] != 0
                and i != last
                and occludes(pf, pi, items, geo, i, ox, oy, oz, dx, dy, dz, a, eps, distance)
            ):
                si[slot * NSI + MEMO] = i
                return True
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, items[i * NITEM + ITEM_D], ox, oy, oz, ix, iy, iz, ZERO, distance):
                i += 1
            else:
                i = items[i * NITEM + ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            m = csg_collect(w, s, i, ox, oy, oz, dx, dy, dz, eps)
            for j in range(m):
                t = sf[j * NSF + CS_T]
                if t >= ZERO and t < distance and pi[si[j * NSI + CS_P] * NI + CASTS_SHADOW] != 0:
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
def tally(p, base, compact, n, t0, t1, t2, t3, t_hit, p_hit, l_hit, state):
    """Chapter 11, for one object's n intersections (t0 ... t3, numbered from ``base``: a
    primitive's from 0; a ``compact`` triangle's is its number): when an odd number of them
    comes before the hit, it is a container; keep the latest-entered one. ``state``:
    (other_t, other_p, other_l, hit_inside, hit_t, hit_l), returned updated."""
    other_t, other_p, other_l, hit_inside, hit_t, hit_l = state
    count = 0
    last_t = -INF
    last_l = -1
    for j in range(n):
        t = nth(t0, t1, t2, t3, j)
        local = base + j
        if before(t, p, local, t_hit, p_hit, l_hit):
            count += 1
            if later(t, p, local, last_t, p, last_l):
                last_t = t
                last_l = local
    if count % 2 == 1:
        # the hit's own object: its primitive, or for a compact triangle its run and number
        if p == p_hit and (not compact or base == l_hit):
            hit_inside = True
            hit_t = last_t
            hit_l = last_l
        elif later(last_t, p, last_l, other_t, other_p, other_l):
            other_t, other_p, other_l = last_t, p, last_l
    return other_t, other_p, other_l, hit_inside, hit_t, hit_l


@njit(**INLINE)
def refractive_indices(w, s, ox, oy, oz, dx, dy, dz, eps, t_hit, p_hit, l_hit):
    """Chapter 11: (n1, n2) at the hit (t_hit, p_hit, l_hit), from every intersection along
    the ray (negative t included, as in the reference's list)."""
    pf, pi, items, n_items, boxes, _, balls, n_balls, _, _, _, geo = w
    sf, si, _ = s
    # the latest-entered container other than the hit's object (t, p, local); is the hit's
    # object a container just before the hit, and its latest entry (t, local)
    state = (-INF, -1, -1, False, -INF, -1)
    ix = ONE / dx
    iy = ONE / dy
    iz = ONE / dz
    i = 0
    while i < n_items:
        kind = items[i * NITEM + ITEM_TYPE]
        if kind == I_PRIM:
            p = items[i * NITEM + ITEM_A]
            if not starts_after(pf, p, ox, oy, oz, dx, dy, dz, t_hit):
                n, t0, t1, t2, t3, _, _ = intersect_prim(
                    pf, pi, p, ox, oy, oz, dx, dy, dz, eps, INF
                )
                state = tally(p, 0, False, n, t0, t1, t2, t3, t_hit, p_hit, l_hit, state)
            i += 1
        elif kind == I_TRI:
            p = items[i * NITEM + ITEM_A]
            q = items[i * NITEM + ITEM_B]
            n, t0 = compact_all(pf, p, geo[0], q, ox, oy, oz, dx, dy, dz, eps)
            state = tally(p, q, True, n, t0, INF, INF, INF, t_hit, p_hit, l_hit, state)
            i += 1
        elif HAS_BOXES and kind == I_BOX:
            if box_range(boxes, items[i * NITEM + ITEM_D], ox, oy, oz, ix, iy, iz, -INF, t_hit):
                i += 1
            else:
                i = items[i * NITEM + ITEM_A]
        elif HAS_CSG and kind == I_CSG:
            other_t, other_p, other_l, hit_inside, hit_t, hit_l = state
            m = csg_collect(w, s, i, ox, oy, oz, dx, dy, dz, eps)
            first = items[i * NITEM + ITEM_C]
            for q in range(first, items[i * NITEM + ITEM_D]):
                si[(q - first) * NSI + CS_COUNT] = 0
            for j in range(m):
                q = si[j * NSI + CS_P]
                if before(sf[j * NSF + CS_T], q, si[j * NSI + CS_L], t_hit, p_hit, l_hit):
                    si[(q - first) * NSI + CS_COUNT] += 1
                    # the list is sorted: the latest is last
                    sf[(q - first) * NSF + CS_LAST_T] = sf[j * NSF + CS_T]
                    si[(q - first) * NSI + CS_LAST_L] = si[j * NSI + CS_L]
            for q in range(first, items[i * NITEM + ITEM_D]):
                if si[(q - first) * NSI + CS_COUNT] % 2 == 1:
                    last_t = sf[(q - first) * NSF + CS_LAST_T]
                    last_l = si[(q - first) * NSI + CS_LAST_L]
                    if q == p_hit:
                        hit_inside = True
                        hit_t = last_t
                        hit_l = last_l
                    elif later(last_t, q, last_l, other_t, other_p, other_l):
                        other_t, other_p, other_l = last_t, q, last_l
            state = (other_t, other_p, other_l, hit_inside, hit_t, hit_l)
            i += 1
        else:
            i += 1
    if HAS_SPHERE:
        a = dx * dx + dy * dy + dz * dz
        # a ball other than the hit's can be a container only if the hit point is inside it
        # (one root before t_hit, one after); a point well outside (1e-6 of r² to spare, more
        # than rounding moves the roots of a grazing ray) skips them
        hx = ox + dx * t_hit
        hy = oy + dy * t_hit
        hz = oz + dz * t_hit
        for j in range(n_balls):
            p = int(balls[B_PRIM * n_balls + j])
            if p != p_hit:
                cx = hx - balls[B_X * n_balls + j]
                cy = hy - balls[B_Y * n_balls + j]
                cz = hz - balls[B_Z * n_balls + j]
                r2 = balls[B_R2 * n_balls + j]
                if cx * cx + cy * cy + cz * cz > r2 + r2 * F(1e-6):
                    continue
            hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
            discriminant = hb * hb - a * cc
            if discriminant >= ZERO:
                t0, t1 = ball_roots(hb, cc, a, discriminant)
                state = tally(p, 0, False, 2, t0, t1, INF, INF, t_hit, p_hit, l_hit, state)
    other_t, other_p, other_l, hit_inside, hit_t, hit_l = state
    outside = pf[other_p * NF + REFRACTIVE_INDEX] if other_p >= 0 else ONE
    own = pf[p_hit * NF + REFRACTIVE_INDEX]
    if hit_inside:
        if other_p >= 0 and later(other_t, other_p, other_l, hit_t, p_hit, hit_l):
            return outside, outside
        return own, outside
    return outside, own


@njit(**INLINE)
def push(stack, top, ox, oy, oz, dx, dy, dz, weight, remaining):
    m = top * STACK_WIDTH
    stack[m + 0] = ox
    stack[m + 1] = oy
    stack[m + 2] = oz
    stack[m + 3] = dx
    stack[m + 4] = dy
    stack[m + 5] = dz
    stack[m + 6] = weight
    stack[m + 7] = remaining
    return top + 1


@njit(**INLINE)
def light_intensity(w, s, k, x, y, z, eps, key):
    """The bonus chapter on soft shadows: ``intensity_at`` for area light k at (x, y, z):
    the fraction of its cells (v outer, u inner) whose point no shadow-casting object
    hides, one shadow ray each (``shadowed``, as for point lights); ``key``: the sample's
    (``sample_key``), for the jitter."""
    _, _, _, _, _, _, _, _, light, n_lights, _, _ = w
    _, si, _ = s
    lm = k * NLIGHT
    seq0 = n_lights * NLIGHT
    usteps = int(light[lm + LIGHT_USTEPS])
    vsteps = int(light[lm + LIGHT_VSTEPS])
    slot = k % MIN_SCRATCH
    lit = 0
    cell = 0
    for v in range(vsteps):
        for u in range(usteps):
            if HAS_SHADOWS:
                qx, qy, qz = cell_point(light, lm, seq0, k, u, v, cell, key)
                if COUNT_RAYS:
                    si[1 * NSI + RAYS] += 1
                if not shadowed(w, s, x, y, z, qx - x, qy - y, qz - z, eps, slot):
                    lit += 1
            else:
                lit += 1
            cell += 1
    return F(lit) / F(usteps * vsteps)


@njit(**INLINE)
def shade_and_push(w, s, p, eyev, normalv, over, under, reflectv, n1, n2, weight, remaining,
                   eps, stack, top, key):  # fmt: skip
    """Chapters 7, 8 and 11 (``shade_hit``): the surface color at a prepared hit (every
    light's, each with its own shadow ray, an area light's with one per cell; the ambient
    term once), times ``weight``; the reflected and refracted rays it spawns are pushed
    on the stack with their weights. ``key``: the sample's (``sample_key``: an area
    light's jitter). Returns (r, g, b, new top)."""
    pf, pi, _, _, _, _, _, _, light, n_lights, tex, _ = w
    _, si, _ = s
    ex, ey, ez = eyev
    nx, ny, nz = normalv
    over_x, over_y, over_z = over
    under_x, under_y, under_z = under
    rx, ry, rz = reflectv
    sr = ZERO
    sg = ZERO
    sb = ZERO
    # several lights: each adds its diffuse and specular, with its own shadow test; the
    # ambient term comes once, with the first; no light: black. (One kernel for any number:
    # a kernel kept to one light measured no faster on the reference scene.)
    cr = ZERO
    cg = ZERO
    cb = ZERO
    if n_lights > 0:
        cr, cg, cb = surface_color(pf, pi, tex, p, over_x, over_y, over_z)
    for k in range(n_lights):
        lm = k * NLIGHT
        if HAS_AREA_LIGHTS and light[lm + LIGHT_USTEPS] > ZERO:
            intensity = light_intensity(w, s, k, over_x, over_y, over_z, eps, key)
            lr, lg, lb = area_phong(
                pf, p, cr, cg, cb, light, lm, n_lights * NLIGHT, k, key, ex, ey, ez, nx, ny,
                nz, over_x, over_y, over_z, intensity, k == 0,
            )  # fmt: skip
            sr += lr
            sg += lg
            sb += lb
            continue
        # towards the light, not normalized (``shadowed`` and the lighting below normalize it)
        vx = light[lm] - over_x
        vy = light[lm + 1] - over_y
        vz = light[lm + 2] - over_z
        facing = vx * nx + vy * ny + vz * nz >= ZERO  # the light is in front of the surface
        if vx * vx + vy * vy + vz * vz == ZERO:
            facing = False  # the light on the point (a cone's tip has no over point): no way in
        lit = facing
        if HAS_SHADOWS and facing:
            if COUNT_RAYS:
                si[1 * NSI + RAYS] += 1
            slot = k % MIN_SCRATCH
            lit = not shadowed(w, s, over_x, over_y, over_z, vx, vy, vz, eps, slot)
        lx = ZERO
        ly = ZERO
        lz = ZERO
        light_dot_normal = -ONE  # in shadow, or facing away: ambient only (phong needs no more)
        if lit:
            scale = ONE / math.sqrt(vx * vx + vy * vy + vz * vz)
            lx = vx * scale
            ly = vy * scale
            lz = vz * scale
            light_dot_normal = lx * nx + ly * ny + lz * nz
        lr, lg, lb = phong(
            pf, p, cr, cg, cb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz, light_dot_normal,
            lit, k == 0,
        )  # fmt: skip
        sr += lr
        sg += lg
        sb += lb
    if remaining > 0 and (HAS_REFLECTION or HAS_REFRACTION):
        reflective = pf[p * NF + REFLECTIVE]
        transparency = pf[p * NF + TRANSPARENCY]
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
                    stack, top, under_x, under_y, under_z, tx, ty, tz, refracted_weight,
                    remaining - 1,
                )  # fmt: skip
    return sr * weight, sg * weight, sb * weight, top


@njit(**INLINE)
def prepare(pf, pi, p, ox, oy, oz, dx, dy, dz, t, u, v, eps, g, local):
    """Chapters 7, 8 and 11 (``prepare_computations`` without n1/n2): point, eyev, normalv,
    inside, over_point, under_point, reflectv."""
    px = ox + dx * t
    py = oy + dy * t
    pz = oz + dz * t
    ex = -dx
    ey = -dy
    ez = -dz
    nx, ny, nz = hit_normal(pf, pi, p, px, py, pz, u, v, eps, g, local)
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
def drain(w, s, eps, stack, top, r, g, b, key):
    """Chapter 7 (``color_at``, iteratively): trace every ray on the stack and everything it
    spawns; returns the sum of their weighted surface colors added to (r, g, b). ``key``:
    the sample's (``sample_key``), the same at every bounce."""
    pf, pi, _, _, _, _, _, _, _, _, _, geo = w
    _, si, _ = s
    while top > 0:
        top -= 1
        m = top * STACK_WIDTH
        ox = stack[m + 0]
        oy = stack[m + 1]
        oz = stack[m + 2]
        dx = stack[m + 3]
        dy = stack[m + 4]
        dz = stack[m + 5]
        weight = stack[m + 6]
        remaining = int(stack[m + 7])
        if COUNT_RAYS:
            si[0 * NSI + RAYS] += 1
        t, p, local, u, v = nearest_hit(w, s, ox, oy, oz, dx, dy, dz, eps)
        if p < 0:
            continue
        (_px, _py, _pz, ex, ey, ez, nx, ny, nz, _inside, over_x, over_y, over_z, under_x, under_y,
         under_z, rx, ry, rz) = prepare(pf, pi, p, ox, oy, oz, dx, dy, dz, t, u, v, eps, geo, local)  # fmt: skip
        n1 = ONE
        n2 = ONE
        if HAS_REFRACTION and remaining > 0 and pf[p * NF + TRANSPARENCY] > ZERO:
            if COUNT_RAYS:
                si[2 * NSI + RAYS] += 1
            n1, n2 = refractive_indices(w, s, ox, oy, oz, dx, dy, dz, eps, t, p, local)
        sr, sg, sb, top = shade_and_push(
            w, s, p, (ex, ey, ez), (nx, ny, nz), (over_x, over_y, over_z),
            (under_x, under_y, under_z), (rx, ry, rz), n1, n2, weight, remaining, eps, stack,
            top, key,
        )  # fmt: skip
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
    pixel_x = cam[m + 0] * wx + cam[m + 1] * wy + cam[m + 2] * -ONE + cam[m + 3]
    pixel_y = cam[m + 4] * wx + cam[m + 5] * wy + cam[m + 6] * -ONE + cam[m + 7]
    pixel_z = cam[m + 8] * wx + cam[m + 9] * wy + cam[m + 10] * -ONE + cam[m + 11]
    ox = cam[m + 3]  # the inverse view transform of the point (0, 0, 0)
    oy = cam[m + 7]
    oz = cam[m + 11]
    vx = pixel_x - ox
    vy = pixel_y - oy
    vz = pixel_z - oz
    scale = ONE / math.sqrt(vx * vx + vy * vy + vz * vz)
    return ox, oy, oz, vx * scale, vy * scale, vz * scale


@njit(**INLINE)
def sample_key(seed_key, x, y, i):
    """``raytracer.sampling.sample_key`` (without its checks); ``seed_key`` is seed *
    GAMMA mod 2**64, computed once per render."""
    return seed_key ^ (
        (np.uint64(y) << np.uint64(34)) | (np.uint64(x) << np.uint64(20)) | np.uint64(i)
    )


@njit(**INLINE)
def sample_offset(seed_key, x, y, i):
    """``raytracer.sampling.sample_offset`` bit for bit (``sample_key``)."""
    key = sample_key(seed_key, x, y, i)
    first = mix64(key + GAMMA)
    second = mix64(key + GAMMA2)
    return np.float64(first >> np.uint64(11)) * UNIT53, np.float64(second >> np.uint64(11)) * UNIT53


@njit(**INLINE)
def sample_ray(cam, seed_key, samples, x, y, i):
    """Chapter 7: the camera ray of sample i of pixel (x, y): through the pixel's centre
    with one sample, else offset by ``sample_offset``."""
    if samples == 1:
        return camera_ray(cam, F(x), F(y))
    sx, sy = sample_offset(seed_key, x, y, i)
    return camera_ray(cam, F(np.float64(x) + sx - 0.5), F(np.float64(y) + sy - 0.5))


@njit(**INLINE)
def render_rows(out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, stack, s):
    """Chapter 7: render rows y0 + k, y0 + k + step ... (below y1) of the region x0 <= x <
    x1, y0 <= y < y1 into ``out`` ((y1 - y0) x (x1 - x0) x 3, flat; pixels and sample
    offsets use the absolute (x, y)), with one thread's scratch: ``stack`` (depth + 2
    entries) and ``s`` = (sf, si, tb) (``layout``; si's MEMO entry set to -1 before the
    first call). Returns the rows done. The next sample's camera ray is made before the
    current one is traced, so that the processor can work on both at once."""
    eps = F(eps)
    scale = ONE / F(samples)
    width = x1 - x0
    if y0 + k >= y1 or width <= 0:
        return 0
    x = x0
    y = y0 + k
    i = 0
    ox, oy, oz, dx, dy, dz = sample_ray(cam, seed_key, samples, x, y, i)
    r = ZERO
    g = ZERO
    b = ZERO
    rows = 0
    while True:
        # the sample after this one
        next_x = x
        next_y = y
        next_i = i + 1
        if next_i == samples:
            next_i = 0
            next_x = x + 1
            if next_x == x1:
                next_x = x0
                next_y = y + step
        more = next_y < y1
        nox, noy, noz, ndx, ndy, ndz = ox, oy, oz, dx, dy, dz
        if more:
            nox, noy, noz, ndx, ndy, ndz = sample_ray(
                cam, seed_key, samples, next_x, next_y, next_i
            )
        top = push(stack, 0, ox, oy, oz, dx, dy, dz, ONE, depth)
        key = sample_key(seed_key, x, y, i) if HAS_AREA_LIGHTS else np.uint64(0)
        r, g, b = drain(w, s, eps, stack, top, r, g, b, key)
        if next_i == 0:  # the pixel is done
            m = ((y - y0) * width + (x - x0)) * 3
            if samples == 1:
                out[m] = r
                out[m + 1] = g
                out[m + 2] = b
            else:
                out[m] = r * scale
                out[m + 1] = g * scale
                out[m + 2] = b * scale
            r = ZERO
            g = ZERO
            b = ZERO
            if next_x == x0:
                rows += 1
        if not more:
            break
        x, y, i = next_x, next_y, next_i
        ox, oy, oz, dx, dy, dz = nox, noy, noz, ndx, ndy, ndz
    return rows


def render_entry(
    out, x0, y0, x1, y1, k, step, cam, pf, pi, items, n_items, boxes, csg, balls, n_balls,
    light, n_lights, ti, tf, tg, tn, depth, samples, seed_key, eps, stack, sf, si, tb,
):  # fmt: skip
    """The render's entry point, compiled as a C function (``make_render_entry``)."""
    w = (pf, pi, items, n_items, boxes, csg, balls, n_balls, light, n_lights, (ti, tf), (tg, tn))
    return render_rows(
        out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, stack, (sf, si, tb)
    )


def make_render_entry(cache):
    """Compile ``render_entry`` as a C-callable function (numba's ``cfunc``) over raw
    pointers: ``int64 f(F* out, int64 x0, int64 y0, int64 x1, int64 y1, int64 k, int64
    step, F* cam, F* pf, int64* pi, int32* items, int64 n_items, F* boxes, int64* csg, F*
    balls, int64 n_balls, F* light, int64 n_lights, int64* ti, F* tf, F* tg, F* tn, int64
    depth, int64 samples, uint64 seed_key, float64 eps, F* stack, F* sf, int64* si, F* tb)``. Without the numba runtime: it cannot
    allocate. ``cache``: numba's disk cache (used only when the render cannot be linked as
    a shared library)."""
    from numba import cfunc, types

    real = types.float32 if F is np.float32 else types.float64
    fp = types.CPointer(real)
    ip = types.CPointer(types.int64)
    i32p = types.CPointer(types.int32)
    i64 = types.int64
    signature = types.int64(
        fp, i64, i64, i64, i64, i64, i64, fp, fp, ip, i32p, i64, fp, ip, fp, i64, fp, i64, ip, fp,
        fp, fp, i64, i64, types.uint64, types.float64, fp, fp, ip, fp,
    )  # fmt: skip
    flags: dict[str, Any] = {"_nrt": False, "fastmath": FASTMATH, "error_model": "numpy"}
    return cfunc(signature, cache=cache, **flags)(render_entry)
