"""The wavefront loop (chapters 7 and 11 without recursion) and the render passes.

``trace`` follows a batch of rays (structure of arrays: origins, directions, weights,
pixels; the batch's remaining depth) and everything they spawn: one nearest-hit query for
the whole batch, shading with every light's shadow rays as further queries, then the
reflected and refracted rays of all hits gathered into the next batch with their weights
(reflectance or transparency, times Schlick's factor where both apply). Batches wait on a
stack, cut to at most ``cap`` rays, so memory stays bounded whatever the depth.

A pass is a block of consecutive pixels of a region (row-major) with all their samples
(``blocks``); its camera rays go through ``trace`` (the book's integrator) or
``paths.trace_paths`` (the path integrator) and the block's pixels come out in float64
(``render_block``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import PATH, RenderSettings
from variants.wavefront.camera import Lens, camera_rays, sample_keys, sample_offsets
from variants.wavefront.hits import Index, blocked, nearest, sub
from variants.wavefront.indices import indices_in_parts
from variants.wavefront.paths import trace_paths
from variants.wavefront.shading import (
    Three,
    prepare,
    refraction,
    schlick,
    shade,
)

Region = tuple[int, int, int, int]


@dataclass(frozen=True)
class Frame:
    """One render's prepared state: the packed, indexed world, the camera, the settings,
    the precision and how many rays a batch holds."""

    idx: Index
    lens: Lens | None
    settings: RenderSettings
    dtype: Any
    eps: float
    cap: int


def _pick(arrays: Three, rows: Any) -> Three:
    return arrays[0][rows], arrays[1][rows], arrays[2][rows]


def trace(
    frame: Frame, ray: tuple[Any, ...], weight: Any, pixel: Any, remaining: int, pixels: int
) -> np.ndarray:
    """Chapter 7's ``color_at`` for a batch of rays and all the rays they spawn: the
    weighted colors summed per pixel, (pixels, 3) float64."""
    with np.errstate(all="ignore"):  # IEEE infinities and NaNs are part of the arithmetic
        return _trace(frame, ray, weight, pixel, remaining, pixels)


def _trace(
    frame: Frame, ray: tuple[Any, ...], weight: Any, pixel: Any, remaining: int, pixels: int
) -> np.ndarray:
    idx, eps, cap = frame.idx, frame.eps, frame.cap
    scene = idx.scene
    total = np.zeros((pixels, 3))
    stack = [(ray, weight, pixel, remaining)]

    def shadows(origin: Three, direction: Three, distance: Any) -> np.ndarray:
        return blocked(idx, (*origin, *direction), distance, eps, cap)

    while stack:
        ray, weight, pixel, remaining = stack.pop()
        hit = nearest(idx, ray, eps, cap)
        found = hit.prim >= 0
        if not found.all():
            rows = np.flatnonzero(found)
            if not len(rows):
                continue
            ray, weight, pixel = sub(ray, rows), weight[rows], pixel[rows]
            hit = hit.take(rows)
        origin, direction = ray[:3], ray[3:]
        hits = prepare(scene, origin, direction, hit, eps)
        color = shade(scene, hits, shadows)
        for c in range(3):
            total[:, c] += np.bincount(pixel, weights=color[c] * weight, minlength=pixels)
        if remaining <= 0 or not scene.mirrors:
            continue
        reflective = scene.reflective[hits.mat]
        transparency = scene.transparency[hits.mat]
        mirror = reflective != 0
        glass = np.flatnonzero(transparency != 0)
        reflected_weight = weight * reflective
        refracted_weight = weight * transparency
        parts = []
        if len(glass):
            n1, n2 = indices_in_parts(idx, sub(ray, glass), hit.take(glass), eps, cap)
            eyev, normal = _pick(hits.eyev, glass), _pick(hits.normal, glass)
            both = (reflective[glass] > 0) & (transparency[glass] > 0)
            if both.any():
                reflectance = schlick(eyev, normal, n1, n2)
                reflected_weight[glass] = np.where(
                    both, reflected_weight[glass] * reflectance, reflected_weight[glass]
                )
                refracted_weight[glass] = np.where(
                    both, refracted_weight[glass] * (1 - reflectance), refracted_weight[glass]
                )
            possible, bent = refraction(eyev, normal, n1, n2)
            go = possible & (refracted_weight[glass] != 0)
            rows = glass[go]
            parts.append(
                (
                    *_pick(hits.under, rows),
                    *(d[go] for d in bent),
                    refracted_weight[rows],
                    pixel[rows],
                )
            )
        rows = np.flatnonzero(mirror & (reflected_weight != 0))
        if len(rows):
            parts.append(
                (
                    *_pick(hits.over, rows),
                    *_pick(hits.reflectv, rows),
                    reflected_weight[rows],
                    pixel[rows],
                )
            )
        if not parts:
            continue
        columns = [np.concatenate([p[k] for p in parts]) for k in range(8)]
        n = len(columns[0])
        if not n:
            continue
        pieces = -(-n // cap)
        for k in range(pieces):
            rows_k = slice(k * n // pieces, (k + 1) * n // pieces)
            child = tuple(a[rows_k] for a in columns[:6])
            stack.append((child, columns[6][rows_k], columns[7][rows_k], remaining - 1))
    return total


def blocks(n_pixels: int, samples: int, cap: int, threads: int = 1) -> Iterator[tuple[int, int]]:
    """(first pixel, end pixel) of each pass over ``n_pixels`` pixels: whole pixels with
    all their samples, at most ``cap`` rays (one pixel when it alone has more samples:
    ``render_block`` then traces its samples ``cap`` at a time), as many passes as that
    takes rounded up to a multiple of ``threads``, all the same size to a pixel, so that
    ``threads`` threads taking them in turn end together."""
    step = max(1, cap // samples)
    count = -(-n_pixels // step)
    count = min(n_pixels, -(-count // threads) * threads)
    for k in range(count):
        yield k * n_pixels // count, (k + 1) * n_pixels // count


def render_block(frame: Frame, region: Region, first: int, end: int) -> np.ndarray:
    """The colors (end - first, 3), float64, of pixels first .. end - 1 of ``region``
    (row-major): chapter 7's ``pixel_color``, the samples' sum times 1 / samples."""
    samples = frame.settings.samples
    if samples == 1:
        return _trace_samples(frame, region, first, end, 0, 1)
    total = np.zeros((end - first, 3))
    for s0 in range(0, samples, frame.cap):
        total += _trace_samples(frame, region, first, end, s0, min(s0 + frame.cap, samples))
    return total * (1.0 / samples)


def _trace_samples(
    frame: Frame, region: Region, first: int, end: int, s0: int, s1: int
) -> np.ndarray:
    """The summed colors of samples s0 .. s1 - 1 of pixels first .. end - 1."""
    assert frame.lens is not None
    x0, y0, x1, _ = region
    width = x1 - x0
    per = s1 - s0
    k = np.arange((end - first) * per)
    local = k // per if per > 1 else k
    pixel = first + local
    x = x0 + pixel % width
    y = y0 + pixel // width
    settings = frame.settings
    sample = s0 + k % per
    if settings.samples == 1:
        ray = camera_rays(frame.lens, x, y, frame.dtype)
    else:
        dx, dy = sample_offsets(settings.seed, x, y, sample)
        ray = camera_rays(frame.lens, x + dx - 0.5, y + dy - 0.5, frame.dtype)
    if settings.integrator == PATH:
        keys = sample_keys(settings.seed, x, y, sample)
        return trace_paths(frame.idx, settings, frame.eps, frame.cap, ray, keys, local,
                           end - first)  # fmt: skip
    weight = np.ones(len(k), dtype=frame.dtype)
    return trace(frame, ray, weight, local, settings.depth, end - first)
