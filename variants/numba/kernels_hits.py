"""Kernel template: what a ray meets in the packed world (chapters 5, 7, 8, 14, 16).

- ``nearest_hit`` tracks the closest non-negative t instead of building a sorted list; ties go
  to the earlier primitive, as the reference's stable sort does. The items are a flat list,
  a group's boxes or a bounding-volume hierarchy (``variants.numba.bvh``), all walked by
  one loop without recursion (a box's item says where to go when the ray misses it). The
  balls (``layout``) come after the items: one vectorized pass says which ones the ray can
  reach at all (``ball_reach``), then those get the exact test.
- ``shadowed`` counts, in one vectorized pass, the shadow-casting balls the ray can reach,
  and tests them exactly only when there are any; then the items. In a world of balls
  alone, the pass before the ray is normalized (``balls_may_shadow``) also picks the balls
  to test: most shadows are certain without the unit vector (``ball_surely_shadows``),
  the rest are tested exactly. Its shadow ray is the
  book's, a unit vector and the distance to the light (along the unnormalized vector the
  book's EPSILON parallel tests would see a direction |v| times too long).
- ``csg_collect`` is chapter 16's list of a CSG tree, sorted and filtered in post-order.

A world travels as one tuple ``w`` = (pf, pi, items, n_items, boxes, csg, balls, n_balls,
lights, n_lights, (ti, tf), (tg, tn)) and a thread's scratch as ``s`` = (sf, si, tb) (see
``layout``). A compact triangle's hit is (its run's row, its number in ``tg``), which
sorts ties as the world's order does. The scratch holds one CSG tree's intersection list
and per primitive of the tree where its entries start and, for n1/n2, how many come before
the hit; the shadow memos (one per light) and ray counters; the hit ray's stack of item
ranges; one value per ball.

No function takes more than 30 arguments: Python compiles longer calls through a tuple,
which numba's inliner refuses.
"""

# ruff: noqa: E501
import math

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_BOXES,
    HAS_CSG,
    HAS_NODES,
    HAS_SPHERE,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    ZERO,
    ball_first,
    box_enter,
    box_hit,
    int32_at,
    int_bits,
    nth,
    slab,
    to_object_point,
    to_object_vector,
    wide_enters,
)
from variants.numba.kernels_prims import (
    first_hit_in,
    intersect_prim,
)
from variants.numba.kernels_shapes import (
    compact_first_hit,
    compact_intersect,
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
    CASTS_SHADOW,
    CS_L,
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
    I_NODES,
    I_PRIM,
    I_TRI,
    ITEM_A,
    ITEM_B,
    ITEM_C,
    ITEM_D,
    ITEM_TYPE,
    MEMO,
    MIN_SCRATCH,
    NCSG,
    NI,
    NITEM,
    NNODE,
    NODE_A,
    NODE_C,
    NSF,
    NSI,
    NWIDE,
    OP_DIFFERENCE,
    OP_INTERSECTION,
    OP_UNION,
    W_LINK,
    WIDE,
)

# ---- kernel template ----

