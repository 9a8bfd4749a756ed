"""The path integrator in passes (chapter 21 here, beyond the book: ``raytracer.path`` gives
the physics), the C++ write-up's design: each ray of a batch carries its throughput and
its sample's key, and the whole batch is marched one bounce at a time.

A bounce is one nearest-hit query for every live ray; the rays that meet nothing add the
sky and are dropped; the others add their emission, then (below the depth cap) survive
Russian roulette, choose a lobe, take its weight, and the diffuse ones add the lights
(one batched shadow query per light; with light sampling off, the area lights that their
new rays cross, one batched shadow query per area light). The rays that are absorbed,
killed or black are dropped (the batch is compacted), the others go on as the next
bounce's batch, never larger than the camera batch, so memory stays bounded by the pass.

The random numbers are ``raytracer.sampling.path_random``'s, computed from each ray's
sample key in uint64 NumPy (``camera.path_numbers``): the generator is per ray, so a
thread, a pass size or a tile split never changes the picture. Each step is the
reference's arithmetic in its order; only the sums into a pixel are in another order
(bounce by bounce rather than nested), so float64 pictures equal the reference's to
rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import RenderSettings
from raytracer.path import DIRECTION, FRESNEL, LIGHTS, LOBE, ROULETTE
from variants.wavefront.camera import path_numbers
from variants.wavefront.hits import Index, Nearest, Ray, blocked, nearest, sub
from variants.wavefront.indices import indices_in_parts
from variants.wavefront.scene import Scene
from variants.wavefront.shading import Hits, Three, prepare, refraction, schlick, surface


@dataclass
class Paths:
    """The live paths of a batch as a structure of arrays: their rays (origin x, y, z and
    direction x, y, z; a shared origin stays a scalar), throughputs (r, g, b), pixels and
    sample keys."""

    ray: Ray
    throughput: Three
    pixel: np.ndarray
    key: np.ndarray

    def take(self, rows: Any) -> Paths:
        return Paths(sub(self.ray, rows), _pick(self.throughput, rows), self.pixel[rows],
                     self.key[rows])  # fmt: skip


@dataclass(frozen=True)
class March:
    """What every bounce of a render reads: the indexed world, the settings, epsilon, the
    batch cap and the pixel totals (pixels, 3) float64 that the paths add to."""

    idx: Index
    settings: RenderSettings
    eps: float
    cap: int
    total: np.ndarray

    def add(self, pixel: np.ndarray, color: Three) -> None:
        """Add each path's ``color`` to its pixel."""
        n = len(self.total)
        for c in range(3):
            self.total[:, c] += np.bincount(pixel, weights=color[c], minlength=n)


def _pick(arrays: Three, rows: Any) -> Three:
    return arrays[0][rows], arrays[1][rows], arrays[2][rows]


def _times(a: Three, b: Three) -> Three:
    return a[0] * b[0], a[1] * b[1], a[2] * b[2]


def trace_paths(
    idx: Index, settings: RenderSettings, eps: float, cap: int, ray: tuple[Any, ...],
    keys: np.ndarray, pixel: np.ndarray, pixels: int,
) -> np.ndarray:  # fmt: skip
    """Chapter 21's ``path_color_at`` for a batch of camera rays (at most ``cap``), with
    their sample keys (``camera.sample_keys``) and pixels (0 .. pixels - 1): the colours
    summed per pixel, (pixels, 3) float64."""
    march = March(idx, settings, eps, cap, np.zeros((pixels, 3)))
    one = np.ones(len(keys), dtype=ray[3].dtype)
    paths: Paths | None = Paths(ray, (one, one.copy(), one.copy()), pixel, keys)
    bounce = 0
    with np.errstate(all="ignore"):  # IEEE infinities and NaNs are part of the arithmetic
        while paths is not None and bounce <= settings.depth:
            paths = bounce_paths(march, paths, bounce)
            bounce += 1
    return march.total


