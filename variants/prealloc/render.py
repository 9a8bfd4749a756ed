"""The camera and the pixels (chapter 7) with one ray buffer and one colour buffer for the
whole image; the loop over the pixels is the reference ``Tracer.render_region``.

The camera's inverse transform, its origin in world space and its pixel size are read once
per render (the naive ``ray_for_pixel`` inverts the camera transform for every pixel).
Samples per pixel, seed and epsilon follow ``raytracer.camera.RenderSettings`` and
``raytracer.sampling`` exactly, so the picture is the reference's, pixel for pixel.
"""

from __future__ import annotations

import math

from raytracer.camera import Camera, RenderSettings
from raytracer.colors import Color
from raytracer.sampling import sample_offset
from raytracer.world import World
from variants.prealloc.buffers import Vec, new_color, new_ray
from variants.prealloc.context import TraceContext
from variants.prealloc.geometry import flat_matrix
from variants.prealloc.shading import color_at_into


class CameraRecord:
    """Chapter 7: what ``ray_for_pixel`` reads, computed once: the flat inverse transform,
    the camera's origin in world space (``inverse * point(0, 0, 0)``), the half extents and
    the pixel size."""

    __slots__ = ("half_height", "half_width", "inverse", "origin", "pixel_size")

    def __init__(self, c: Camera) -> None:
        self.inverse = inv = flat_matrix(c.inverse_transform)
        self.half_width = c.half_width
        self.half_height = c.half_height
        self.pixel_size = c.pixel_size
        # inv * point(0, 0, 0), term by term as Matrix * Tuple computes it
        self.origin = [
            inv[0] * 0.0 + inv[1] * 0.0 + inv[2] * 0.0 + inv[3] * 1.0,
            inv[4] * 0.0 + inv[5] * 0.0 + inv[6] * 0.0 + inv[7] * 1.0,
            inv[8] * 0.0 + inv[9] * 0.0 + inv[10] * 0.0 + inv[11] * 1.0,
            inv[12] * 0.0 + inv[13] * 0.0 + inv[14] * 0.0 + inv[15] * 1.0,
        ]


def ray_for_pixel_into(cam: CameraRecord, px: float, py: float, out: Vec) -> None:
    """Chapter 7: the ray through pixel (px, py), written into ``out`` (naive twin:
    ``raytracer.camera.ray_for_pixel``)."""
    pixel_size = cam.pixel_size
    world_x = cam.half_width - (px + 0.5) * pixel_size
    world_y = cam.half_height - (py + 0.5) * pixel_size
    m = cam.inverse
    # pixel = inverse * point(world_x, world_y, -1)
    x = m[0] * world_x + m[1] * world_y + m[2] * -1.0 + m[3] * 1.0
    y = m[4] * world_x + m[5] * world_y + m[6] * -1.0 + m[7] * 1.0
    z = m[8] * world_x + m[9] * world_y + m[10] * -1.0 + m[11] * 1.0
    w = m[12] * world_x + m[13] * world_y + m[14] * -1.0 + m[15] * 1.0
    ox, oy, oz, ow = cam.origin
    x, y, z, w = x - ox, y - oy, z - oz, w - ow
    length = math.sqrt(x * x + y * y + z * z + w * w)
    out[0], out[1], out[2], out[3] = ox, oy, oz, ow
    out[4], out[5], out[6], out[7] = x / length, y / length, z / length, w / length


def pixel_color_into(
    ctx: TraceContext,
    cam: CameraRecord,
    x: int,
    y: int,
    settings: RenderSettings,
    ray: Vec,
    sample: Vec,
    out: Vec,
) -> None:
    """The colour of pixel (x, y) into ``out``: one ray through its centre, or the mean of
    the samples, summed in order then scaled by 1 / samples (naive twin:
    ``raytracer.tracer.Tracer.pixel_color``). ``ray``, ``sample``: scratch buffers. Sets
    ``ctx.sample`` before each sample (the jitter of area lights)."""
    depth = settings.depth
    if settings.samples == 1:
        ctx.sample = (settings.seed, x, y, 0)
        ray_for_pixel_into(cam, x, y, ray)
        color_at_into(ctx, ray, depth, out)
        return
    r = g = b = 0.0
    for i in range(settings.samples):
        ctx.sample = (settings.seed, x, y, i)
        dx, dy = sample_offset(settings.seed, x, y, i)
        ray_for_pixel_into(cam, x + dx - 0.5, y + dy - 0.5, ray)
        color_at_into(ctx, ray, depth, sample)
        r, g, b = r + sample[0], g + sample[1], b + sample[2]
    scale = 1.0 / settings.samples
    out[0], out[1], out[2] = r * scale, g * scale, b * scale


class PixelTracer:
    """Chapter 7: everything one frame reuses for every pixel: the context (records,
    per-depth scratch), the camera record and the ray and colour buffers. ``tracer(x, y)``
    is pixel (x, y)'s colour, as the reference's ``pixel_color`` computes it.

    ``PreallocTracer.prepare`` makes one per frame (a ``pooled`` worker: one for all its
    jobs); ``Tracer.render_region`` calls it for each pixel.
    """

    __slots__ = ("camera", "color", "ctx", "ray", "sample", "settings")

    def __init__(self, c: Camera, w: World, settings: RenderSettings | None = None) -> None:
        self.settings = settings if settings is not None else RenderSettings()
        self.ctx = TraceContext.for_world(w, self.settings.epsilon, self.settings.depth)
        self.camera = CameraRecord(c)
        self.ray, self.sample, self.color = new_ray(), new_color(), new_color()

    def __call__(self, x: int, y: int) -> Color:
        color = self.color
        pixel_color_into(self.ctx, self.camera, x, y, self.settings, self.ray, self.sample, color)
        return Color(color[0], color[1], color[2])