# the compact nodes' walks: called, not inlined into each of ``nearest_hit``'s and
# ``shadowed``'s callers (once per ray, a call costs nothing; inlined, a mesh scene's kernel
# took half as long again to compile); only in a kernel whose scene has them (``HAS_NODES``)
CALLED = {**INLINE, "forceinline": False}


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
    """Chapter 5: can the ray meet ball j at some t >= 0? A value >= 0 when it may: the
    discriminant hb² - a cc (see ``ball_terms``) is not negative, and the origin is inside
    the ball (cc <= 0) or the ball is not behind it (hb <= 0); else a negative value: the
    line misses the ball, or its origin is outside and the ball behind. Only a filter: the
    exact test (``ball_first``) turns down the rest (hb = 0 from outside). Written as a min
    and a max of floats, so that a loop over the balls becomes vector min and max
    instructions (no masks to combine); most balls stop here."""
    hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
    return min(hb * hb - a * cc, max(-cc, -hb))


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
    # long: one loop over every kind of item, each branch updating the hit so far and the
    # range stack (numba passes no scalar by reference: a branch of its own would hand the
    # hit's five values and the stack's top back and forth)
    pf, pi, items, n_items, boxes, _, balls, n_balls, _, _, _, geo = w
    sf, si, tb = s
    a = dx * dx + dy * dy + dz * dz
    ix = ONE / dx
    iy = ONE / dy
    iz = ONE / dz
    parallel = abs(ix) == INF or abs(iy) == INF or abs(iz) == INF  # to an axis: the slow test
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
        if HAS_BOXES and kind == I_BOX:
            if box_hit(boxes, items[i * NITEM + ITEM_D], ox, oy, oz, ix, iy, iz, best_t, parallel):
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
        elif HAS_NODES and kind == I_NODES:
            if items[i * NITEM + ITEM_C] == WIDE:
                best_t, best_p, best_l, best_u, best_v = wide_nearest(
                    w, s, i, top, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, eps,
                    best_t, best_p, best_l, best_u, best_v,
                )  # fmt: skip
            else:
                best_t, best_p, best_l, best_u, best_v = nodes_nearest(
                    w, s, i, top, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, eps,
                    best_t, best_p, best_l, best_u, best_v,
                )  # fmt: skip
            i = items[i * NITEM + ITEM_A]
        elif kind == I_PRIM:
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
        return nearest_ball(balls, n_balls, tb, ox, oy, oz, dx, dy, dz, a,
                            best_t, best_p, best_l, best_u, best_v)  # fmt: skip
    return best_t, best_p, best_l, best_u, best_v


@njit(**INLINE)
def node_enter(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel):
    """``box_enter`` for the compact node at ``boxes[m]``, its sides taken in the order the
    ray meets them (``near_*``: 0, or 3 for a ray going down the axis): the same answer
    with no min or max to order each slab's two t."""
    if parallel:
        return box_enter(boxes, m, ox, oy, oz, ix, iy, iz, thi, parallel)
    tlo = max(max(ZERO, (boxes[m + near_x] - ox) * ix),
              max((boxes[m + 1 + near_y] - oy) * iy, (boxes[m + 2 + near_z] - oz) * iz))
    thi = min(min(thi, (boxes[m + 3 - near_x] - ox) * ix),
              min((boxes[m + 4 - near_y] - oy) * iy, (boxes[m + 5 - near_z] - oz) * iz))
    return tlo if tlo <= thi else INF


@njit(**INLINE)
def leaf_nearest(pf, items, geo, first, count, ox, oy, oz, dx, dy, dz, eps, run, lox, loy,
                 loz, ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v):  # fmt: skip
    """A hierarchy leaf's compact triangles ``first`` .. ``first + count - 1`` against the
    nearest hit so far (ties: the earlier run's row, then its earlier triangle). ``run`` and
    the ray in its object space (lo*, ld*) carry over from leaf to leaf: the ray is moved
    into a run's space once per run. Returns them and the nearest hit."""
    for k in range(first, first + count):
        p = items[k * NITEM + ITEM_A]
        q = items[k * NITEM + ITEM_B]
        if p != run:
            run = p
            lox, loy, loz = to_object_point(pf, p, ox, oy, oz)
            ldx, ldy, ldz = to_object_vector(pf, p, dx, dy, dz)
        n, hit, u, v = compact_intersect(geo[0], q, lox, loy, loz, ldx, ldy, ldz, eps)
        t = hit if n > 0 and hit >= ZERO else INF
        if t < best_t or (t == best_t and (p < best_p or (p == best_p and q < best_l))):
            best_t, best_p, best_l, best_u, best_v = t, p, q, u, v
    return run, lox, loy, loz, ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v


