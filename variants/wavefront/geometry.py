"""Each primitive kind's intersection and normal over arrays of rays (chapters 5, 9, 12, 13,
15), with the reference's arithmetic in the reference's order, so that a ray meets a shape
at the very t the reference computes.

A function takes the world-space rays as six arrays (``ox`` ... ``dz``) and the shape's
parameters as values that broadcast against them: scalars when one shape meets many rays,
arrays when each ray meets its own shape (pairs). ``m`` is the 12 numbers of rows 0-2 of
the world-to-object matrix. An intersection list is a list of t arrays, one per slot
(``scene.SLOTS``), in the order the reference's ``local_intersect`` lists them; ``inf``
where that slot has no intersection (an entry is one when ``t < inf``). NaN and overflow
follow IEEE rules (callers run under ``np.errstate(all="ignore")``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from variants.wavefront.quartic import KEPT, quartic_roots
from variants.wavefront.scene import CONE, CUBE, CYLINDER, PLANE, SMOOTH, SPHERE, TORUS, TRIANGLE

INF = np.inf
Arrays = tuple[Any, Any, Any]


def per_ray(value: Any) -> bool:
    """Is ``value`` an array of one value per ray (or per pair), not a scalar, None or a
    0-d array? (``np.ndim`` answers the same, but at a few microseconds a call it was a
    tenth of a pass's Python time: the loop between NumPy's calls holds the GIL that a
    second thread waits for.)"""
    return isinstance(value, np.ndarray) and value.ndim > 0


def _row(a: Any, b: Any, c: Any, d: Any, x: Any, y: Any, z: Any) -> Any:
    """``a * x + b * y + c * z + d`` added left to right; with scalar coefficients the
    terms whose coefficient is 0 are left out and a coefficient 1 is not multiplied (the
    same sum: adding a zero changes no sum but the sign of a zero one)."""
    if per_ray(a) or per_ray(b) or per_ray(c) or per_ray(d):
        if d is None:
            return a * x + b * y + c * z
        return a * x + b * y + c * z + d
    total: Any = None
    for coefficient, value in ((a, x), (b, y), (c, z), (d, None)):
        if coefficient is None or coefficient == 0:
            continue
        term = coefficient if value is None else value if coefficient == 1 else coefficient * value
        total = term if total is None else total + term
    if total is None:
        return np.zeros(np.shape(x), dtype=np.result_type(x))
    return total


def point_to_object(m: Any, x: Any, y: Any, z: Any) -> Arrays:
    """Chapter 3: ``inv * point(x, y, z)``, term by term as ``Matrix * Tuple`` adds them."""
    return (
        _row(m[0], m[1], m[2], m[3], x, y, z),
        _row(m[4], m[5], m[6], m[7], x, y, z),
        _row(m[8], m[9], m[10], m[11], x, y, z),
    )


def vector_to_object(m: Any, x: Any, y: Any, z: Any) -> Arrays:
    """Chapter 3: ``inv * vector(x, y, z)`` (the translation column meets w = 0)."""
    return (
        _row(m[0], m[1], m[2], None, x, y, z),
        _row(m[4], m[5], m[6], None, x, y, z),
        _row(m[8], m[9], m[10], None, x, y, z),
    )


def _none_where(t: Any, miss: Any) -> Any:
    """``t`` with ``inf`` where ``miss`` (a NaN stays NaN: no comparison lets it through)."""
    return np.where(miss, INF, t)


def sphere(ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any) -> list[Any]:
    """Chapter 5: the unit sphere (object space). The roots are computed for every ray when
    most rays meet it (then set to inf where the discriminant is negative), else only for
    those that do; either way each value is the reference's arithmetic in its order, summed
    in place to spare temporaries."""
    a = dx * dx
    a += dy * dy
    a += dz * dz
    b = dx * ox
    b += dy * oy
    b += dz * oz
    b *= 2
    c = ox * ox + oy * oy + oz * oz - 1
    discriminant = b * b
    discriminant -= 4 * a * c
    meet = discriminant >= 0
    if 2 * np.count_nonzero(meet) > meet.size:
        with np.errstate(invalid="ignore"):  # NaN where negative, set to inf below
            root = np.sqrt(discriminant)
        twice = a
        twice *= 2
        t1 = np.negative(b)
        t1 -= root
        t1 /= twice
        t2 = np.negative(b, out=b)
        t2 += root
        t2 /= twice
        miss = ~meet
        t1[miss] = INF
        t2[miss] = INF
        return [t1, t2]
    rows = np.flatnonzero(meet)
    t1 = np.full(discriminant.shape, INF, dtype=discriminant.dtype)
    t2 = t1.copy()
    if len(rows):
        b, root = b[rows], np.sqrt(discriminant[rows])
        twice = 2 * a[rows]
        t1[rows] = (-b - root) / twice
        t2[rows] = (-b + root) / twice
    return [t1, t2]


def plane(m: Any, ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, eps: float) -> list[Any]:
    """Chapter 9: the plane y = 0 (only the object-space y of the ray is needed)."""
    origin_y = _row(m[4], m[5], m[6], m[7], ox, oy, oz)
    direction_y = _row(m[4], m[5], m[6], None, dx, dy, dz)
    return [_none_where(-origin_y / direction_y, np.abs(direction_y) < eps)]


def _axis(origin: Any, direction: Any, eps: float) -> tuple[Any, Any]:
    """Chapter 12's ``check_axis``: (tmin, tmax) on one axis, nearest first."""
    tmin_numerator = -1 - origin
    tmax_numerator = 1 - origin
    far = np.abs(direction) >= eps
    tmin = np.where(far, tmin_numerator / direction, np.where(tmin_numerator <= 0, -INF, INF))
    tmax = np.where(far, tmax_numerator / direction, np.where(tmax_numerator >= 0, INF, -INF))
    return np.minimum(tmin, tmax), np.maximum(tmin, tmax)


