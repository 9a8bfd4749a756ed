"""Kernel template: the explicit stack that replaces the book's recursion (chapters 7, 8,
11), camera rays and samples, and the render.

- ``drain`` is ``color_at`` without recursion: a stack of (ray, weight, remaining), where the
  weight is the product of the reflective / transparency / Schlick factors on the way.
- ``light_intensity`` is the soft shadows chapter's ``intensity_at`` for an area light: a
  shadow ray to every cell's point (jittered by the sample's key, which ``render_rows``
  computes once per sample and every bounce of it shares, or placed by the light's
  sequence); ``shade_and_push`` then lights the point from every cell (``area_phong``).
- ``render_rows`` renders rows k, k + T, k + 2T ... of a region (x0, y0, x1, y1) of the
  image for thread k of T (the top and bottom of an image cost very different amounts, so
  contiguous blocks would leave one thread idle), making each sample's camera ray before
  tracing the previous one (the processor overlaps them); ``kernels_entry`` makes it (or
  the path integrator's ``path_rows``) the render's C entry point.

The world and scratch tuples are ``kernels_hits``'s.
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
    HAS_REFLECTION,
    HAS_REFRACTION,
    HAS_SCHLICK,
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
from variants.numba.kernels_prims import (
    hit_normal,
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
    CAM_HALF_HEIGHT,
    CAM_HALF_WIDTH,
    CAM_INV,
    CAM_PIXEL_SIZE,
    LIGHT_USTEPS,
    LIGHT_VSTEPS,
    MIN_SCRATCH,
    NF,
    NLIGHT,
    NSI,
    RAY_BLOCK,
    RAYS,
    REFLECTIVE,
    STACK_WIDTH,
    TRANSPARENCY,
)

# ---- kernel template ----

ENTRY: dict[str, Any] = {"fastmath": FASTMATH, "error_model": "numpy", "cache": True}
GAMMA2 = np.uint64((2 * 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF)


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
    # long: the book's shade_hit with its three chapters (lights and shadows, reflection,
    # refraction with Schlick) in one place, sharing the colour so far and the stack's top
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
    pf, pi, _, _, _, _, _, _, _, n_lights, _, geo = w
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
        if p < 0 or (n_lights == 0 and not COUNT_RAYS):
            # nothing hit; or no light: every hit is black (the ambient term comes with a
            # light), so its normal, shading and the rays it spawns are skipped (the
            # counting kernel still traces them: the reference's ray counts)
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
def sample_rays(cam, seed_key, x, y, first, count, rays, base):
    """``sample_ray`` of samples first ... first + count - 1 (count <= ``RAY_BLOCK``) of
    pixel (x, y) rendered with more than one sample, into ``rays[base:]`` (a row of
    ``RAY_BLOCK`` per coordinate: ox, oy, oz, dx, dy, dz): one loop without branches, which
    the compiler makes vector instructions (the same numbers as ``sample_ray``'s)."""
    for n in range(count):
        sx, sy = sample_offset(seed_key, x, y, first + n)
        ox, oy, oz, dx, dy, dz = camera_ray(
            cam, F(np.float64(x) + sx - 0.5), F(np.float64(y) + sy - 0.5)
        )
        rays[base + n] = ox
        rays[base + RAY_BLOCK + n] = oy
        rays[base + 2 * RAY_BLOCK + n] = oz
        rays[base + 3 * RAY_BLOCK + n] = dx
        rays[base + 4 * RAY_BLOCK + n] = dy
        rays[base + 5 * RAY_BLOCK + n] = dz


@njit(**INLINE)
def block_ray(cam, seed_key, samples, x, y, i, rays, base):
    """``sample_ray`` of sample i of pixel (x, y), taken from the block of camera rays at
    ``rays[base:]`` (``sample_rays``), which is filled with the next ``RAY_BLOCK`` when i
    starts a block; samples are asked for in order."""
    if samples == 1:
        return camera_ray(cam, F(x), F(y))
    n = i % RAY_BLOCK
    if n == 0:
        sample_rays(cam, seed_key, x, y, i, min(RAY_BLOCK, samples - i), rays, base)
    return (
        rays[base + n], rays[base + RAY_BLOCK + n], rays[base + 2 * RAY_BLOCK + n],
        rays[base + 3 * RAY_BLOCK + n], rays[base + 4 * RAY_BLOCK + n],
        rays[base + 5 * RAY_BLOCK + n],
    )  # fmt: skip


@njit(**ONCE)
def render_rows(out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, stack, s):
    """Chapter 7: render rows y0 + k, y0 + k + step ... (below y1) of the region x0 <= x <
    x1, y0 <= y < y1 into ``out`` ((y1 - y0) x (x1 - x0) x 3, flat; pixels and sample
    offsets use the absolute (x, y)), with one thread's scratch: ``stack`` (depth + 2
    entries, then a block of camera rays: ``block_ray``) and ``s`` = (sf, si, tb)
    (``layout``; si's MEMO entry set to -1 before the first call). Returns the rows done.
    The next sample's camera ray is taken before the current one is traced, so that the
    processor can work on both at once; they are made ``RAY_BLOCK`` at a time."""
    eps = F(eps)
    scale = ONE / F(samples)
    width = x1 - x0
    if y0 + k >= y1 or width <= 0:
        return 0
    x = x0
    y = y0 + k
    i = 0
    block = (depth + 2) * STACK_WIDTH  # the block of camera rays, after the stack
    ox, oy, oz, dx, dy, dz = block_ray(cam, seed_key, samples, x, y, i, stack, block)
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
            nox, noy, noz, ndx, ndy, ndz = block_ray(
                cam, seed_key, samples, next_x, next_y, next_i, stack, block
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