@njit(**CALLED)
def nodes_nearest(w, s, i, top, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, eps,
                  best_t, best_p, best_l, best_u, best_v):  # fmt: skip
    """``nearest_hit`` through I_NODES item i's compact nodes (``layout``): a node's two
    children's boxes tested together, the nearer along the node's split axis taken first,
    the other kept on the range stack (above ``top``) with where the ray enters it, and
    dropped when it comes back beyond the nearest hit so far. A box's sides are taken in
    the order the ray meets them (``node_enter``), and the ray is taken into a run's
    object space once, not per triangle. Returns the hit (t, primitive, index, u, v) after
    the node's triangles; ties as ``nearest_hit``'s."""
    pf, _, items, _, boxes, _, _, _, _, _, _, geo = w
    sf, si, _ = s
    base = items[i * NITEM + ITEM_B]
    bottom = top
    node = 0
    near_x = 3 if dx < ZERO else 0  # the side of a box the ray meets first, per axis
    near_y = 3 if dy < ZERO else 0
    near_z = 3 if dz < ZERO else 0
    run = -1  # the run whose object space (lo*, ld*) the ray is in
    lox = loy = loz = ldx = ldy = ldz = ZERO
    enter = box_enter(boxes, base, ox, oy, oz, ix, iy, iz, best_t, parallel)
    while True:
        if enter != INF:
            m = base + node * NNODE
            first = int_bits(boxes[m + NODE_A])
            code = int_bits(boxes[m + NODE_C])
            if code < 0:
                m = base + first * NNODE
                near = node_enter(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, best_t, parallel)
                far = node_enter(boxes, m + NNODE, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, best_t, parallel)
                node = first
                if code < -1 and (dx if code == -2 else (dy if code == -3 else dz)) < ZERO:
                    near, far = far, near
                    node = first + 1
                if near == INF:
                    node = 2 * first + 1 - node
                    enter = far
                    continue
                if far != INF:
                    si[top * NSI + BV_FROM] = 2 * first + 1 - node
                    sf[top * NSF + CS_T] = far
                    top += 1
                enter = near
                continue
            run, lox, loy, loz, ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v = leaf_nearest(
                pf, items, geo, first, code, ox, oy, oz, dx, dy, dz, eps, run, lox, loy, loz,
                ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v)  # fmt: skip
        if top == bottom:
            break
        top -= 1
        node = si[top * NSI + BV_FROM]
        enter = sf[top * NSF + CS_T]
        if enter > best_t:
            enter = INF
    return best_t, best_p, best_l, best_u, best_v


NO_NODE = -1  # a link no leaf has (a leaf holds a triangle at least)
LINKS = np.dtype(F).itemsize // 4  # int32 links per value of the box table (wide nodes)


@njit(**INLINE)
def lane_enter(boxes, m, j, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel):
    """``node_enter`` for child j of the wide node at float32 ``m`` of the box table (its
    box a column of the node's six rows of WIDE, ``layout``; ``near_*``: 0, or 3 * WIDE
    for a ray going down the axis)."""
    if parallel:
        tlo, thi = slab(ox, ix, boxes[m + j], boxes[m + 3 * WIDE + j], ZERO, thi)
        tlo, thi = slab(oy, iy, boxes[m + WIDE + j], boxes[m + 4 * WIDE + j], tlo, thi)
        tlo, thi = slab(oz, iz, boxes[m + 2 * WIDE + j], boxes[m + 5 * WIDE + j], tlo, thi)
        return tlo if tlo <= thi else INF
    tlo = max(max(ZERO, (boxes[m + near_x + j] - ox) * ix),
              max((boxes[m + WIDE + near_y + j] - oy) * iy,
                  (boxes[m + 2 * WIDE + near_z + j] - oz) * iz))
    thi = min(min(thi, (boxes[m + 3 * WIDE - near_x + j] - ox) * ix),
              min((boxes[m + 4 * WIDE - near_y + j] - oy) * iy,
                  (boxes[m + 5 * WIDE - near_z + j] - oz) * iz))
    return tlo if tlo <= thi else INF


