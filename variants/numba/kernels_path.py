"""Kernel template: the path integrator (chapter 21 here, beyond the book: ``raytracer.path``),
compiled and iterative.

``raytracer.path.path_color_at`` recurses once per bounce; here ``trace_path`` is a loop
over the bounces carrying the path's throughput (as the C++ report's renderer does), adding
each hit's emission and direct light as it goes, and the sky's light where the path escapes.
Its arithmetic is the reference's, step by step (``choose_lobe``, ``cosine_direction``,
``russian_roulette``, ``direct_light``, ``crossed_lights``, ``sky_color``), and its random
numbers are
``raytracer.sampling.path_random`` bit for bit (``path_random``: splitmix64 of the sample's
key XOR ``PATH_TAG``, counter ``1 + (bounce << 32) + dimension``), so a pixel is the
reference's to rounding, whatever thread renders it. The sums differ only in order: the
reference adds the rest of a path to a hit's light from the last bounce back, this loop
from the first on.

``path_rows`` renders rows k, k + T ... of a region for thread k of T, as the Whitted
``render_rows`` does; ``kernels_entry`` chooses between them. A kernel module compiled
without ``HAS_PATH`` (a Whitted render's) leaves all of this out.
"""

# ruff: noqa: E501
import math

import numpy as np
from numba import njit

from variants.numba.kernel_flags import (
    COUNT_RAYS,
    HAS_AREA_LIGHTS,
    HAS_REFLECTION,
    HAS_REFRACTION,
    HAS_SHADOWS,
    F,
)
from variants.numba.kernels_geometry import (
    INLINE,
    ONCE,
    ONE,
    ZERO,
)
from variants.numba.kernels_hits import (
    nearest_hit,
    shadowed,
)
from variants.numba.kernels_indices import (
    refractive_indices,
)
from variants.numba.kernels_shading import (
    GAMMA,
    UNIT53,
    mix64,
    refraction,
    schlick_at,
    surface_color,
)
from variants.numba.kernels_trace import (
    prepare,
    sample_key,
    sample_ray,
)
from variants.numba.layout import (
    DIFFUSE,
    EMISSIVE,
    LIGHT_CORNER,
    LIGHT_INTENSITY,
    LIGHT_USTEPS,
    LIGHT_UVEC,
    LIGHT_VSTEPS,
    LIGHT_VVEC,
    MIN_SCRATCH,
    NF,
    NLIGHT,
    NSI,
    RAYS,
    REFLECTIVE,
    SKY_HORIZON,
    SKY_ZENITH,
    TRANSPARENCY,
)

# ---- kernel template ----

PATH_TAG = np.uint64(0x5851F42D4C957F2D)  # raytracer.sampling.PATH_TAG
LOBE_GLASS = 0  # raytracer.scatter's lobes, in the order choose_lobe tests them
LOBE_MIRROR = 1
LOBE_DIFFUSE = 2
D_ROULETTE = 0  # raytracer.path's dimensions of a bounce's random numbers
D_LOBE = 1
D_FRESNEL = 2
D_DIRECTION = 3  # and 4
D_LIGHTS = 5  # light k: 5 + 2k and 6 + 2k


@njit(**INLINE)
def path_random(path_key, bounce, dimension):
    """``raytracer.sampling.path_random_key`` bit for bit, for a sample whose key XOR
    ``PATH_TAG`` is ``path_key``: a float64 in [0, 1)."""
    counter = np.uint64(1) + (np.uint64(bounce) << np.uint64(32)) + np.uint64(dimension)
    z = mix64(path_key + counter * GAMMA)
    return np.float64(z >> np.uint64(11)) * UNIT53


@njit(**INLINE)
def choose_lobe(pf, p, u):
    """``raytracer.scatter.choose_lobe``: glass with probability t', a mirror with r' (both
    scaled by 1 / (r + t) when r + t > 1), else diffuse."""
    r = pf[p * NF + REFLECTIVE]
    t = pf[p * NF + TRANSPARENCY]
    s = r + t
    glass = t / s if s > ONE else t
    if HAS_REFRACTION and u < glass:
        return LOBE_GLASS
    if HAS_REFLECTION and u < min(s, ONE):
        return LOBE_MIRROR
    return LOBE_DIFFUSE


