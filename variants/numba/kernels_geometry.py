"""Kernel template: what every part uses (the helpers' compile options, the constants in
the float type ``F``), transforms between world and object space (chapters 5, 6), the
world-space balls, the bounding spheres that let a ray skip a primitive, and bounding boxes
(chapter 14).

A sphere whose transform is a similarity (``pack``: rotation, uniform scale, translation) is
a world-space ball, tested without the object-space transform, with the quadratic solved
without cancellation (one root as q / a, the other as c / q), and its normal taken from its
centre. Its t and normal equal the reference's up to rounding (about 1e-15 relative), so a
pixel can change only where a ray grazes an edge or a shadow boundary exactly. Everything
is scalar: vectors are passed and returned as separate x, y, z values, so nothing
allocates. Literals are wrapped in ``F`` so the float32 option computes in float32
throughout.
"""

import math
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_SPHERE,
    HELPER_WRAPPERS,
    INLINE_HELPERS,
    F,
)
from variants.numba.layout import (
    BOUND,
    INV,
    K_SPHERE,
    KIND,
    NBOX,
    NF,
    NI,
    NRM,
    SPH_CENTER,
    SPH_R2,
    WORLD_SPHERE,
)

# ---- kernel template ----

# Helpers: compiled once, then inlined by LLVM into every caller (numba's own inlining,
# inline="always", copies the IR into each caller before typing: for a helper with many
# callers, several times slower to compile). Without the numba runtime (_nrt=False) they
# do no reference counting of the arrays they are passed, and they allocate nothing.
# ``pf``, ``pi`` ... are flat (see ``layout``): numpy arrays in the book-API kernels, raw
# pointers in the render.
INLINE: dict[str, Any] = {
    "forceinline": INLINE_HELPERS,
    "_nrt": False,
    "fastmath": FASTMATH,
    "error_model": "numpy",
    "no_cpython_wrapper": not HELPER_WRAPPERS,
    "no_cfunc_wrapper": not HELPER_WRAPPERS,
}
# The big steps with one caller in the render (its rows; a path's rows, bounces and lights):
# numba copies their IR into the caller before typing, so none is compiled, optimized and
# turned into machine code a second time as a library of its own with every helper below
# it linked in. Copying the Whitted steps below ``render_rows`` as well (``drain``,
# ``shade_and_push``, ``light_intensity``) cut more, but changed the machine code of the
# render's inner loop and slowed a render a few per cent; ``render_rows`` alone leaves it
# instruction for instruction as it was. The book API's module (``INLINE_HELPERS`` off)
# calls them: copying cost more than it saved there.
ONCE: dict[str, Any] = {**INLINE, "inline": "always"} if INLINE_HELPERS else INLINE
INF = F(np.inf)
ZERO = F(0.0)
ONE = F(1.0)
TWO = F(2.0)
THIRD = F(1.0 / 3.0)
PI = F(math.pi)


def _int_bits(typingctx, x):
    """The bits of float ``x`` as a signed integer of its width (a compact node's links,
    stored as such in its float row by the builder, ``bvh.node_links``; read without a
    conversion)."""
    width = x.bitwidth
    result = types.int64 if width == 64 else types.int32

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(width))

    return result(x), codegen


int_bits: Any = intrinsic(_int_bits)  # (called as int_bits(x): numba passes typingctx)


def _table_data(context, builder, table_type, table):
    """The pointer to a table's first value (an array's data, or a C entry's pointer)."""
    if isinstance(table_type, types.CPointer):
        return table
    return context.make_array(table_type)(context, builder, table).data