@njit(**INLINE)
def wide_entries(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel):
    """Where the ray enters each of the four children of the wide node at ``m`` (``INF``:
    not before ``thi``): a ray along an axis child by child (``lane_enter``'s exact parallel
    tests), any other the four boxes at once (``wide_enters``)."""
    if parallel:
        return (
            lane_enter(boxes, m, 0, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel),
            lane_enter(boxes, m, 1, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel),
            lane_enter(boxes, m, 2, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel),
            lane_enter(boxes, m, 3, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, thi, parallel),
        )
    return wide_enters(boxes, m, near_x, near_y, near_z, ox, oy, oz, ix, iy, iz, thi)


@njit(**INLINE)
def ordered(ea, ca, eb, cb):
    """The two (entry, link) pairs, the nearer first."""
    if eb < ea:
        return eb, cb, ea, ca
    return ea, ca, eb, cb


@njit(**CALLED)
def wide_nearest(w, s, i, top, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, eps,
                 best_t, best_p, best_l, best_u, best_v):  # fmt: skip
    """``nodes_nearest`` through I_NODES item i's wide nodes (``layout``, ``bvh=sah4``):
    a node's four children's boxes tested together, the children entered taken nearest
    first (a sorting network over the four entry distances, a miss being INF), the others
    kept on the range stack (above ``top``) and dropped when they come back beyond the
    nearest hit so far. Returns the hit after the node's triangles; ties as
    ``nearest_hit``'s."""
    pf, _, items, _, boxes, _, _, _, _, _, _, geo = w
    sf, si, _ = s
    base = items[i * NITEM + ITEM_B]
    bottom = top
    node = 0
    near_x = 3 * WIDE if dx < ZERO else 0  # the side of a box the ray meets first, per axis
    near_y = 3 * WIDE if dy < ZERO else 0
    near_z = 3 * WIDE if dz < ZERO else 0
    run = -1  # the run whose object space (lo*, ld*) the ray is in
    lox = loy = loz = ldx = ldy = ldz = ZERO
    while True:
        if node >= 0:
            m = base + node * NWIDE
            e0, e1, e2, e3 = wide_entries(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z,
                                          best_t, parallel)  # fmt: skip
            c0 = int32_at(boxes, (m + W_LINK) * LINKS)
            c1 = int32_at(boxes, (m + W_LINK) * LINKS + 1)
            c2 = int32_at(boxes, (m + W_LINK) * LINKS + 2)
            c3 = int32_at(boxes, (m + W_LINK) * LINKS + 3)
            e0, c0, e1, c1 = ordered(e0, c0, e1, c1)
            e2, c2, e3, c3 = ordered(e2, c2, e3, c3)
            e0, c0, e2, c2 = ordered(e0, c0, e2, c2)
            e1, c1, e3, c3 = ordered(e1, c1, e3, c3)
            e1, c1, e2, c2 = ordered(e1, c1, e2, c2)
            if e0 != INF:
                if e3 != INF:
                    si[top * NSI + BV_FROM] = c3
                    sf[top * NSF + CS_T] = e3
                    top += 1
                if e2 != INF:
                    si[top * NSI + BV_FROM] = c2
                    sf[top * NSF + CS_T] = e2
                    top += 1
                if e1 != INF:
                    si[top * NSI + BV_FROM] = c1
                    sf[top * NSF + CS_T] = e1
                    top += 1
                node = c0
                continue
        else:
            leaf = -1 - node
            run, lox, loy, loz, ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v = leaf_nearest(
                pf, items, geo, leaf >> 3, leaf & 7, ox, oy, oz, dx, dy, dz, eps, run, lox, loy, loz,
                ldx, ldy, ldz, best_t, best_p, best_l, best_u, best_v)  # fmt: skip
        node = NO_NODE  # the nearest child left that the ray enters before best_t
        while top > bottom:
            top -= 1
            if sf[top * NSF + CS_T] <= best_t:
                node = si[top * NSI + BV_FROM]
                break
        if node == NO_NODE:
            break
    return best_t, best_p, best_l, best_u, best_v