@njit(**INLINE)
def cosine_direction(nx, ny, nz, u1, u2):
    """``raytracer.scatter.cosine_direction``: a cosine-weighted direction around the unit
    normal (nx, ny, nz) from u1, u2 in [0, 1), in the basis of Duff et al. (2017)."""
    r = math.sqrt(u1)
    phi = 2.0 * math.pi * u2
    x = F(r * math.cos(phi))
    y = F(r * math.sin(phi))
    z = F(math.sqrt(max(0.0, 1.0 - u1)))
    sign = F(math.copysign(1.0, nz))
    a = -ONE / (sign + nz)
    b = nx * ny * a
    tx = ONE + sign * nx * nx * a
    ty = sign * b
    tz = -sign * nx
    bx = b
    by = sign + ny * ny * a
    bz = -ny
    return tx * x + bx * y + nx * z, ty * x + by * y + ny * z, tz * x + bz * y + nz * z


@njit(**INLINE)
def sky_color(sky, dx, dy, dz):
    """``raytracer.sky.sky_color``: the horizon's colour at and below the horizon, the
    zenith's straight up, in between by the direction's height."""
    t = max(ZERO, dy / math.sqrt(dx * dx + dy * dy + dz * dz))
    h = SKY_HORIZON
    z = SKY_ZENITH
    return (
        sky[h] + (sky[z] - sky[h]) * t,
        sky[h + 1] + (sky[z + 1] - sky[h + 1]) * t,
        sky[h + 2] + (sky[z + 2] - sky[h + 2]) * t,
    )


@njit(**ONCE)
def direct_light(
    w, s, over_x, over_y, over_z, nx, ny, nz, wr, wg, wb, eps, path_key, bounce, area
):  # fmt: skip
    """``raytracer.path.direct_light``: every light's light at a diffuse hit, times the
    path's weight (wr, wg, wb): one shadow ray per light, to a point light or to one point
    spread uniformly over an area light (its numbers 5 + 2k and 6 + 2k); ``area`` False:
    the point lights only (light sampling off)."""
    _, _, _, _, _, _, _, _, light, n_lights, _, _ = w
    _, si, _ = s
    dr = ZERO
    dg = ZERO
    db = ZERO
    for k in range(n_lights):
        lm = k * NLIGHT
        qx = light[lm]
        qy = light[lm + 1]
        qz = light[lm + 2]
        if HAS_AREA_LIGHTS and light[lm + LIGHT_USTEPS] > ZERO:
            if not area:
                continue
            along_u = F(path_random(path_key, bounce, D_LIGHTS + 2 * k) * light[lm + LIGHT_USTEPS])
            along_v = F(
                path_random(path_key, bounce, D_LIGHTS + 2 * k + 1) * light[lm + LIGHT_VSTEPS]
            )
            c = lm + LIGHT_CORNER
            qx = light[c] + light[lm + LIGHT_UVEC] * along_u + light[lm + LIGHT_VVEC] * along_v
            qy = (
                light[c + 1]
                + light[lm + LIGHT_UVEC + 1] * along_u
                + light[lm + LIGHT_VVEC + 1] * along_v
            )
            qz = (
                light[c + 2]
                + light[lm + LIGHT_UVEC + 2] * along_u
                + light[lm + LIGHT_VVEC + 2] * along_v
            )
        vx = qx - over_x
        vy = qy - over_y
        vz = qz - over_z
        distance = math.sqrt(vx * vx + vy * vy + vz * vz)
        if distance == ZERO:
            continue  # the light is on the point: no direction to it
        cosine = vx / distance * nx + vy / distance * ny + vz / distance * nz
        if cosine <= ZERO:
            continue
        if HAS_SHADOWS:
            if COUNT_RAYS:
                si[1 * NSI + RAYS] += 1
            if shadowed(w, s, over_x, over_y, over_z, vx, vy, vz, eps, k % MIN_SCRATCH):
                continue
        i = lm + LIGHT_INTENSITY
        dr += wr * light[i] * cosine
        dg += wg * light[i + 1] * cosine
        db += wb * light[i + 2] * cosine
    return dr, dg, db