def _wide_enters(typingctx, table, m, near_x, near_y, near_z, ox, oy, oz, ix, iy, iz, thi):
    """The wide node at ``table[m]`` (``layout``): its four children's slab tests at once,
    as vector instructions (a row of WIDE values per side); ``near_*``: 0, or 3 * WIDE for
    a ray going down the axis. Returns where the ray enters each child (t >= 0), or INF
    where it misses it or enters it only beyond ``thi``: the same values as four
    ``kernels_hits.lane_enter`` (no NaN arises: every 1 / d is finite)."""
    dtype = table.dtype
    width = dtype.bitwidth
    signature = types.UniTuple(dtype, 4)(
        table, m, near_x, near_y, near_z, ox, oy, oz, ix, iy, iz, thi
    )

    def codegen(context, builder, signature, args):
        data = _table_data(context, builder, signature.args[0], args[0])
        real = context.get_value_type(dtype)
        vector = ir.VectorType(real, 4)
        at = context.cast(builder, args[1], signature.args[1], types.intp)
        near = [
            context.cast(builder, args[2 + a], signature.args[2 + a], types.intp) for a in range(3)
        ]

        def side(offset):  # the row of four values at table[m + offset]
            pointer = builder.gep(data, [builder.add(at, offset)])
            return builder.load(builder.bitcast(pointer, vector.as_pointer()), align=width // 8)

        def scalar(k):  # argument k in every lane
            value = context.cast(builder, args[k], signature.args[k], dtype)
            lanes = ir.Constant(vector, None)
            for j in range(4):
                lanes = builder.insert_element(lanes, value, ir.Constant(ir.IntType(32), j))
            return lanes

        def larger(a, b):
            return builder.select(builder.fcmp_ordered(">", a, b), a, b)

        def smaller(a, b):
            return builder.select(builder.fcmp_ordered("<", a, b), a, b)

        row = 4  # WIDE
        o = [scalar(5), scalar(6), scalar(7)]
        inverse = [scalar(8), scalar(9), scalar(10)]
        first = [side(builder.add(ir.Constant(at.type, a * row), near[a])) for a in range(3)]
        last = [side(builder.sub(ir.Constant(at.type, (3 + a) * row), near[a])) for a in range(3)]
        enters = [builder.fmul(builder.fsub(first[a], o[a]), inverse[a]) for a in range(3)]
        exits = [builder.fmul(builder.fsub(last[a], o[a]), inverse[a]) for a in range(3)]
        tlo = larger(larger(ir.Constant(vector, None), enters[0]), larger(enters[1], enters[2]))
        thi = smaller(smaller(scalar(11), exits[0]), smaller(exits[1], exits[2]))
        inf = ir.Constant(vector, [ir.Constant(real, float("inf"))] * 4)
        entry = builder.select(builder.fcmp_ordered("<=", tlo, thi), tlo, inf)
        lanes = [builder.extract_element(entry, ir.Constant(ir.IntType(32), j)) for j in range(4)]
        return context.make_tuple(builder, signature.return_type, lanes)

    return signature, codegen


def _int32_at(typingctx, table, k):
    """The int32 at int32 index ``k`` of the table (read as int32), as int64 (a wide node's
    links, ``layout``)."""

    def codegen(context, builder, signature, args):
        data = builder.bitcast(
            _table_data(context, builder, signature.args[0], args[0]), ir.IntType(32).as_pointer()
        )
        at = context.cast(builder, args[1], signature.args[1], types.intp)
        return builder.sext(builder.load(builder.gep(data, [at]), align=4), ir.IntType(64))

    return types.int64(table, k), codegen


int32_at: Any = intrinsic(_int32_at)  # (called without typingctx, as ``int_bits``)
wide_enters: Any = intrinsic(_wide_enters)


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
def box_span(boxes, m, ox, oy, oz, ix, iy, iz, thi, parallel):
    """Chapter 14 (bounding boxes): the stretch [tlo, thi] of t in [0, ``thi``] where the ray
    (origin, 1 / direction) is inside the box at ``boxes[m]`` (empty: tlo > thi). A ray
    ``parallel`` to no axis (every 1 / d finite, so no slab can give 0 * inf) skips
    ``slab``'s test for it and takes no branch."""
    if parallel:
        tlo, thi = slab(ox, ix, boxes[m], boxes[m + 3], ZERO, thi)
        tlo, thi = slab(oy, iy, boxes[m + 1], boxes[m + 4], tlo, thi)
        return slab(oz, iz, boxes[m + 2], boxes[m + 5], tlo, thi)
    x1 = (boxes[m] - ox) * ix
    x2 = (boxes[m + 3] - ox) * ix
    y1 = (boxes[m + 1] - oy) * iy
    y2 = (boxes[m + 4] - oy) * iy
    z1 = (boxes[m + 2] - oz) * iz
    z2 = (boxes[m + 5] - oz) * iz
    tlo = max(max(ZERO, min(x1, x2)), max(min(y1, y2), min(z1, z2)))
    return tlo, min(min(thi, max(x1, x2)), min(max(y1, y2), max(z1, z2)))


@njit(**INLINE)
def box_hit(boxes, b, ox, oy, oz, ix, iy, iz, thi, parallel):
    """``box_range`` from t = 0 to ``thi`` for box item b (its ITEM_D): the same answer."""
    tlo, thi = box_span(boxes, b * NBOX, ox, oy, oz, ix, iy, iz, thi, parallel)
    return tlo <= thi


@njit(**INLINE)
def box_enter(boxes, m, ox, oy, oz, ix, iy, iz, thi, parallel):
    """``box_hit`` for the box at ``boxes[m]`` (a compact node's): where the ray enters
    it (t >= 0), or INF when it misses it or enters it only beyond ``thi``."""
    tlo, thi = box_span(boxes, m, ox, oy, oz, ix, iy, iz, thi, parallel)
    return tlo if tlo <= thi else INF


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