@njit(**INLINE)
def nearest_ball(balls, n_balls, tb, ox, oy, oz, dx, dy, dz, a, best_t, best_p, best_l, best_u,
                 best_v):  # fmt: skip
    """``nearest_hit``'s last pass: the hit (t, primitive, index, u, v) after the balls,
    given the nearest so far. Every ball's ``ball_reach`` at once (in ``tb``), then the
    exact test of those the ray can reach, stopping after the last of them (most rays
    reach one ball or none: the ground, a sphere, the sky)."""
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
            if found or (t == best_t and t != INF and int(balls[B_PRIM * n_balls + j]) < best_p):
                best_t = t
                best_l = local
                best_p = int(balls[B_PRIM * n_balls + j])
                nearest = j
            reached -= 1
            if reached == 0:  # the last ball the ray can reach: the rest cannot
                break
    if nearest >= 0:
        best_u = ZERO
        best_v = ZERO
    return best_t, best_p, best_l, best_u, best_v


# how far below zero a ball's ``ball_reach`` along the shadow ray's unnormalized vector must
# be, relative to the size of its terms, for the reach along the unit vector to be negative
# too (rounding moves it by a few units in the last place: this is thousands of them)
SLACK = F(4096) * np.finfo(F).eps


@njit(**INLINE)
def balls_may_shadow(balls, n_balls, ox, oy, oz, vx, vy, vz, tb):
    """Can a shadow-casting ball meet the ray from (ox, oy, oz) along (vx, vy, vz), not
    normalized? ``ball_reach``'s two signs (with a = |v|² and hb = |v| times the unit
    vector's, up to rounding) taken with ``SLACK`` to spare: each ball's value is below 0
    only where ``shadowed``'s test along the unit vector does not reach it either (kept in
    ``tb``); no square root, no division. One vectorized pass (a min and a max of floats
    per ball, no masks)."""
    a = vx * vx + vy * vy + vz * vz
    may = 0
    for j in range(n_balls):
        cx = ox - balls[B_X * n_balls + j]
        cy = oy - balls[B_Y * n_balls + j]
        cz = oz - balls[B_Z * n_balls + j]
        hb = cx * vx + cy * vy + cz * vz
        cc = cx * cx + cy * cy + cz * cz - balls[B_R2 * n_balls + j]
        size = abs(cx * vx) + abs(cy * vy) + abs(cz * vz)
        line = hb * hb - a * cc + SLACK * (hb * hb + a * abs(cc))
        ahead = max(-cc, SLACK * size - hb)
        reach = min(min(line, ahead), balls[B_SHADOW * n_balls + j] - F(0.5))
        tb[j] = reach
        may += 1 if reach >= ZERO else 0
    return may > 0


# ``ball_surely_shadows``'s margins: its line's discriminant at least this much of its
# terms, and the point of the line nearest the centre this much before the light (far more
# than rounding moves the exact test's entry point: a few parts in 1e9 in float64)
SURE = F(max(2.0**-20, 65536 * float(np.finfo(F).eps)))