@njit(**ONCE)
def crossed_lights(w, s, ox, oy, oz, dx, dy, dz, wr, wg, wb, eps):
    """``raytracer.path.crossed_lights`` (light sampling off): the light of the area lights
    that the ray from (ox, oy, oz) along (dx, dy, dz), leaving a diffuse hit, crosses where
    they are seen from its origin, times the path's weight (wr, wg, wb)."""
    _, _, _, _, _, _, _, _, light, n_lights, _, _ = w
    _, si, _ = s
    cr = ZERO
    cg = ZERO
    cb = ZERO
    for k in range(n_lights):
        lm = k * NLIGHT
        if not (HAS_AREA_LIGHTS and light[lm + LIGHT_USTEPS] > ZERO):
            continue
        us = light[lm + LIGHT_USTEPS]
        vs = light[lm + LIGHT_VSTEPS]
        u = lm + LIGHT_UVEC
        v = lm + LIGHT_VVEC
        c = lm + LIGHT_CORNER
        ux, uy, uz = light[u] * us, light[u + 1] * us, light[u + 2] * us
        vx, vy, vz = light[v] * vs, light[v + 1] * vs, light[v + 2] * vs
        nx = uy * vz - uz * vy
        ny = uz * vx - ux * vz
        nz = ux * vy - uy * vx
        facing = dx * nx + dy * ny + dz * nz
        if facing == ZERO:
            continue  # the ray runs along the light's plane
        t = ((light[c] - ox) * nx + (light[c + 1] - oy) * ny + (light[c + 2] - oz) * nz) / facing
        if t <= ZERO:
            continue
        px = ox + dx * t
        py = oy + dy * t
        pz = oz + dz * t
        qx = px - light[c]
        qy = py - light[c + 1]
        qz = pz - light[c + 2]
        area2 = nx * nx + ny * ny + nz * nz
        a = ((qy * vz - qz * vy) * nx + (qz * vx - qx * vz) * ny + (qx * vy - qy * vx) * nz) / area2
        b = ((uy * qz - uz * qy) * nx + (uz * qx - ux * qz) * ny + (ux * qy - uy * qx) * nz) / area2
        if not (ZERO <= a <= ONE and ZERO <= b <= ONE):
            continue
        if HAS_SHADOWS:
            if COUNT_RAYS:
                si[1 * NSI + RAYS] += 1
            if shadowed(w, s, ox, oy, oz, px - ox, py - oy, pz - oz, eps, k % MIN_SCRATCH):
                continue
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        factor = F(math.pi) * t * t * length * length * length / abs(facing)
        i = lm + LIGHT_INTENSITY
        cr += wr * light[i] * factor
        cg += wg * light[i + 1] * factor
        cb += wb * light[i + 2] * factor
    return cr, cg, cb