def cube(ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, eps: float) -> list[Any]:
    """Chapter 12: the axis-aligned cube from -1 to 1."""
    xmin, xmax = _axis(ox, dx, eps)
    ymin, ymax = _axis(oy, dy, eps)
    zmin, zmax = _axis(oz, dz, eps)
    tmin = np.maximum(np.maximum(xmin, ymin), zmin)
    tmax = np.minimum(np.minimum(xmax, ymax), zmax)
    miss = tmin > tmax
    return [_none_where(tmin, miss), _none_where(tmax, miss)]


def _caps(
    ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, lo: Any, hi: Any, closed: Any,
    eps: float, cone: bool, gone: Any,
) -> list[Any]:  # fmt: skip
    """Chapter 13's ``intersect_caps``: the caps at y = lo and y = hi of a closed shape."""
    skip = ~(closed != 0) | (np.abs(dy) < eps) | gone
    out = []
    for y in (lo, hi):
        t = (y - oy) / dy
        x = ox + t * dx
        z = oz + t * dz
        r = np.abs(y) if cone else 1
        out.append(_none_where(t, skip | ~(x * x + z * z <= r * r)))
    return out


def _sides(t: Any, oy: Any, dy: Any, lo: Any, hi: Any, miss: Any) -> Any:
    """Chapter 13's ``side_hits``: keep t where lo < y < hi."""
    y = oy + t * dy
    return _none_where(t, miss | ~((lo < y) & (y < hi)))


def cylinder(
    ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, lo: Any, hi: Any, closed: Any,
    eps: float,
) -> list[Any]:  # fmt: skip
    """Chapter 13: the cylinder x² + z² = 1 between lo and hi, capped when closed."""
    a = dx * dx + dz * dz
    side = np.abs(a) >= eps
    b = 2 * ox * dx + 2 * oz * dz
    c = ox * ox + oz * oz - 1
    discriminant = b * b - 4 * a * c
    gone = side & (discriminant < 0)  # misses the infinite cylinder, so the caps too
    root = np.sqrt(np.where(gone, 0, discriminant))
    t0 = (-b - root) / (2 * a)
    t1 = (-b + root) / (2 * a)
    first, second = np.where(t0 > t1, t1, t0), np.where(t0 > t1, t0, t1)
    miss = ~side | gone
    return [
        _sides(first, oy, dy, lo, hi, miss),
        _sides(second, oy, dy, lo, hi, miss),
        *_caps(ox, oy, oz, dx, dy, dz, lo, hi, closed, eps, False, gone),
    ]