@njit(**INLINE)
def ball_surely_shadows(balls, n_balls, j, ox, oy, oz, vx, vy, vz, a):
    """Does shadow-casting ball j certainly meet the segment from (ox, oy, oz) to the end
    of (vx, vy, vz), not normalized (``a`` = |v|²), where ``shadowed``'s exact test along
    the unit vector would find it too? From inside it (cc < 0, the same cc as that test's):
    the light well outside it (by ``SURE``), so the segment leaves it before the light. From
    outside (cc > 0), going towards it (hb < 0 with ``SLACK`` to spare, as
    ``balls_may_shadow``), its line well through it and the point of the line nearest its
    centre (-hb / a) well before the light (both by ``SURE``): the segment then enters it
    before the light. No square root, no division."""
    cx = ox - balls[B_X * n_balls + j]
    cy = oy - balls[B_Y * n_balls + j]
    cz = oz - balls[B_Z * n_balls + j]
    hb = cx * vx + cy * vy + cz * vz
    cc = cx * cx + cy * cy + cz * cz - balls[B_R2 * n_balls + j]
    size = abs(cx * vx) + abs(cy * vy) + abs(cz * vz)
    if balls[B_SHADOW * n_balls + j] == ZERO:
        return False
    if cc < ZERO:  # from inside: the light well outside it (|c + v|² - r² = cc + 2 hb + a)
        r2 = balls[B_R2 * n_balls + j]
        return cc + F(2.0) * hb + a > SURE * (a + r2 - cc + F(2.0) * abs(hb))
    return (
        cc > ZERO
        and hb < -SLACK * size
        and -hb < a - SURE * a
        and hb * hb - a * cc > SURE * (hb * hb + a * cc)
    )


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
def leaf_occluder(pf, pi, items, geo, first, count, last, ox, oy, oz, dx, dy, dz, a, eps,
                  distance):  # fmt: skip
    """A hierarchy leaf's items ``first`` .. ``first + count - 1``: the first one other than
    item ``last`` that casts a shadow and meets the ray before ``distance``, or -1."""
    for k in range(first, first + count):
        if (
            k != last
            and pi[items[k * NITEM + ITEM_A] * NI + CASTS_SHADOW] != 0
            and occludes(pf, pi, items, geo, k, ox, oy, oz, dx, dy, dz, a, eps, distance)
        ):
            return k
    return -1


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
    sf, si, tb = s
    if HAS_SPHERE and n_items == 0:
        # balls alone: none in the way needs no unit vector; else the exact test of those
        # ``balls_may_shadow`` may not turn down (a ball it does is not reached along the
        # unit vector either, and ``ball_first`` finds no hit in a ball not reached)
        if not balls_may_shadow(balls, n_balls, ox, oy, oz, vx, vy, vz, tb):
            return False
        av = vx * vx + vy * vy + vz * vz
        for j in range(n_balls):  # most shadows: a ball well in the way, no unit vector
            if tb[j] >= ZERO and ball_surely_shadows(balls, n_balls, j, ox, oy, oz, vx, vy, vz, av):
                return True
        distance = math.sqrt(vx * vx + vy * vy + vz * vz)
        if distance == ZERO:
            return False
        dx = vx / distance
        dy = vy / distance
        dz = vz / distance
        a = dx * dx + dy * dy + dz * dz
        for j in range(n_balls):
            if tb[j] >= ZERO:
                hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
                found, _, _ = ball_first(hb, cc, a, distance)
                if found:
                    return True
        return False  # (no items: no memo either)
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
    parallel = abs(ix) == INF or abs(iy) == INF or abs(iz) == INF
    if HAS_SPHERE and n_balls > 0:
        reached = 0
        for j in range(n_balls):  # counts only: no stores, so no overlap checks
            reach = ball_reach(balls, n_balls, j, ox, oy, oz, dx, dy, dz, a)
            # (B_SHADOW is 1 or 0: >= 0 when the ball is reached and casts a shadow, and
            # as a min of floats, vector instructions without masks to combine)
            shadowing = min(reach, balls[B_SHADOW * n_balls + j] - F(0.5))
            reached += 1 if shadowing >= ZERO else 0
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
            if box_hit(boxes, items[i * NITEM + ITEM_D], ox, oy, oz, ix, iy, iz, distance, parallel):
                i += 1
            else:
                i = items[i * NITEM + ITEM_A]
        elif HAS_NODES and kind == I_NODES:
            if items[i * NITEM + ITEM_C] == WIDE:
                if wide_occluded(w, s, i, last, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, a, eps, distance, slot):
                    return True
            elif nodes_occluded(w, s, i, last, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, a, eps, distance, slot):
                return True
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