@njit(**ONCE)
def trace_path(w, s, eps, sky, depth, roulette, light_sampling, ox, oy, oz, dx, dy, dz, key):
    """``raytracer.path.path_color_at`` for a camera ray, as a loop over its bounces: the
    light it carries back (r, g, b). ``key``: the sample's (``sample_key``);
    ``light_sampling``: shadow rays to the area lights, else their crossings."""
    # long: the reference's three steps (path_color_at, scatter, direct_light's call) in
    # one loop, which carries the throughput and the ray from bounce to bounce
    pf, pi, _, _, _, _, _, _, _, _, tex, geo = w
    _, si, _ = s
    path_key = key ^ PATH_TAG
    r = ZERO
    g = ZERO
    b = ZERO
    tr = ONE
    tg = ONE
    tb = ONE
    bounce = 0
    while True:
        if COUNT_RAYS:
            si[0 * NSI + RAYS] += 1
        t, p, local, u, v = nearest_hit(w, s, ox, oy, oz, dx, dy, dz, eps)
        if p < 0:
            sr, sg, sb = sky_color(sky, dx, dy, dz)
            return r + tr * sr, g + tg * sg, b + tb * sb
        (_px, _py, _pz, ex, ey, ez, nx, ny, nz, _inside, over_x, over_y, over_z, under_x, under_y,
         under_z, rx, ry, rz) = prepare(pf, pi, p, ox, oy, oz, dx, dy, dz, t, u, v, eps, geo, local)  # fmt: skip
        m = p * NF + EMISSIVE
        r += tr * pf[m]
        g += tg * pf[m + 1]
        b += tb * pf[m + 2]
        if bounce >= depth:
            return r, g, b
        if roulette > 0 and bounce >= roulette:
            survival = min(ONE, max(tr, tg, tb))
            if path_random(path_key, bounce, D_ROULETTE) >= survival:
                return r, g, b
            tr = tr / survival
            tg = tg / survival
            tb = tb / survival
        lobe = choose_lobe(pf, p, path_random(path_key, bounce, D_LOBE))
        # the next ray: a mirror's, unless glass refracts or the surface is diffuse
        nox, noy, noz, ndx, ndy, ndz = over_x, over_y, over_z, rx, ry, rz
        if HAS_REFRACTION and lobe == LOBE_GLASS:
            if COUNT_RAYS:
                si[2 * NSI + RAYS] += 1
            n1, n2 = refractive_indices(w, s, ox, oy, oz, dx, dy, dz, eps, t, p, local)
            if path_random(path_key, bounce, D_FRESNEL) >= schlick_at(
                ex, ey, ez, nx, ny, nz, n1, n2
            ):
                ok, fx, fy, fz = refraction(ex, ey, ez, nx, ny, nz, n1, n2)
                if ok:  # else total internal reflection: the mirror's ray
                    nox, noy, noz, ndx, ndy, ndz = under_x, under_y, under_z, fx, fy, fz
        elif lobe == LOBE_DIFFUSE:
            cr, cg, cb = surface_color(pf, pi, tex, p, over_x, over_y, over_z)
            diffuse = pf[p * NF + DIFFUSE]
            tr = tr * (cr * diffuse)
            tg = tg * (cg * diffuse)
            tb = tb * (cb * diffuse)
            ndx, ndy, ndz = cosine_direction(
                nx, ny, nz, path_random(path_key, bounce, D_DIRECTION),
                path_random(path_key, bounce, D_DIRECTION + 1),
            )  # fmt: skip
        if tr == ZERO and tg == ZERO and tb == ZERO:
            return r, g, b  # it can add nothing more
        if lobe == LOBE_DIFFUSE:
            lr, lg, lb = direct_light(
                w, s, over_x, over_y, over_z, nx, ny, nz, tr, tg, tb, eps, path_key, bounce,
                light_sampling,
            )  # fmt: skip
            r += lr
            g += lg
            b += lb
            if HAS_AREA_LIGHTS and not light_sampling:
                lr, lg, lb = crossed_lights(
                    w, s, nox, noy, noz, ndx, ndy, ndz, tr, tg, tb, eps
                )
                r += lr
                g += lg
                b += lb
        ox, oy, oz, dx, dy, dz = nox, noy, noz, ndx, ndy, ndz
        bounce += 1


@njit(**ONCE)
def path_rows(
    out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, s, sky, roulette,
    light_sampling,
):  # fmt: skip
    """Chapter 21 here: path-trace rows y0 + k, y0 + k + step ... (below y1) of the region
    x0 <= x < x1, y0 <= y < y1 into ``out`` (as ``render_rows``), each pixel the mean of
    its samples' paths (``trace_path``; one sample: through the pixel's centre;
    ``light_sampling``: its). Returns the rows done."""
    eps = F(eps)
    scale = ONE / F(samples)
    width = x1 - x0
    rows = 0
    for y in range(y0 + k, y1, step):
        for x in range(x0, x1):
            r = ZERO
            g = ZERO
            b = ZERO
            for i in range(samples):
                ox, oy, oz, dx, dy, dz = sample_ray(cam, seed_key, samples, x, y, i)
                key = sample_key(seed_key, x, y, i)
                sr, sg, sb = trace_path(
                    w, s, eps, sky, depth, roulette, light_sampling, ox, oy, oz, dx, dy, dz,
                    key,
                )  # fmt: skip
                r += sr
                g += sg
                b += sb
            m = ((y - y0) * width + (x - x0)) * 3
            if samples == 1:
                out[m] = r
                out[m + 1] = g
                out[m + 2] = b
            else:
                out[m] = r * scale
                out[m + 1] = g * scale
                out[m + 2] = b * scale
        rows += 1
    return rows