def cone(
    ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, lo: Any, hi: Any, closed: Any,
    eps: float,
) -> list[Any]:  # fmt: skip
    """Chapter 13: the double cone x² + z² = y² between lo and hi, capped when closed."""
    a = dx * dx - dy * dy + dz * dz
    b = 2 * (ox * dx - oy * dy + oz * dz)
    c = ox * ox - oy * oy + oz * oz
    flat = np.abs(a) < eps
    single = flat & (np.abs(b) >= eps)
    discriminant = b * b - 4 * a * c
    quadratic = ~flat & (discriminant >= 0)
    root = np.sqrt(np.where(quadratic, discriminant, 0))
    t0 = (-b - root) / (2 * a)
    t1 = (-b + root) / (2 * a)
    first = np.where(single, -c / (2 * b), np.where(t0 <= t1, t0, t1))
    second = np.where(t0 <= t1, t1, t0)
    return [
        _sides(first, oy, dy, lo, hi, ~(single | quadratic)),
        _sides(second, oy, dy, lo, hi, ~quadratic),
        *_caps(ox, oy, oz, dx, dy, dz, lo, hi, closed, eps, True, False),
    ]


def torus(ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, big: Any, small: Any) -> list[Any]:
    """Chapter 20 (beyond the book): the torus of radii ``big`` and ``small``: the real
    roots of its quartic (``raytracer.shapes.torus.torus_coefficients``) as ``robust``
    finds them (``variants.robust.geometry.torus_roots``): each ray's origin moved to its
    closest approach to the centre, the roots isolated and refined (``quartic``), a double
    root (a grazing ray) twice. In float64 under the float32 option too (in float32 whole
    stretches of tube are lost); returned in the rays' own type."""
    dtype = np.result_type(ox, dx)
    ox, oy, oz, dx, dy, dz, big, small = np.broadcast_arrays(
        *(np.asarray(v, dtype=np.float64) for v in (ox, oy, oz, dx, dy, dz, big, small))
    )
    with np.errstate(all="ignore"):
        dd = dx * dx + dy * dy + dz * dz
        lost = (dd == 0.0) | ~np.isfinite(dd)
        shift = -(ox * dx + oy * dy + oz * dz) / np.where(lost, 1.0, dd)
        ox, oy, oz = ox + shift * dx, oy + shift * dy, oz + shift * dz
        od = ox * dx + oy * dy + oz * dz
        oo = ox * ox + oy * oy + oz * oz
        k = oo + big * big - small * small
        four_r2 = 4 * big * big
        c = [
            dd * dd,
            4 * dd * od,
            2 * dd * k + 4 * od * od - four_r2 * (dx * dx + dz * dz),
            4 * od * k - 2 * four_r2 * (ox * dx + oz * dz),
            k * k - four_r2 * (ox * ox + oz * oz),
        ]
        lost |= ~np.logical_and.reduce([np.isfinite(v) for v in c])
        solved = np.nonzero(~lost)
        roots = [np.full(dd.shape, INF) for _ in range(KEPT)]
        if solved[0].size:
            found = quartic_roots([v[solved] for v in c])
            for root, ts in zip(roots, found, strict=True):
                moved = ts + shift[solved]
                root[solved] = np.where(np.isfinite(moved), moved, INF)
        roots = list(np.sort(np.stack(roots), axis=0))
    return [root.astype(dtype, copy=False) for root in roots]


def triangle(
    ox: Any, oy: Any, oz: Any, dx: Any, dy: Any, dz: Any, tri: Any, eps: float
) -> tuple[list[Any], Any, Any]:
    """Chapter 15: Möller–Trumbore; ``tri``: p1, e1, e2 (9 values). Returns ([t], u, v)."""
    p1x, p1y, p1z, e1x, e1y, e1z, e2x, e2y, e2z = tri[:9]
    cx = dy * e2z - dz * e2y
    cy = dz * e2x - dx * e2z
    cz = dx * e2y - dy * e2x
    det = e1x * cx + e1y * cy + e1z * cz
    f = 1.0 / det
    px = ox - p1x
    py = oy - p1y
    pz = oz - p1z
    u = f * (px * cx + py * cy + pz * cz)
    qx = py * e1z - pz * e1y
    qy = pz * e1x - px * e1z
    qz = px * e1y - py * e1x
    v = f * (dx * qx + dy * qy + dz * qz)
    t = f * (e2x * qx + e2y * qy + e2z * qz)
    miss = (np.abs(det) < eps) | (u < 0) | (u > 1) | (v < 0) | (u + v > 1)
    return [_none_where(t, miss)], u, v


