"""Kernel template, part 2: patterns (chapter 10) and texture maps (the bonus chapter
"Texture mapping"), the Phong model (chapter 6) with point and area lights (the bonus
chapter "Rendering soft shadows": the cells' points, jittered by ``light_jitter``, the
reference's splitmix64 in uint64 arithmetic), Schlick's approximation and Snell's law
(chapter 11), and n1/n2 from a list of intersections.

The arithmetic follows the reference's, with these shortcuts (each changes a color by far
less than 1/255):

- the unit vector towards the light is scaled by 1 / distance (one division, three
  multiplications) instead of three divisions;
- the specular term is left out where ``reflect_dot_eye ** shininess`` is below 1e-9
  (``pack.POW_FLOOR``), so ``pow`` runs only near highlights;
- Schlick's ``r0 = ((n1 - n2) / (n1 + n2))²`` and ``(1 - cos)⁵`` are multiplications, not
  ``pow`` (the reference's ``**``).
"""

import math
from typing import Any

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_AREA_LIGHTS,
    HAS_CHECKERS_PATTERN,
    HAS_CUBE_MAP,
    HAS_GRADIENT_PATTERN,
    HAS_JITTER,
    HAS_PATTERNS,
    HAS_RING_PATTERN,
    HAS_STRIPE_PATTERN,
    HAS_TEXTURE_MAP,
    HAS_UV_IMAGE,
    F,
)
from variants.numba.kernels_geometry import (
    INLINE,
    ONE,
    ZERO,
    normalized,
    to_object_point,
)
from variants.numba.layout import (
    AMBIENT,
    COLOR,
    DIFFUSE,
    FACE_BACK,
    FACE_DOWN,
    FACE_FRONT,
    FACE_LEFT,
    FACE_RIGHT,
    FACE_UP,
    LIGHT_CORNER,
    LIGHT_JITTER,
    LIGHT_SEQ,
    LIGHT_SEQ_AT,
    LIGHT_SEQ_N,
    LIGHT_USTEPS,
    LIGHT_UVEC,
    LIGHT_VSTEPS,
    LIGHT_VVEC,
    M_CUBE,
    M_CYLINDRICAL,
    M_PLANAR,
    MAP_KIND,
    MAP_UV,
    NF,
    NI,
    P_CHECKERS,
    P_CUBE_MAP,
    P_GRADIENT,
    P_MAP,
    P_NONE,
    P_RING,
    P_STRIPE,
    PAT,
    PAT_A,
    PAT_B,
    PAT_TEX,
    PATTERN,
    POW_FLOOR,
    SHININESS,
    SPECULAR,
    UV_AT,
    UV_CHECKERS,
    UV_HEIGHT,
    UV_IMAGE,
    UV_KIND,
    UV_WIDTH,
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
def tex_color(tf, at):
    """Three floats of ``tf`` from ``at``: a color of a texture pattern."""
    return tf[at], tf[at + 1], tf[at + 2]


@njit(**INLINE)
def nearest(x):
    """Python's ``round(x)`` of a float: the nearest integer, halves to the even one."""
    below = math.floor(x)
    rest = x - below  # exact: both are in the same binade or below
    if rest > F(0.5):
        return below + 1
    if rest < F(0.5):
        return below
    return below + below % 2


@njit(**INLINE)
def uv_color(ti, tf, q, u, v):
    """The bonus chapter on texture mapping: ``uv_pattern_at`` of the uv pattern whose
    record starts at ``ti[q]`` (``layout``: checkers, align check, image)."""
    kind = ti[q + UV_KIND]
    at = ti[q + UV_AT]
    if kind == UV_CHECKERS:
        if (math.floor(u * tf[at]) + math.floor(v * tf[at + 1])) % 2 == 0:
            return tex_color(tf, at + 2)
        return tex_color(tf, at + 5)
    if HAS_UV_IMAGE and kind == UV_IMAGE:
        width = ti[q + UV_WIDTH]
        height = ti[q + UV_HEIGHT]
        x = nearest(u * F(width - 1))
        y = nearest((ONE - v) * F(height - 1))
        # (u and v from a mapping are in [0, 1]: the clamps only keep the lookup inside)
        x = min(max(x, 0), width - 1)
        y = min(max(y, 0), height - 1)
        return tex_color(tf, at + (y * width + x) * 3)
    # align check: main, then the corners ul, ur, bl, br
    if v > F(0.8):
        if u < F(0.2):
            return tex_color(tf, at + 3)
        if u > F(0.8):
            return tex_color(tf, at + 6)
    elif v < F(0.2):
        if u < F(0.2):
            return tex_color(tf, at + 9)
        if u > F(0.8):
            return tex_color(tf, at + 12)
    return tex_color(tf, at)


@njit(**INLINE)
def map_uv(mapping, x, y, z):
    """The bonus chapter on texture mapping: (u, v) of a pattern-space point by
    ``spherical_map``, ``planar_map`` or ``cylindrical_map``."""
    if mapping == M_PLANAR:
        return x % ONE, z % ONE
    theta = math.atan2(x, z)
    raw_u = theta / (F(2.0) * F(math.pi))
    u = ONE - (raw_u + F(0.5))
    if mapping == M_CYLINDRICAL:
        return u, y % ONE
    radius = math.sqrt(x * x + y * y + z * z)
    phi = F(math.pi / 2.0)  # the origin (no direction): the equator
    if radius > ZERO:
        phi = F(math.acos(max(-ONE, min(ONE, y / radius))))
    return u, ONE - phi / F(math.pi)


@njit(**INLINE)
def cube_face(x, y, z):
    """The bonus chapter on texture mapping: ``face_from_point``: the face whose axis
    has the largest absolute coordinate (ties: right, left, up, down, front, back)."""
    coord = max(abs(x), abs(y), abs(z))
    if coord == x:
        return FACE_RIGHT
    if coord == -x:
        return FACE_LEFT
    if coord == y:
        return FACE_UP
    if coord == -y:
        return FACE_DOWN
    if coord == z:
        return FACE_FRONT
    return FACE_BACK


@njit(**INLINE)
def cube_uv(face, x, y, z):
    """The bonus chapter on texture mapping: ``cube_uv_front`` ... ``cube_uv_down``."""
    two = F(2.0)
    if face == FACE_FRONT:
        return ((x + ONE) % two) / two, ((y + ONE) % two) / two
    if face == FACE_BACK:
        return ((ONE - x) % two) / two, ((y + ONE) % two) / two
    if face == FACE_LEFT:
        return ((z + ONE) % two) / two, ((y + ONE) % two) / two
    if face == FACE_RIGHT:
        return ((ONE - z) % two) / two, ((y + ONE) % two) / two
    if face == FACE_UP:
        return ((x + ONE) % two) / two, ((ONE - z) % two) / two
    return ((x + ONE) % two) / two, ((z + ONE) % two) / two


@njit(**INLINE)
def texture_color(ti, tf, r, x, y, z):
    """The bonus chapter on texture mapping: the color at a pattern-space point of the
    texture pattern whose map record starts at ``ti[r]``: a cube map's face's uv pattern,
    or the uv pattern at the mapping's (u, v)."""
    mapping = ti[r + MAP_KIND]
    if HAS_CUBE_MAP and mapping == M_CUBE:
        face = cube_face(x, y, z)
        u, v = cube_uv(face, x, y, z)
        return uv_color(ti, tf, ti[r + MAP_UV + face], u, v)
    u, v = map_uv(mapping, x, y, z)
    return uv_color(ti, tf, ti[r + MAP_UV], u, v)


@njit(**INLINE)
def local_pattern(pf, pi, tex, p, x, y, z):
    """Chapter 10: primitive p's pattern color at a pattern-space point; the bonus
    chapter's texture patterns read their records from ``tex`` = (ti, tf)."""
    kind = pi[p * NI + PATTERN]
    if HAS_STRIPE_PATTERN and kind == P_STRIPE:
        if math.floor(x) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    if HAS_GRADIENT_PATTERN and kind == P_GRADIENT:
        fraction = x - math.floor(x)
        a = p * NF + PAT_A
        b = p * NF + PAT_B
        return (
            pf[a] + (pf[b] - pf[a]) * fraction,
            pf[a + 1] + (pf[b + 1] - pf[a + 1]) * fraction,
            pf[a + 2] + (pf[b + 2] - pf[a + 2]) * fraction,
        )
    if HAS_RING_PATTERN and kind == P_RING:
        if math.floor(math.sqrt(x * x + z * z)) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    if HAS_CHECKERS_PATTERN and kind == P_CHECKERS:
        if (math.floor(x) + math.floor(y) + math.floor(z)) % 2 == 0:
            return pattern_a(pf, p)
        return pattern_b(pf, p)
    if (HAS_TEXTURE_MAP and kind == P_MAP) or (HAS_CUBE_MAP and kind == P_CUBE_MAP):
        ti, tf = tex
        return texture_color(ti, tf, pi[p * NI + PAT_TEX], x, y, z)
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
def surface_color(pf, pi, tex, p, x, y, z):
    """Chapters 6 and 10: the material's color at a world-space point: the pattern's when
    it has one (through the shape's and the pattern's transforms), else its own."""
    if HAS_PATTERNS and pi[p * NI + PATTERN] != P_NONE:
        ox, oy, oz = to_object_point(pf, p, x, y, z)
        px, py, pz = pattern_point(pf, p, ox, oy, oz)
        return local_pattern(pf, pi, tex, p, px, py, pz)
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


GAMMA = np.uint64(0x9E3779B97F4A7C15)  # raytracer.sampling.GAMMA
MIX1 = np.uint64(0xBF58476D1CE4E5B9)
MIX2 = np.uint64(0x94D049BB133111EB)
UNIT53 = 2.0**-53


@njit(**INLINE)
def mix64(z):
    """splitmix64's output function (``raytracer.sampling.mix64``)."""
    z = (z ^ (z >> np.uint64(30))) * MIX1
    z = (z ^ (z >> np.uint64(27))) * MIX2
    return z ^ (z >> np.uint64(31))


@njit(**INLINE)
def light_jitter(key, k, u, v):
    """``raytracer.sampling.light_jitter`` bit for bit: where in its cell (u, v) the point
    of light k goes for the sample whose key (``sample_key``) is ``key``: (ju, jv), each
    in [0, 1), from two splitmix64 outputs of the stream 3 + 2 (k << 32 | v << 16 | u)."""
    stream = np.uint64(3) + np.uint64(2) * (
        (np.uint64(k) << np.uint64(32)) | (np.uint64(v) << np.uint64(16)) | np.uint64(u)
    )
    first = mix64(key + stream * GAMMA)
    second = mix64(key + (stream + np.uint64(1)) * GAMMA)
    return np.float64(first >> np.uint64(11)) * UNIT53, np.float64(second >> np.uint64(11)) * UNIT53


@njit(**INLINE)
def cell_point(light, lm, seq0, k, u, v, cell, key):
    """The bonus chapter on soft shadows: ``point_on_light`` for cell (u, v) (number
    ``cell`` = v usteps + u) of light k, whose row is ``light[lm:lm + NLIGHT]``: corner +
    uvec (u + ju) + vvec (v + jv), the jitter at random (``light_jitter``) or from the
    light's sequence (its values from ``light[seq0 + LIGHT_SEQ]``; a cell takes two, in
    order, from where the sequence stands: the packer checks that its length divides the
    2 usteps vsteps values ``intensity_at`` and ``lighting`` each take, so that every
    call starts where the last one did)."""
    if HAS_JITTER and light[lm + LIGHT_JITTER] != ZERO:
        random_u, random_v = light_jitter(key, k, u, v)
        ju = F(random_u)
        jv = F(random_v)
    else:
        n = int(light[lm + LIGHT_SEQ_N])
        at = seq0 + int(light[lm + LIGHT_SEQ])
        start = int(light[lm + LIGHT_SEQ_AT])
        ju = light[at + (start + 2 * cell) % n]
        jv = light[at + (start + 2 * cell + 1) % n]
    su = F(u) + ju
    sv = F(v) + jv
    c = lm + LIGHT_CORNER
    a = lm + LIGHT_UVEC
    b = lm + LIGHT_VVEC
    return (
        light[c] + light[a] * su + light[b] * sv,
        light[c + 1] + light[a + 1] * su + light[b + 1] * sv,
        light[c + 2] + light[a + 2] * su + light[b + 2] * sv,
    )


@njit(**INLINE)
def phong_parts(pf, p, er, eg, eb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz):
    """Chapter 6: the diffuse and specular colors (dr, dg, db, qr, qg, qb) of effective
    color (er, eg, eb) lit by the light at ``light[lm:]`` from the unit vector (lx, ly,
    lz): black where the light is behind the surface; no specular where the reflection
    points away from the eye (or its factor is below 1e-9, as ``phong`` leaves it out)."""
    m = p * NF
    light_dot_normal = lx * nx + ly * ny + lz * nz
    if light_dot_normal < ZERO:
        return ZERO, ZERO, ZERO, ZERO, ZERO, ZERO
    diffuse = pf[m + DIFFUSE]
    dr = er * diffuse * light_dot_normal
    dg = eg * diffuse * light_dot_normal
    db = eb * diffuse * light_dot_normal
    twice = -lx * nx + -ly * ny + -lz * nz
    rx = -lx - nx * F(2.0) * twice
    ry = -ly - ny * F(2.0) * twice
    rz = -lz - nz * F(2.0) * twice
    reflect_dot_eye = rx * ex + ry * ey + rz * ez
    specular = pf[m + SPECULAR]
    if reflect_dot_eye <= ZERO or specular == ZERO or reflect_dot_eye <= pf[m + POW_FLOOR]:
        return dr, dg, db, ZERO, ZERO, ZERO
    factor = math.pow(reflect_dot_eye, pf[m + SHININESS]) * specular
    return dr, dg, db, light[lm + 3] * factor, light[lm + 4] * factor, light[lm + 5] * factor


@njit(**INLINE)
def ambient_part(pf, p, er, eg, eb, ambient_on):
    """Chapter 6: the ambient color of effective color (er, eg, eb) (black when not
    ``ambient_on``: a world's second and later lights)."""
    if not ambient_on:
        return ZERO, ZERO, ZERO
    ambient = pf[p * NF + AMBIENT]
    return er * ambient, eg * ambient, eb * ambient


@njit(**INLINE)
def area_phong(pf, p, sr, sg, sb, light, lm, seq0, k, key, ex, ey, ez, nx, ny, nz, x, y, z,
               intensity, ambient_on):  # fmt: skip
    """The bonus chapter on soft shadows: ``lighting`` with area light k (its row at
    ``light[lm:]``) and the fraction ``intensity`` of it that reaches (x, y, z): the
    ambient term (when ``ambient_on``), plus the diffuse and the specular colors summed
    over the light's cells (v outer, u inner; each lit from its own point), each sum times
    intensity / cells (``raytracer.materials``)."""
    er = sr * light[lm + 3]
    eg = sg * light[lm + 4]
    eb = sb * light[lm + 5]
    ar, ag, ab = ambient_part(pf, p, er, eg, eb, ambient_on)
    if intensity == ZERO:  # (the sums times 0 add nothing)
        return ar, ag, ab
    usteps = int(light[lm + LIGHT_USTEPS])
    vsteps = int(light[lm + LIGHT_VSTEPS])
    diffuse_r = ZERO
    diffuse_g = ZERO
    diffuse_b = ZERO
    specular_r = ZERO
    specular_g = ZERO
    specular_b = ZERO
    for v in range(vsteps):
        for u in range(usteps):
            qx, qy, qz = cell_point(light, lm, seq0, k, u, v, v * usteps + u, key)
            lx, ly, lz = normalized(qx - x, qy - y, qz - z)
            dr, dg, db, qr, qg, qb = phong_parts(
                pf, p, er, eg, eb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz
            )
            diffuse_r += dr
            diffuse_g += dg
            diffuse_b += db
            specular_r += qr
            specular_g += qg
            specular_b += qb
    weight = intensity / F(usteps * vsteps)
    return (
        ar + diffuse_r * weight + specular_r * weight,
        ag + diffuse_g * weight + specular_g * weight,
        ab + diffuse_b * weight + specular_b * weight,
    )


@njit(**INLINE)
def towards_light(light, lm, x, y, z):
    """Chapters 6 and 8: the unit vector from (x, y, z) to the light whose position is
    ``light[lm:lm + 3]``, and the distance."""
    vx = light[lm] - x
    vy = light[lm + 1] - y
    vz = light[lm + 2] - z
    distance = math.sqrt(vx * vx + vy * vy + vz * vz)
    scale = ONE / distance
    return vx * scale, vy * scale, vz * scale, distance


@njit(**INLINE)
def lighting_at(pf, pi, tex, p, light, lm, seq0, k, key, x, y, z, ex, ey, ez, nx, ny, nz,
                intensity, ambient_on):  # fmt: skip
    """Chapter 6 and the bonus chapter on soft shadows: ``lighting(material, object,
    light, point, eyev, normalv, intensity, ambient)`` with light k (its row at
    ``light[lm:]``): a point light's Phong color (intensity 1: lit; 0: in shadow, ambient
    only; another fraction scales the diffuse and specular terms), or an area light's
    (``area_phong``)."""
    sr, sg, sb = surface_color(pf, pi, tex, p, x, y, z)
    if HAS_AREA_LIGHTS and light[lm + LIGHT_USTEPS] > ZERO:
        return area_phong(
            pf, p, sr, sg, sb, light, lm, seq0, k, key, ex, ey, ez, nx, ny, nz, x, y, z,
            intensity, ambient_on,
        )  # fmt: skip
    lx, ly, lz, _ = towards_light(light, lm, x, y, z)
    if not ZERO < intensity < ONE:  # (``light_fraction``: from 0 to 1)
        light_dot_normal = lx * nx + ly * ny + lz * nz
        return phong(
            pf, p, sr, sg, sb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz,
            light_dot_normal, intensity == ONE, ambient_on,
        )  # fmt: skip
    er = sr * light[lm + 3]
    eg = sg * light[lm + 4]
    eb = sb * light[lm + 5]
    ar, ag, ab = ambient_part(pf, p, er, eg, eb, ambient_on)
    dr, dg, db, qr, qg, qb = phong_parts(
        pf, p, er, eg, eb, light, lm, ex, ey, ez, nx, ny, nz, lx, ly, lz
    )
    return (
        ar + dr * intensity + qr * intensity,
        ag + dg * intensity + qg * intensity,
        ab + db * intensity + qb * intensity,
    )


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
def api_containers_indices(ids, indices, hit_index):
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
