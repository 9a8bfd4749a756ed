"""Shading a pass's hits, all at once (chapters 6, 7, 8, 10, 11), each step the reference's
arithmetic over arrays: ``prepare_computations`` (``prepare``), the pattern or the
material's color (``surface``), ``lighting`` with every light's shadow ray (``shade``),
Schlick's reflectance and the refracted direction (n1 and n2: ``indices``).

Rays and vectors travel as tuples of three arrays (x, y, z); colors likewise (r, g, b).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from scene.pattern_kinds import NO_PATTERN
from variants.wavefront import geometry as G
from variants.wavefront.hits import Nearest, params, split
from variants.wavefront.scene import (
    CHECKERS,
    GRADIENT,
    KIND_NAMES,
    PATTERN_KINDS,
    RINGS,
    STRIPES,
    TEST_PATTERN,
    Scene,
)

Three = tuple[Any, Any, Any]


@dataclass
class Hits:
    """Chapter 7's ``Computations`` for many hits: the prepared state of each; ``under``
    and ``reflectv`` are computed when first asked for (``under_at`` and ``reflect_at``:
    for some rows only, as the path integrator needs them)."""

    prim: np.ndarray
    mat: np.ndarray
    point: Three
    eyev: Three
    normal: Three
    over: Three
    eps: float

    def take(self, rows: Any) -> Hits:
        """The hits ``rows``."""
        return Hits(
            self.prim[rows], self.mat[rows], _pick(self.point, rows), _pick(self.eyev, rows),
            _pick(self.normal, rows), _pick(self.over, rows), self.eps,
        )  # fmt: skip

    @cached_property
    def under(self) -> Three:
        return self.under_at(slice(None))

    @cached_property
    def reflectv(self) -> Three:
        return self.reflect_at(slice(None))

    def under_at(self, rows: Any) -> Three:
        """Chapter 11's under points of the hits ``rows``."""
        (px, py, pz), (nx, ny, nz) = _pick(self.point, rows), _pick(self.normal, rows)
        eps = self.eps
        return px - nx * eps, py - ny * eps, pz - nz * eps

    def reflect_at(self, rows: Any) -> Three:
        """Chapter 11's reflected vectors of the hits ``rows``: the ray's direction (minus
        the eye vector, exactly) reflected about the normal."""
        ex, ey, ez = _pick(self.eyev, rows)
        dx, dy, dz = -ex, -ey, -ez
        nx, ny, nz = _pick(self.normal, rows)
        twice = dx * nx + dy * ny + dz * nz
        return dx - nx * 2 * twice, dy - ny * 2 * twice, dz - nz * 2 * twice


def _pick(arrays: Three, rows: Any) -> Three:
    return arrays[0][rows], arrays[1][rows], arrays[2][rows]


def _dot(a: Three, b: Three) -> Any:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def prepare(scene: Scene, origin: Three, direction: Three, hit: Nearest, eps: float) -> Hits:
    """Chapters 7, 8, 11 (``prepare_computations`` but n1 and n2): the point, eye and
    normal vectors (the normal flipped towards the eye), the over points (the under points
    and reflectv when asked for: ``Hits``)."""
    t = hit.t
    point = (
        origin[0] + direction[0] * t,
        origin[1] + direction[1] * t,
        origin[2] + direction[2] * t,
    )
    eyev = (-direction[0], -direction[1], -direction[2])
    normal = _normals(scene, hit, point, eps)
    inside = _dot(normal, eyev) < 0
    for c in normal:  # the normals' own arrays: flipped in place
        np.negative(c, out=c, where=inside)
    (px, py, pz), (nx, ny, nz) = point, normal
    over = (px + nx * eps, py + ny * eps, pz + nz * eps)
    return Hits(hit.prim, scene.mat[hit.prim], point, eyev, normal, over, eps)


def _groups(
    scene: Scene, prims: np.ndarray, kinds: np.ndarray, count: int
) -> list[tuple[Any, Any]]:
    """(prim, rows) per primitive when few are concerned (their parameters then scalars),
    else (kind, rows) per kind ``kinds`` (0 .. count - 1), ``prim`` None."""
    few = split(prims, scene.n_prims)
    if few is not None:
        return [(p, rows) for p, rows in few]
    found = split(kinds, count, count)
    assert found is not None
    return [(None, (k, rows)) for k, rows in found]


def _normals(scene: Scene, hit: Nearest, point: Three, eps: float) -> Three:
    """Chapters 6, 9, 14 (``normal_at``): world-space normals at the hit points."""
    n = len(hit.t)
    out = [np.empty(n, dtype=hit.t.dtype) for _ in range(3)]
    for p, rows in _groups(scene, hit.prim, scene.kind[hit.prim], len(KIND_NAMES)):
        if p is None:
            kind, rows = rows
            prims: Any = hit.prim[rows]
        else:
            kind, prims = int(scene.kind[p]), p
        xform = scene.xform[prims]
        local = G.point_to_object(scene.inv[:, xform], *(c[rows] for c in point))
        normal = G.local_normal(
            kind, *local, params(scene, kind, prims, normals=True), hit.u[rows], hit.v[rows], eps
        )
        world = G.normal_to_world(scene.nrm[:, xform], *normal)
        for k in range(3):
            out[k][rows] = world[k]
    return out[0], out[1], out[2]