def intersect(kind: int, m: Any, params: Any, ray: Any, eps: float) -> tuple[list[Any], Any, Any]:
    """The intersection list of a ray (world space, six arrays) with primitives of ``kind``
    whose world-to-object rows are ``m`` and own parameters ``params`` (cylinders and cones:
    minimum, maximum, closed; triangles: p1, e1, e2: ``hits.params``); (ts, u, v), u and v
    None but for triangles."""
    ox, oy, oz, dx, dy, dz = ray
    if kind == PLANE:
        return plane(m, ox, oy, oz, dx, dy, dz, eps), None, None
    lox, loy, loz = point_to_object(m, ox, oy, oz)
    ldx, ldy, ldz = vector_to_object(m, dx, dy, dz)
    if kind == SPHERE:
        return sphere(lox, loy, loz, ldx, ldy, ldz), None, None
    if kind == CUBE:
        return cube(lox, loy, loz, ldx, ldy, ldz, eps), None, None
    if kind == CYLINDER:
        return (
            cylinder(lox, loy, loz, ldx, ldy, ldz, params[0], params[1], params[2], eps),
            None,
            None,
        )
    if kind == CONE:
        return cone(lox, loy, loz, ldx, ldy, ldz, params[0], params[1], params[2], eps), None, None
    if kind == TORUS:
        return torus(lox, loy, loz, ldx, ldy, ldz, params[0], params[1]), None, None
    if kind in (TRIANGLE, SMOOTH):
        return triangle(lox, loy, loz, ldx, ldy, ldz, params, eps)
    raise ValueError(f"wavefront: unknown primitive kind {kind}")


def local_normal(
    kind: int, x: Any, y: Any, z: Any, params: Any, u: Any, v: Any, eps: float
) -> Arrays:
    """Chapters 6, 9, 12, 13, 15: the object-space normal at object-space points (x, y, z);
    ``params``: cylinders and cones: minimum, maximum; triangles: the face normal; smooth
    triangles: n1, n2, n3 (``hits.params(..., normals=True)``)."""
    zero = np.zeros_like(x)
    if kind == SPHERE:
        return x, y, z
    if kind == PLANE:
        return zero, zero + 1, zero
    if kind == CUBE:
        ax, ay, az = np.abs(x), np.abs(y), np.abs(z)
        largest = np.maximum(np.maximum(ax, ay), az)
        on_x = largest == ax
        on_y = ~on_x & (largest == ay)
        on_z = ~on_x & ~on_y
        return np.where(on_x, x, zero), np.where(on_y, y, zero), np.where(on_z, z, zero)
    if kind in (CYLINDER, CONE):
        lo, hi = params[0], params[1]
        distance = x * x + z * z
        if kind == CYLINDER:
            up = (distance < 1) & (y >= hi - eps)
            down = ~up & (distance < 1) & (y <= lo + eps)
            side_y = zero
        else:
            up = (distance < hi * hi) & (y >= hi - eps)
            down = ~up & (distance < lo * lo) & (y <= lo + eps)
            side_y = np.sqrt(distance)
            side_y = np.where(y > 0, -side_y, side_y)
        cap = up | down
        return (
            np.where(cap, zero, x),
            np.where(up, zero + 1, np.where(down, zero - 1, side_y)),
            np.where(cap, zero, z),
        )
    if kind == TORUS:
        across = np.sqrt(x * x + z * z)
        axis = across == 0
        scale = params[0] / np.where(axis, 1, across)
        up = np.where(y >= 0, zero + 1, zero - 1)
        return (
            np.where(axis, zero, x - x * scale),
            np.where(axis, up, y),
            np.where(axis, zero, z - z * scale),
        )
    if kind == TRIANGLE:
        return zero + params[0], zero + params[1], zero + params[2]
    if kind == SMOOTH:
        n1x, n1y, n1z, n2x, n2y, n2z, n3x, n3y, n3z = params[0:9]
        w = 1 - u - v
        return (
            n2x * u + n3x * v + n1x * w,
            n2y * u + n3y * v + n1y * w,
            n2z * u + n3z * v + n1z * w,
        )
    raise ValueError(f"wavefront: unknown primitive kind {kind}")


def normal_to_world(n: Any, x: Any, y: Any, z: Any) -> Arrays:
    """Chapter 6's ``normal_to_world``: the inverse's transpose (3x3 rows ``n``) times the
    normal, normalized (a zero normal, a cone's tip, stays zero)."""
    wx = _row(n[0], n[1], n[2], None, x, y, z)
    wy = _row(n[3], n[4], n[5], None, x, y, z)
    wz = _row(n[6], n[7], n[8], None, x, y, z)
    length = np.sqrt(wx * wx + wy * wy + wz * wz)
    zero = length == 0
    length = np.where(zero, 1, length)
    return wx / length, wy / length, wz / length
