"""Kernel template: n1 and n2 of a hit (chapter 11) without a sorted list.

``refractive_indices``: an object is in the book's ``containers`` when an odd number of its
intersections come before the hit, and the last of them entered is the one whose latest
such intersection comes last. A ball other than the hit's is skipped when the hit point is
well outside it (it cannot be a container). The world and scratch tuples are
``kernels_hits``'s.
"""

from numba import njit

from variants.numba.kernel_flags import (
    HAS_BOXES,
    HAS_CSG,
    HAS_SPHERE,
    F,
)
from variants.numba.kernels_geometry import (
    INF,
    INLINE,
    ONE,
    ZERO,
    ball_roots,
    ball_terms,
    box_range,
    nth,
    starts_after,
)
from variants.numba.kernels_hits import (
    ball_soa_terms,
    csg_collect,
)
from variants.numba.kernels_prims import (
    intersect_prim,
)
from variants.numba.kernels_shapes import (
    compact_all,
)
from variants.numba.layout import (
    B_PRIM,
    B_R2,
    B_X,
    B_Y,
    B_Z,
    CS_COUNT,
    CS_L,
    CS_LAST_L,
    CS_LAST_T,
    CS_P,
    CS_T,
    I_BOX,
    I_CSG,
    I_PRIM,
    I_TRI,
    ITEM_A,
    ITEM_B,
    ITEM_C,
    ITEM_D,
    ITEM_TYPE,
    NF,
    NITEM,
    NSF,
    NSI,
    REFRACTIVE_INDEX,
)

# ---- kernel template ----


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
def ball_may_hold(balls, n_balls, j, hx, hy, hz):
    """Can ball j hold the point (hx, hy, hz)? False when the point is well outside it
    (1e-6 of r² to spare, more than rounding moves the roots of a grazing ray)."""
    cx = hx - balls[B_X * n_balls + j]
    cy = hy - balls[B_Y * n_balls + j]
    cz = hz - balls[B_Z * n_balls + j]
    r2 = balls[B_R2 * n_balls + j]
    return not cx * cx + cy * cy + cz * cz > r2 + r2 * F(1e-6)


@njit(**INLINE)
def balls_tally(balls, n_balls, pf, ox, oy, oz, dx, dy, dz, t_hit, p_hit, l_hit, state):
    """``refractive_indices``'s balls: a ball other than the hit's can be a container only
    if the hit point is inside it (one root before t_hit, one after). One vectorized pass
    counts those that may hold the point and whether the hit's primitive is a ball; when
    no other may, only the hit's ball is tallied (from its row, the same numbers), else
    every ball that may hold the point and the hit's own. Returns ``state`` updated."""
    a = dx * dx + dy * dy + dz * dz
    hx = ox + dx * t_hit
    hy = oy + dy * t_hit
    hz = oz + dz * t_hit
    others = 0
    own = 0
    for j in range(n_balls):  # counts only: no stores, so vector instructions
        mine = balls[B_PRIM * n_balls + j] == F(p_hit)
        own += 1 if mine else 0
        others += 1 if not mine and ball_may_hold(balls, n_balls, j, hx, hy, hz) else 0
    if others == 0:
        if own > 0:
            hb, cc = ball_terms(pf, p_hit, ox, oy, oz, dx, dy, dz)
            discriminant = hb * hb - a * cc
            if discriminant >= ZERO:
                t0, t1 = ball_roots(hb, cc, a, discriminant)
                state = tally(p_hit, 0, False, 2, t0, t1, INF, INF, t_hit, p_hit, l_hit, state)
        return state
    for j in range(n_balls):
        p = int(balls[B_PRIM * n_balls + j])
        if p != p_hit and not ball_may_hold(balls, n_balls, j, hx, hy, hz):
            continue
        hb, cc = ball_soa_terms(balls, n_balls, j, ox, oy, oz, dx, dy, dz)
        discriminant = hb * hb - a * cc
        if discriminant >= ZERO:
            t0, t1 = ball_roots(hb, cc, a, discriminant)
            state = tally(p, 0, False, 2, t0, t1, INF, INF, t_hit, p_hit, l_hit, state)
    return state


@njit(**INLINE)
def refractive_indices(w, s, ox, oy, oz, dx, dy, dz, eps, t_hit, p_hit, l_hit):
    """Chapter 11: (n1, n2) at the hit (t_hit, p_hit, l_hit), from every intersection along
    the ray (negative t included, as in the reference's list)."""
    # long: the walk over every kind of item of ``nearest_hit``, each branch tallying its
    # intersections into ``state`` (``tally``)
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
    if HAS_SPHERE and n_balls > 0:
        state = balls_tally(balls, n_balls, pf, ox, oy, oz, dx, dy, dz, t_hit, p_hit, l_hit, state)
    other_t, other_p, other_l, hit_inside, hit_t, hit_l = state
    outside = pf[other_p * NF + REFRACTIVE_INDEX] if other_p >= 0 else ONE
    own = pf[p_hit * NF + REFRACTIVE_INDEX]
    if hit_inside:
        if other_p >= 0 and later(other_t, other_p, other_l, hit_t, p_hit, hit_l):
            return outside, outside
        return own, outside
    return outside, own