def surface(scene: Scene, hits: Hits) -> Three:
    """Chapters 6 and 10: the material's color, or its pattern's at the over point
    (``pattern_at_shape``: world to object space, then to pattern space)."""
    mats = hits.mat
    color = [scene.color[k][mats] for k in range(3)]
    kinds = scene.pattern[mats]
    patterned = np.flatnonzero(kinds != NO_PATTERN)
    if not len(patterned):
        return color[0], color[1], color[2]
    prims = hits.prim[patterned]
    for p, rows in _groups(scene, prims, kinds[patterned], len(PATTERN_KINDS) + 1):
        if p is None:
            kind, rows = rows
            prim: Any = prims[rows]
        else:
            prim = p
            kind = int(scene.pattern[scene.mat[p]])
        at = patterned[rows]
        m = scene.mat[prim]
        xform = scene.xform[prim]
        obj = G.point_to_object(scene.inv[:, xform], *(c[at] for c in hits.over))
        x, y, z = G.point_to_object(scene.pat_inv[:, m], *obj)
        a, b = scene.pat_a[:, m], scene.pat_b[:, m]
        if kind == TEST_PATTERN:
            values: Any = (x, y, z)
        elif kind == GRADIENT:
            fraction = x - np.floor(x)
            values = tuple(a[k] + (b[k] - a[k]) * fraction for k in range(3))
        else:
            if kind == STRIPES:
                even = np.floor(x) % 2 == 0
            elif kind == RINGS:
                even = np.floor(np.sqrt(x * x + z * z)) % 2 == 0
            elif kind == CHECKERS:
                even = (np.floor(x) + np.floor(y) + np.floor(z)) % 2 == 0
            else:  # pragma: no cover - packing refuses any other
                raise ValueError(f"wavefront: unknown pattern kind {kind}")
            values = tuple(np.where(even, a[k], b[k]) for k in range(3))
        for k in range(3):
            color[k][at] = values[k]
    return color[0], color[1], color[2]


Blocked = Callable[[Three, Three, Any], np.ndarray]
"""(origins, directions, distances) -> which shadow rays are blocked."""


def shade(scene: Scene, hits: Hits, blocked: Blocked) -> Three:
    """Chapters 6, 7, 8 (``shade_hit``'s surface part): every light's ``lighting`` at the
    over point, each with its own shadow ray (cast only where the light is in front of
    the surface: behind it, the result is the ambient term either way); the ambient term
    once, with the first light. No light: black."""
    mats = hits.mat
    n = len(mats)
    dtype = hits.point[0].dtype
    total = [np.zeros(n, dtype=dtype) for _ in range(3)]
    if not len(scene.light_pos):
        return total[0], total[1], total[2]
    base = surface(scene, hits)
    ambient = scene.ambient[mats]
    diffuse = scene.diffuse[mats]
    specular = scene.specular[mats]
    shininess = scene.shininess[mats]
    normal, eyev, over = hits.normal, hits.eyev, hits.over
    for k in range(len(scene.light_pos)):
        position = scene.light_pos[k]
        intensity = scene.light_int[k]
        effective = [base[c] * intensity[c] for c in range(3)]
        v = (position[0] - over[0], position[1] - over[1], position[2] - over[2])
        distance = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        lightv = (v[0] / distance, v[1] / distance, v[2] / distance)
        light_dot_normal = _dot(lightv, normal)
        facing = np.flatnonzero(light_dot_normal >= 0)
        lit = np.zeros(n, dtype=bool)
        if len(facing):
            shadowed = blocked(
                tuple(c[facing] for c in over),
                tuple(c[facing] for c in lightv),
                distance[facing],
            )
            lit[facing[~shadowed]] = True
        twice = -light_dot_normal  # dot(-lightv, normal)
        reflectv = tuple(-lv - nv * 2 * twice for lv, nv in zip(lightv, normal, strict=True))
        reflect_dot_eye = _dot(reflectv, eyev)
        shiny = lit & (reflect_dot_eye > 0)
        factor = np.power(np.where(shiny, reflect_dot_eye, 0), shininess)
        for c in range(3):
            part = effective[c] * ambient if k == 0 else np.zeros(n, dtype=dtype)
            diffuse_c = effective[c] * diffuse * light_dot_normal
            specular_c = np.where(shiny, intensity[c] * specular * factor, 0)
            lit_c = np.where(lit, part + diffuse_c + specular_c, part)
            total[c] = lit_c if k == 0 else total[c] + lit_c
    return total[0], total[1], total[2]


def schlick(eyev: Three, normal: Three, n1: Any, n2: Any) -> Any:
    """Chapter 11: Schlick's approximation of the reflectance."""
    cos = _dot(eyev, normal)
    ratio = n1 / n2
    sin2_t = ratio * ratio * (1.0 - cos * cos)
    denser = n1 > n2
    total = denser & (sin2_t > 1.0)
    cos = np.where(denser & ~total, np.sqrt(np.where(total, 0, 1.0 - sin2_t)), cos)
    r0 = np.power((n1 - n2) / (n1 + n2), 2.0)
    return np.where(total, 1.0, r0 + (1 - r0) * np.power(1 - cos, 5.0))


def refraction(eyev: Three, normal: Three, n1: Any, n2: Any) -> tuple[Any, Three]:
    """Chapter 11 (``refracted_color``'s ray): (possible, direction), possible False under
    total internal reflection."""
    n_ratio = n1 / n2
    cos_i = _dot(eyev, normal)
    sin2_t = n_ratio * n_ratio * (1 - cos_i * cos_i)
    possible = ~(sin2_t > 1)
    cos_t = np.sqrt(np.where(possible, 1.0 - sin2_t, 0))
    scale = n_ratio * cos_i - cos_t
    direction = tuple(nv * scale - ev * n_ratio for nv, ev in zip(normal, eyev, strict=True))
    return possible, direction
