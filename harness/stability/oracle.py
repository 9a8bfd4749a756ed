"""Oracles: the exact answers the stability cases compare with.

Every oracle takes the float inputs a variant was given (the float64 values of a ray's
origin and direction, a matrix's entries) as exact numbers and works in exact rational
arithmetic (``fractions.Fraction``) as far as it can, then in 60-digit ``mpmath`` for square
roots and trigonometry. So the oracle answers for exactly the inputs the variant saw, and a
difference is the variant's rounding (or its method), never the oracle's.

Conventions follow the book: intersections are a multiset of distances ``t`` (a tangent ray
gives the same ``t`` twice), a ray along a surface or exactly parallel to a plane meets
nothing, bounded cylinders and cones keep side hits with ``minimum < y < maximum``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction

import mpmath

DIGITS = 60
Vec = tuple[float, float, float]
Rows = Sequence[Sequence[float]]


def exact(value: float) -> Fraction:
    """A float (or int) as the exact rational it is."""
    return Fraction(value)


def _mp(value: Fraction) -> mpmath.mpf:
    return mpmath.mpf(value.numerator) / value.denominator


def _q(v: Vec) -> tuple[Fraction, Fraction, Fraction]:
    return exact(v[0]), exact(v[1]), exact(v[2])


def _roots(a: Fraction, half_b: Fraction, c: Fraction) -> list[mpmath.mpf]:
    """The real roots of ``a t² + 2 half_b t + c`` (``a != 0``), smaller first."""
    disc = half_b * half_b - a * c
    if disc < 0:
        return []
    with mpmath.workdps(DIGITS):
        root = mpmath.sqrt(_mp(disc))
        t0 = (-_mp(half_b) - root) / _mp(a)
        t1 = (-_mp(half_b) + root) / _mp(a)
    return sorted([t0, t1])


def sphere_ts(origin: Vec, direction: Vec, center: Vec, radius: float = 1.0) -> list[mpmath.mpf]:
    """Chapter 5: where the line ``origin + t direction`` meets the sphere (0 or 2 values)."""
    o = [a - b for a, b in zip(_q(origin), _q(center), strict=True)]
    d = _q(direction)
    a = sum((x * x for x in d), Fraction(0))
    half_b = sum((x * y for x, y in zip(o, d, strict=True)), Fraction(0))
    c = sum((x * x for x in o), Fraction(0)) - exact(radius) ** 2
    return _roots(a, half_b, c)


def plane_ts(origin: Vec, direction: Vec) -> list[mpmath.mpf]:
    """Chapter 9: the plane y = 0; nothing for a direction exactly parallel to it."""
    oy, dy = exact(origin[1]), exact(direction[1])
    if dy == 0:
        return []
    return [_mp(-oy / dy)]


def cube_ts(origin: Vec, direction: Vec) -> list[mpmath.mpf]:
    """Chapter 12: the closed cube [-1, 1]³ (a ray touching an edge or a corner hits it)."""
    lo, hi = Fraction(-(10**400)), Fraction(10**400)  # stand-ins for -inf, +inf
    tmin, tmax = lo, hi
    for o, d in zip(_q(origin), _q(direction), strict=True):
        if d == 0:
            if not -1 <= o <= 1:
                return []
            continue
        t0, t1 = sorted(((-1 - o) / d, (1 - o) / d))
        tmin, tmax = max(tmin, t0), min(tmax, t1)
    if tmin > tmax or tmin == lo or tmax == hi:
        return []
    return [_mp(tmin), _mp(tmax)]


def _caps(
    origin: Vec, direction: Vec, minimum: float, maximum: float, radius_is_y: bool
) -> list[mpmath.mpf]:
    """The caps of a closed cylinder (radius 1) or cone (radius |y|) at finite bounds."""
    o, d = _q(origin), _q(direction)
    if d[1] == 0:
        return []
    found = []
    for bound in (minimum, maximum):
        if math.isinf(bound):
            continue
        y = exact(bound)
        t = (y - o[1]) / d[1]
        x, z = o[0] + t * d[0], o[2] + t * d[2]
        radius = abs(y) if radius_is_y else 1
        if x * x + z * z <= radius * radius:
            found.append(_mp(t))
    return found


def _bounded(
    ts: list[mpmath.mpf], origin: Vec, direction: Vec, lo: float, hi: float
) -> list[mpmath.mpf]:
    """The ``ts`` whose point has ``lo < y < hi``."""
    kept = []
    with mpmath.workdps(DIGITS):
        for t in ts:
            y = mpmath.mpf(origin[1]) + t * mpmath.mpf(direction[1])
            if (math.isinf(lo) or y > lo) and (math.isinf(hi) or y < hi):
                kept.append(t)
    return kept


def cylinder_ts(
    origin: Vec,
    direction: Vec,
    minimum: float = -math.inf,
    maximum: float = math.inf,
    closed: bool = False,
) -> list[mpmath.mpf]:
    """Chapter 13: the cylinder x² + z² = 1 (a line along its surface meets nothing)."""
    o, d = _q(origin), _q(direction)
    a = d[0] * d[0] + d[2] * d[2]
    side: list[mpmath.mpf] = []
    if a != 0:
        half_b = o[0] * d[0] + o[2] * d[2]
        c = o[0] * o[0] + o[2] * o[2] - 1
        if half_b * half_b - a * c < 0:
            return []
        side = _bounded(_roots(a, half_b, c), origin, direction, minimum, maximum)
    caps = _caps(origin, direction, minimum, maximum, False) if closed else []
    return sorted(side + caps)


def cone_ts(
    origin: Vec,
    direction: Vec,
    minimum: float = -math.inf,
    maximum: float = math.inf,
    closed: bool = False,
) -> list[mpmath.mpf]:
    """Chapter 13: the double cone x² + z² = y². Parallel to one half, the one true
    intersection ``-c / 2 half_b`` (the book's scenario expects half of it: an erratum). A
    line lying on the surface meets nothing."""
    o, d = _q(origin), _q(direction)
    a = d[0] * d[0] - d[1] * d[1] + d[2] * d[2]
    half_b = o[0] * d[0] - o[1] * d[1] + o[2] * d[2]
    c = o[0] * o[0] - o[1] * o[1] + o[2] * o[2]
    if a != 0:
        side = _roots(a, half_b, c)
    elif half_b != 0:
        side = [_mp(-c / (2 * half_b))]
    else:
        side = []
    side = _bounded(side, origin, direction, minimum, maximum)
    caps = _caps(origin, direction, minimum, maximum, True) if closed else []
    return sorted(side + caps)


def _trim(p: list[Fraction]) -> list[Fraction]:
    """``p`` (highest power first) without leading zeros."""
    while p and p[0] == 0:
        p = p[1:]
    return p


def _divide(p: list[Fraction], q: list[Fraction]) -> tuple[list[Fraction], list[Fraction]]:
    """Quotient and remainder of ``p / q`` (exact)."""
    p = list(p)
    quotient: list[Fraction] = []
    while len(p) >= len(q):
        factor = p[0] / q[0]
        quotient.append(factor)
        p = [a - factor * b for a, b in zip(p, [*q, *[Fraction(0)] * (len(p) - len(q))],
                                            strict=True)][1:]  # fmt: skip
    return quotient, _trim(p)


def _gcd(p: list[Fraction], q: list[Fraction]) -> list[Fraction]:
    while q:
        p, q = q, _divide(p, q)[1]
    return [a / p[0] for a in p]


def polynomial_real_roots(p: Sequence[Fraction]) -> list[mpmath.mpf]:
    """The real roots of an exact polynomial (highest power first), increasing, each as
    often as its multiplicity. ``p`` is the product of its square-free part ``p / g`` (each
    root once) and ``g = gcd(p, p')`` (each root one time fewer), both exact; the square-free
    part's simple roots are found to 60 digits (``mpmath.polyroots``) and those with an
    imaginary part below 1e-40 of their size are real."""
    p = _trim(list(p))
    if len(p) <= 1:
        return []
    n = len(p) - 1
    g = _gcd(p, [a * (n - i) for i, a in enumerate(p[:-1])])
    square_free = _divide(p, g)[0]
    with mpmath.workdps(DIGITS):
        found = mpmath.polyroots(
            [_mp(a) for a in reversed(square_free)], maxsteps=400, extraprec=400, asc=True
        )
        simple = [
            mpmath.re(z) for z in (found if isinstance(found, list) else [found])
            if abs(mpmath.im(z)) <= mpmath.mpf(10) ** -40 * (1 + abs(z))
        ]  # fmt: skip
    return sorted(simple + (polynomial_real_roots(g) if len(g) > 1 else []))


def torus_ts(origin: Vec, direction: Vec, major: float, minor: float) -> list[mpmath.mpf]:
    """Chapter 20 here: where the line meets (x² + y² + z² + R² - r²)² = 4 R² (x² + z²), a
    quartic in t with exact coefficients; a tangent ray's double root twice."""
    (ox, oy, oz), (dx, dy, dz) = _q(origin), _q(direction)
    big, small = exact(major), exact(minor)
    dd = dx * dx + dy * dy + dz * dz
    od = ox * dx + oy * dy + oz * dz
    k = ox * ox + oy * oy + oz * oz + big * big - small * small
    four_r2 = 4 * big * big
    return polynomial_real_roots([
        dd * dd,
        4 * dd * od,
        2 * dd * k + 4 * od * od - four_r2 * (dx * dx + dz * dz),
        4 * od * k - 2 * four_r2 * (ox * dx + oz * dz),
        k * k - four_r2 * (ox * ox + oz * oz),
    ])  # fmt: skip


def triangle_t(origin: Vec, direction: Vec, corners: Sequence[Vec]) -> list[Fraction]:
    """Chapter 15: where the ray meets the triangle (its closed interior); nothing for a
    triangle of zero area or a ray in its plane."""
    p1, p2, p3 = (_q(p) for p in corners)
    o, d = _q(origin), _q(direction)
    e1 = [b - a for a, b in zip(p1, p2, strict=True)]
    e2 = [b - a for a, b in zip(p1, p3, strict=True)]
    normal = _cross(e1, e2)
    if not any(normal):
        return []
    denominator = sum(n * x for n, x in zip(normal, d, strict=True))
    if denominator == 0:
        return []
    t = sum(n * (a - b) for n, a, b in zip(normal, p1, o, strict=True)) / denominator
    p = [a + t * b for a, b in zip(o, d, strict=True)]
    # barycentric test: p is inside when it lies on the inner side of every edge
    for a, b in ((p1, p2), (p2, p3), (p3, p1)):
        edge = [y - x for x, y in zip(a, b, strict=True)]
        to_p = [y - x for x, y in zip(a, p, strict=True)]
        if sum(n * x for n, x in zip(normal, _cross(edge, to_p), strict=True)) < 0:
            return []
    return [t]


def _cross(a: Sequence[Fraction], b: Sequence[Fraction]) -> list[Fraction]:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


# ------------------------------------------------------------------------- matrices


def exact_inverse(rows: Rows) -> list[list[Fraction]] | None:
    """The exact inverse of a square float matrix (Gauss-Jordan in rationals), or None when
    it is singular."""
    n = len(rows)
    m = [
        [exact(v) for v in row] + [Fraction(int(i == j)) for j in range(n)]
        for i, row in enumerate(rows)
    ]
    for col in range(n):
        pivot = next((r for r in range(col, n) if m[r][col] != 0), None)
        if pivot is None:
            return None
        m[col], m[pivot] = m[pivot], m[col]
        scale = m[col][col]
        m[col] = [v / scale for v in m[col]]
        for r in range(n):
            if r != col and m[r][col] != 0:
                factor = m[r][col]
                m[r] = [v - factor * w for v, w in zip(m[r], m[col], strict=True)]
    return [row[n:] for row in m]


def norm_inf(rows: Sequence[Sequence[Fraction | float]]) -> Fraction:
    """The infinity norm (largest absolute row sum), exactly."""
    return max(sum((abs(Fraction(v)) for v in row), Fraction(0)) for row in rows)


def condition_number(rows: Rows) -> float:
    """κ∞ = |M|∞ |M⁻¹|∞ of the float matrix, exactly (as a float); inf when singular."""
    inv = exact_inverse(rows)
    if inv is None:
        return float("inf")
    return float(norm_inf([[exact(v) for v in row] for row in rows]) * norm_inf(inv))


# ------------------------------------------------------------------------ shading


def schlick(n1: float, n2: float, cos_i: mpmath.mpf) -> mpmath.mpf:
    """Chapter 11: Schlick's reflectance, exactly, for the cosine of incidence ``cos_i``;
    1 under total internal reflection."""
    with mpmath.workdps(DIGITS):
        n1m, n2m = mpmath.mpf(n1), mpmath.mpf(n2)
        cos = cos_i
        if n1m > n2m:
            sin2_t = (n1m / n2m) ** 2 * (1 - cos_i * cos_i)
            if sin2_t > 1:
                return mpmath.mpf(1)
            cos = mpmath.sqrt(1 - sin2_t)
        r0 = ((n1m - n2m) / (n1m + n2m)) ** 2
        return r0 + (1 - r0) * (1 - cos) ** 5


def total_internal_reflection(n1: float, n2: float, sin_i: mpmath.mpf) -> bool:
    """Whether light going from index ``n1`` to ``n2`` at sin(incidence) ``sin_i`` is
    totally reflected, exactly."""
    with mpmath.workdps(DIGITS):
        return bool(mpmath.mpf(n1) / mpmath.mpf(n2) * sin_i > 1)


# ------------------------------------------------------------------------- the camera


def camera_directions(
    hsize: int, vsize: int, field_of_view: float, view: Rows
) -> dict[tuple[int, int], tuple[mpmath.mpf, mpmath.mpf, mpmath.mpf]]:
    """Chapter 7: the exact unit direction of the ray through the centre of every pixel of
    a camera with the float ``field_of_view`` and view transform ``view`` (rows)."""
    inv = exact_inverse(view)
    if inv is None:
        raise ValueError("camera_directions: the view transform is singular")
    directions = {}
    with mpmath.workdps(DIGITS):
        m = [[_mp(v) for v in row] for row in inv]
        half_view = mpmath.tan(mpmath.mpf(field_of_view) / 2)
        aspect = mpmath.mpf(hsize) / vsize
        if aspect >= 1:
            half_width, half_height = half_view, half_view / aspect
        else:
            half_width, half_height = half_view * aspect, half_view
        pixel_size = half_width * 2 / hsize
        origin = [m[r][3] for r in range(3)]
        for py in range(vsize):
            for px in range(hsize):
                x = half_width - (px + mpmath.mpf(0.5)) * pixel_size
                y = half_height - (py + mpmath.mpf(0.5)) * pixel_size
                p = [m[r][0] * x + m[r][1] * y - m[r][2] + m[r][3] for r in range(3)]
                d = [a - b for a, b in zip(p, origin, strict=True)]
                length = mpmath.sqrt(sum(v * v for v in d))
                directions[(px, py)] = (d[0] / length, d[1] / length, d[2] / length)
    return directions