@njit(**CALLED)
def wide_occluded(w, s, i, last, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, a, eps,
                  distance, slot):  # fmt: skip
    """``nodes_occluded`` through I_NODES item i's wide nodes (``bvh=sah4``): every child
    the ray enters before ``distance`` is visited, in slot order."""
    pf, pi, items, _, boxes, _, _, _, _, _, _, geo = w
    _, si, _ = s
    base = items[i * NITEM + ITEM_B]
    top = 0
    node = 0
    near_x = 3 * WIDE if dx < ZERO else 0
    near_y = 3 * WIDE if dy < ZERO else 0
    near_z = 3 * WIDE if dz < ZERO else 0
    while True:
        if node >= 0:
            m = base + node * NWIDE
            e0, e1, e2, e3 = wide_entries(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z,
                                          distance, parallel)  # fmt: skip
            links = (m + W_LINK) * LINKS
            if e3 != INF:
                si[top * NSI + BV_FROM] = int32_at(boxes, links + 3)
                top += 1
            if e2 != INF:
                si[top * NSI + BV_FROM] = int32_at(boxes, links + 2)
                top += 1
            if e1 != INF:
                si[top * NSI + BV_FROM] = int32_at(boxes, links + 1)
                top += 1
            if e0 != INF:
                si[top * NSI + BV_FROM] = int32_at(boxes, links)
                top += 1
        else:
            leaf = -1 - node
            k = leaf_occluder(pf, pi, items, geo, leaf >> 3, leaf & 7, last, ox, oy, oz, dx, dy,
                              dz, a, eps, distance)  # fmt: skip
            if k >= 0:
                si[slot * NSI + MEMO] = k
                return True
        if top == 0:
            return False
        top -= 1
        node = si[top * NSI + BV_FROM]


@njit(**CALLED)
def nodes_occluded(w, s, i, last, ox, oy, oz, dx, dy, dz, ix, iy, iz, parallel, a, eps,
                   distance, slot):  # fmt: skip
    """``shadowed`` through I_NODES item i's compact nodes: does a shadow-casting
    triangle other than item ``last`` meet the ray before ``distance``? Any one answers
    (it becomes the light's memo); both children of a node the ray enters are visited."""
    pf, pi, items, _, boxes, _, _, _, _, _, _, geo = w
    _, si, _ = s
    base = items[i * NITEM + ITEM_B]
    top = 0
    node = 0
    near_x = 3 if dx < ZERO else 0  # the side of a box the ray meets first, per axis
    near_y = 3 if dy < ZERO else 0
    near_z = 3 if dz < ZERO else 0
    inside = box_enter(boxes, base, ox, oy, oz, ix, iy, iz, distance, parallel) != INF
    while True:
        if inside:
            m = base + node * NNODE
            first = int_bits(boxes[m + NODE_A])
            code = int_bits(boxes[m + NODE_C])
            if code < 0:
                m = base + first * NNODE
                near = node_enter(boxes, m, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, distance, parallel) != INF
                far = node_enter(boxes, m + NNODE, ox, oy, oz, ix, iy, iz, near_x, near_y, near_z, distance, parallel) != INF
                if near and far:
                    si[top * NSI + BV_FROM] = first + 1
                    top += 1
                node = first if near else first + 1
                inside = near or far
                continue
            k = leaf_occluder(pf, pi, items, geo, first, code, last, ox, oy, oz, dx, dy, dz, a,
                              eps, distance)  # fmt: skip
            if k >= 0:
                si[slot * NSI + MEMO] = k
                return True
        if top == 0:
            return False
        top -= 1
        node = si[top * NSI + BV_FROM]
        inside = True
