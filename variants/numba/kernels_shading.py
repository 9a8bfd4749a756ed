"""Kernel template, part 2: patterns (chapter 10), the Phong model (chapter 6), Schlick's
approximation and Snell's law (chapter 11), and n1/n2 from a list of intersections.

The arithmetic follows the reference's, with these shortcuts (each changes a color by far
less than 1/255):

- the unit vector towards the light is scaled by 1 / distance (one division, three
  multiplications) instead of three divisions;
- the specular term is left out where ``reflect_dot_eye ** shininess`` is below 1e-9
  (``pack.POW_FLOOR``), so ``pow`` runs only near highlights;
- Schlick's ``r0 = ((n1 - n2) / (n1 + n2))²`` and ``(1 - cos)⁵`` are multiplications, not
  ``pow`` (the reference's ``**``).
"""

# ruff: noqa: F401
import math
from typing import Any

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_CHECKERS,
    HAS_GRADIENT,
    HAS_PATTERNS,
    HAS_RING,
    HAS_STRIPE,
    HAS_TEST_PATTERN,
    F,
)
from variants.numba.kernels_geometry import INLINE, ONE, ZERO, normalized, to_object_point
from variants.numba.layout import (
    AMBIENT,
    COLOR,
    DIFFUSE,
    NF,
    NI,
    P_CHECKERS,
    P_GRADIENT,
    P_NONE,
    P_RING,
    P_STRIPE,
    PAT,
    PAT_A,
    PAT_B,
    PATTERN,
    POW_FLOOR,
    SHININESS,
    SPECULAR,
)

# ---- kernel template ----

API: dict[str, Any] = {"fastmath": FASTMATH, "error_model": "numpy", "cache": True}


@njit(**INLINE)
def pattern_a(pf, p):
    m = p * NF + PAT_A
    return pf[m], pf[m + 1], pf[m + 2]


@njit(**INLINE)
def pattern_b(pf, p):
    m = p * NF + PAT_B
    return pf[m], pf[m + 1], pf[m + 2]


@njit(**INLINE)
def local_pattern(pf, pi, p, x, y, z):
    """Chapter 10: primitive p's pattern color at a pattern-space point."""
    kind = pi[p * NI + PATTERN]
    if HAS_STRIPE and kind == P_STRIPE:
        if math.floor(x) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    if HAS_GRADIENT and kind == P_GRADIENT:
        fraction = x - math.floor(x)
        a = p * NF + PAT_A
        b = p * NF + PAT_B
        return (
            pf[a] + (pf[b] - pf[a]) * fraction,
            pf[a + 1] + (pf[b + 1] - pf[a + 1]) * fraction,
            pf[a + 2] + (pf[b + 2] - pf[a + 2]) * fraction,
        )
    if HAS_RING and kind == P_RING:
        if math.floor(math.sqrt(x * x + z * z)) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    if HAS_CHECKERS and kind == P_CHECKERS:
        if (math.floor(x) + math.floor(y) + math.floor(z)) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    return x, y, z  # the test pattern: the point itself


@njit(**INLINE)
def pattern_point(pf, p, x, y, z):
    """Chapter 10: an object-space point in the pattern's space."""
    m = p * NF + PAT
    return (
        pf[m + 0] * x + pf[m + 1] * y + pf[m + 2] * z + pf[m + 3],
        pf[m + 4] * x + pf[m + 5] * y + pf[m + 6] * z + pf[m + 7],
        pf[m + 8] * x + pf[m + 9] * y + pf[m + 10] * z + pf[m + 11],
    )


@njit(**INLINE)
def surface_color(pf, pi, p, x, y, z):
    """Chapters 6 and 10: the material's color at a world-space point: the pattern's when
    it has one (through the shape's and the pattern's transforms), else its own."""
    if HAS_PATTERNS and pi[p * NI + PATTERN] != P_NONE:
        ox, oy, oz = to_object_point(pf, p, x, y, z)
        px, py, pz = pattern_point(pf, p, ox, oy, oz)
        return local_pattern(pf, pi, p, px, py, pz)
    m = p * NF + COLOR
    return pf[m], pf[m + 1], pf[m + 2]