def bounce_paths(march: March, paths: Paths, bounce: int) -> Paths | None:
    """One bounce of every live path: what it meets adds its light, and the paths that go
    on are returned (None: none)."""
    idx, eps = march.idx, march.eps
    scene = idx.scene
    hit = nearest(idx, paths.ray, eps, march.cap)
    found = hit.prim >= 0
    if not found.all():
        missed = np.flatnonzero(~found)
        if scene.sky is not None:
            sky = sky_colors(scene.sky, _pick(paths.ray[3:], missed))
            march.add(paths.pixel[missed], _times(_pick(paths.throughput, missed), sky))
        rows = np.flatnonzero(found)
        if not len(rows):
            return None
        paths, hit = paths.take(rows), hit.take(rows)
    settings = march.settings
    emits = bool(scene.emissive.any())
    if bounce >= settings.depth and not emits:
        return None  # at the cap only emission counts, and nothing emits
    hits = prepare(scene, paths.ray[:3], paths.ray[3:], hit, eps)
    if emits:
        march.add(paths.pixel, _times(paths.throughput, tuple(e[hits.mat] for e in scene.emissive)))
    if bounce >= settings.depth:
        return None
    if 0 < settings.roulette <= bounce:
        live = _roulette(paths, bounce)
        if not len(live):
            return None
        if len(live) < len(paths.key):
            paths, hit, hits = paths.take(live), hit.take(live), hits.take(live)
    return _scatter(march, paths, hit, hits, bounce)


def sky_colors(sky: np.ndarray, direction: Three) -> Three:
    """``raytracer.sky.sky_color`` along many directions: ``sky`` is (horizon, zenith)."""
    x, y, z = direction
    t = np.maximum(0.0, y / np.sqrt(x * x + y * y + z * z))
    horizon, zenith = sky[0], sky[1]
    red, green, blue = (horizon[c] + (zenith[c] - horizon[c]) * t for c in range(3))
    return red, green, blue


def _roulette(paths: Paths, bounce: int) -> np.ndarray:
    """Russian roulette (``raytracer.path.russian_roulette``): the rows that survive, their
    throughputs divided by their chance (in place)."""
    r, g, b = paths.throughput
    p = np.minimum(1.0, np.maximum(np.maximum(r, g), b))
    survive = path_numbers(paths.key, bounce, ROULETTE) < p
    paths.throughput = (r / p, g / p, b / p)
    return np.flatnonzero(survive)


def _scatter(march: March, paths: Paths, hit: Nearest, hits: Hits, bounce: int) -> Paths | None:
    """``raytracer.path.scatter`` for every path (lobes as in ``raytracer.scatter``), then
    the lights at the diffuse hits; the paths that go on, with their new rays and weights
    (the mirror's ray and a white weight unless the lobe says otherwise). When every path
    goes on (the usual case), its arrays are the next bounce's as they are, not copies."""
    scene = march.idx.scene
    r, t = scene.reflective[hits.mat], scene.transparency[hits.mat]
    s = r + t
    lobe_u = path_numbers(paths.key, bounce, LOBE)
    glass = lobe_u < np.where(s > 1.0, t / s, t)
    diffuse = ~glass & ~(lobe_u < np.minimum(s, 1.0))
    lambert = np.flatnonzero(diffuse)
    weight = paths.throughput
    if len(lambert):
        color, kd = surface(scene, hits), scene.diffuse[hits.mat]
        weight = _where(diffuse, _times(weight, (color[0] * kd, color[1] * kd, color[2] * kd)),
                        weight)  # fmt: skip
    alive = (weight[0] != 0) | (weight[1] != 0) | (weight[2] != 0)
    go = np.flatnonzero(alive)
    if not len(go):
        return None
    everyone = len(go) == len(alive)
    place = None if everyone else np.cumsum(alive) - 1  # each row's place among those going on
    direction = tuple(np.empty(len(go), dtype=hits.over[0].dtype) for _ in range(3))
    mirrored = alive & ~diffuse  # the mirror's ray, unless the glass refracts
    shine = lambert[alive[lambert]]
    if len(shine):
        keys = paths.key[shine]
        normal = _pick(hits.normal, shine)
        turned = cosine_directions(normal, path_numbers(keys, bounce, DIRECTION),
                                   path_numbers(keys, bounce, DIRECTION + 1))  # fmt: skip
        _put(direction, shine if place is None else place[shine], turned)
        if len(scene.light_pos):
            over, lit = _pick(hits.over, shine), _pick(weight, shine)
            sampling = march.settings.light_sampling
            march.add(paths.pixel[shine],
                      direct_light(march, over, normal, lit, keys, bounce, sampling))  # fmt: skip
            if not sampling:
                march.add(paths.pixel[shine], crossed_lights(march, over, turned, lit))
    origin = hits.over if everyone else _pick(hits.over, go)
    rows = np.flatnonzero(glass & alive)
    if len(rows):
        through, bent = _refract(march, paths, hit, hits, bounce, rows)
        if len(through):
            at = through if place is None else place[through]
            origin = tuple(c.copy() if everyone else c for c in origin)  # not the hits' own
            _put(origin, at, hits.under_at(through))
            _put(direction, at, bent)
            mirrored[through] = False
    rows = np.flatnonzero(mirrored)
    if len(rows):
        _put(direction, rows if place is None else place[rows], hits.reflect_at(rows))
    ray = (*origin, *direction)
    if everyone:
        return Paths(ray, weight, paths.pixel, paths.key)
    return Paths(ray, _pick(weight, go), paths.pixel[go], paths.key[go])