@njit(**INLINE)
def phong(pf, p, sr, sg, sb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz, light_dot_normal, lit,
          ambient_on):  # fmt: skip
    """Chapters 6 and 8: the Phong color of a surface of color (sr, sg, sb) (``surface_color``
    at the point) lit by the light at ``light[lm:lm + NLIGHT]``, given the unit vector (lx,
    ly, lz) towards it and its dot product with the normal; ``lit`` is False in shadow
    (ambient only); ``ambient_on`` False leaves the ambient term out (the second and later
    lights of a world: the ambient light is counted once)."""
    m = p * NF
    er = sr * light[lm + 3]
    eg = sg * light[lm + 4]
    eb = sb * light[lm + 5]
    ar = ZERO
    ag = ZERO
    ab = ZERO
    if ambient_on:
        ambient = pf[m + AMBIENT]
        ar = er * ambient
        ag = eg * ambient
        ab = eb * ambient
    if not lit or light_dot_normal < ZERO:
        return ar, ag, ab
    diffuse = pf[m + DIFFUSE]
    dr = er * diffuse * light_dot_normal
    dg = eg * diffuse * light_dot_normal
    db = eb * diffuse * light_dot_normal
    # reflect(-lightv, normalv)
    twice = -lx * nx + -ly * ny + -lz * nz
    rx = -lx - nx * F(2.0) * twice
    ry = -ly - ny * F(2.0) * twice
    rz = -lz - nz * F(2.0) * twice
    reflect_dot_eye = rx * ex + ry * ey + rz * ez
    specular = pf[m + SPECULAR]
    # (reflect_dot_eye <= 0 leaves the term out in the reference too; below the floor
    # the factor is under 1e-9)
    if reflect_dot_eye <= ZERO or specular == ZERO or reflect_dot_eye <= pf[m + POW_FLOOR]:
        return ar + dr, ag + dg, ab + db
    factor = math.pow(reflect_dot_eye, pf[m + SHININESS]) * specular
    return (
        ar + dr + light[lm + 3] * factor,
        ag + dg + light[lm + 4] * factor,
        ab + db + light[lm + 5] * factor,
    )


@njit(**INLINE)
def towards_light(light, x, y, z):
    """Chapters 6 and 8: the unit vector from (x, y, z) to the light, and the distance."""
    vx = light[0] - x
    vy = light[1] - y
    vz = light[2] - z
    distance = math.sqrt(vx * vx + vy * vy + vz * vz)
    scale = ONE / distance
    return vx * scale, vy * scale, vz * scale, distance


@njit(**INLINE)
def lighting_at(pf, pi, p, light, x, y, z, ex, ey, ez, nx, ny, nz, in_shadow, ambient_on):
    """Chapter 6: ``lighting(material, object, light, point, eyev, normalv, in_shadow,
    ambient)``."""
    lx, ly, lz, _ = towards_light(light, x, y, z)
    light_dot_normal = lx * nx + ly * ny + lz * nz
    sr, sg, sb = surface_color(pf, pi, p, x, y, z)
    return phong(
        pf, p, sr, sg, sb, light, 0, ex, ey, ez, nx, ny, nz, lx, ly, lz, light_dot_normal,
        not in_shadow, ambient_on,
    )  # fmt: skip


@njit(**INLINE)
def schlick_at(ex, ey, ez, nx, ny, nz, n1, n2):
    """Chapter 11: Schlick's approximation of the reflectance at a hit."""
    cos = ex * nx + ey * ny + ez * nz
    if n1 > n2:
        n = n1 / n2
        sin2_t = n * n * (ONE - cos * cos)
        if sin2_t > ONE:
            return ONE
        cos = math.sqrt(ONE - sin2_t)
    r = (n1 - n2) / (n1 + n2)
    r0 = r * r
    x = ONE - cos
    x2 = x * x
    return r0 + (ONE - r0) * (x2 * x2 * x)


@njit(**INLINE)
def refraction(ex, ey, ez, nx, ny, nz, n1, n2):
    """Chapter 11: Snell's law: (ok, direction); ok is False under total internal
    reflection."""
    n_ratio = n1 / n2
    cos_i = ex * nx + ey * ny + ez * nz
    sin2_t = n_ratio * n_ratio * (ONE - cos_i * cos_i)
    if sin2_t > ONE:
        return False, ZERO, ZERO, ZERO
    cos_t = math.sqrt(ONE - sin2_t)
    k = n_ratio * cos_i - cos_t
    return True, nx * k - ex * n_ratio, ny * k - ey * n_ratio, nz * k - ez * n_ratio


@njit(**API)
def containers_indices(ids, indices, hit_index):
    """Chapter 11: n1 and n2 for entry ``hit_index`` of a sorted intersection list, where
    ``ids[i]`` names entry i's object and ``indices[i]`` is that object's refractive index.
    The objects the ray is inside of are kept in the order they were entered, as the book's
    ``containers`` list; (1, 1) when ``hit_index`` is not in the list."""
    n = ids.shape[0]
    inside_ids = np.empty(n, np.int64)
    inside_indices = np.empty(n, F)
    depth = 0
    n1 = ONE
    n2 = ONE
    for i in range(n):
        if i == hit_index:
            n1 = inside_indices[depth - 1] if depth > 0 else ONE
        found = -1
        for j in range(depth):
            if inside_ids[j] == ids[i]:
                found = j
                break
        if found >= 0:
            for j in range(found, depth - 1):
                inside_ids[j] = inside_ids[j + 1]
                inside_indices[j] = inside_indices[j + 1]
            depth -= 1
        else:
            inside_ids[depth] = ids[i]
            inside_indices[depth] = indices[i]
            depth += 1
        if i == hit_index:
            n2 = inside_indices[depth - 1] if depth > 0 else ONE
            break
    return n1, n2