def _put(arrays: tuple[np.ndarray, ...], rows: Any, values: Three) -> None:
    """Write ``values`` into the rows ``rows`` of three arrays."""
    for c in range(3):
        arrays[c][rows] = values[c]


def _where(mask: np.ndarray, a: Three, b: Three) -> Three:
    return np.where(mask, a[0], b[0]), np.where(mask, a[1], b[1]), np.where(mask, a[2], b[2])


def _refract(
    march: March, paths: Paths, hit: Nearest, hits: Hits, bounce: int, rows: np.ndarray
) -> tuple[np.ndarray, Three]:
    """The glass lobe at ``rows``: the rows that refract (the others reflect: their
    Fresnel number is below Schlick's reflectance, or the light is totally reflected) and
    the book's refracted directions of those, which leave from the under point."""
    n1, n2 = indices_in_parts(march.idx, sub(paths.ray, rows), hit.take(rows), march.eps,
                              march.cap)  # fmt: skip
    eyev, normal = _pick(hits.eyev, rows), _pick(hits.normal, rows)
    reflects = path_numbers(paths.key[rows], bounce, FRESNEL) < schlick(eyev, normal, n1, n2)
    possible, bent = refraction(eyev, normal, n1, n2)
    through = ~reflects & possible
    return rows[through], _pick(bent, through)


def cosine_directions(n: Three, u1: np.ndarray, u2: np.ndarray) -> Three:
    """``raytracer.scatter.cosine_direction`` for many unit normals ``n`` and numbers."""
    radius = np.sqrt(u1)
    phi = 2.0 * math.pi * u2
    x, y, z = radius * np.cos(phi), radius * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))
    nx, ny, nz = n
    sign = np.copysign(1.0, nz)
    a = -1.0 / (sign + nz)
    b = nx * ny * a
    tangent = (1.0 + sign * nx * nx * a, sign * b, -sign * nx)
    bitangent = (b, sign + ny * ny * a, -ny)
    dtype = nx.dtype
    return (
        (tangent[0] * x + bitangent[0] * y + nx * z).astype(dtype, copy=False),
        (tangent[1] * x + bitangent[1] * y + ny * z).astype(dtype, copy=False),
        (tangent[2] * x + bitangent[2] * y + nz * z).astype(dtype, copy=False),
    )


def direct_light(
    march: March, over: Three, normal: Three, weight: Three, keys: np.ndarray, bounce: int,
    area: bool = True,
) -> Three:  # fmt: skip
    """``raytracer.path.direct_light`` at many diffuse hits (their over points and normals):
    for each light, its point (an area light's drawn from the path's numbers), and where it
    is in front of the surface a batched shadow query; the lit hits add weight * intensity
    * cosine. ``area`` False: the point lights only (light sampling off)."""
    scene: Scene = march.idx.scene
    n = len(keys)
    total = [np.zeros(n) for _ in range(3)]
    for k in range(len(scene.light_pos)):
        if not area and scene.light_steps[k][0] > 0:
            continue
        target = _light_points(scene, k, keys, bounce)
        toward = tuple(target[c] - over[c] for c in range(3))
        length = np.sqrt(toward[0] * toward[0] + toward[1] * toward[1] + toward[2] * toward[2])
        unit = tuple(toward[c] / length for c in range(3))
        cosine = unit[0] * normal[0] + unit[1] * normal[1] + unit[2] * normal[2]
        front = np.flatnonzero((length != 0.0) & (cosine > 0.0))
        if not len(front):
            continue
        shadowed = blocked(
            march.idx, (*_pick(over, front), *_pick(unit, front)), length[front], march.eps,
            march.cap,
        )  # fmt: skip
        lit = front[~shadowed]
        intensity = scene.light_int[k]
        for c in range(3):
            total[c][lit] += weight[c][lit] * intensity[c] * cosine[lit]
    return total[0], total[1], total[2]


def _light_points(scene: Scene, k: int, keys: np.ndarray, bounce: int) -> tuple[Any, Any, Any]:
    """Light ``k``'s point for each path: a point light's position, or one point of an
    area light (``corner + uvec * (u * usteps) + vvec * (v * vsteps)``)."""
    corner = scene.light_pos[k]
    usteps, vsteps = (int(s) for s in scene.light_steps[k])
    if usteps == 0:
        return corner[0], corner[1], corner[2]
    u = path_numbers(keys, bounce, LIGHTS + 2 * k) * usteps
    v = path_numbers(keys, bounce, LIGHTS + 2 * k + 1) * vsteps
    edges = scene.light_edges[k]
    x, y, z = (corner[c] + edges[c] * u + edges[3 + c] * v for c in range(3))
    return x, y, z


def crossed_lights(march: March, origin: Three, direction: Three, weight: Three) -> Three:
    """``raytracer.path.crossed_lights`` for many rays leaving diffuse hits (light sampling
    off): each area light's crossing, and where it is inside the light a batched shadow
    query; the rays that see it add weight * intensity * pi t^2 |d|^3 / |d . n|."""
    scene: Scene = march.idx.scene
    total = [np.zeros(len(origin[0])) for _ in range(3)]
    for k in range(len(scene.light_pos)):
        steps = scene.light_steps[k]
        if steps[0] <= 0:
            continue
        corner, edges = scene.light_pos[k], scene.light_edges[k]
        u = tuple(edges[c] * steps[0] for c in range(3))
        v = tuple(edges[3 + c] * steps[1] for c in range(3))
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        facing = direction[0] * n[0] + direction[1] * n[1] + direction[2] * n[2]
        t = sum((corner[c] - origin[c]) * n[c] for c in range(3)) / facing
        q = tuple(origin[c] + direction[c] * t - corner[c] for c in range(3))
        area2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
        a = _triple(q, v, n) / area2
        b = _triple(u, q, n) / area2
        inside = (facing != 0.0) & (t > 0.0) & (a >= 0.0) & (a <= 1.0) & (b >= 0.0) & (b <= 1.0)
        rows = np.flatnonzero(inside)
        if not len(rows):
            continue
        d = _pick(direction, rows)
        length = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        unit = (d[0] / length, d[1] / length, d[2] / length)
        distance = t[rows] * length
        shadowed = blocked(march.idx, (*_pick(origin, rows), *unit), distance, march.eps,
                           march.cap)  # fmt: skip
        seen = rows[~shadowed]
        factor = (math.pi * t * t)[seen] * (length * length * length)[~shadowed]
        factor = factor / np.abs(facing[seen])
        for c in range(3):
            total[c][seen] += weight[c][seen] * scene.light_int[k][c] * factor
    return total[0], total[1], total[2]


def _triple(a: Three | tuple[Any, ...], b: Three | tuple[Any, ...], n: tuple[Any, ...]) -> Any:
    """(a x b) . n, component arrays or numbers."""
    return (
        (a[1] * b[2] - a[2] * b[1]) * n[0]
        + (a[2] * b[0] - a[0] * b[2]) * n[1]
        + (a[0] * b[1] - a[1] * b[0]) * n[2]
    )
