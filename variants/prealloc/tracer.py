"""``PreallocTracer``: the book's pipeline (chapters 6, 7, 8, 11, and the soft shadows bonus
chapter's ``intensity_at``) on the ``prealloc`` hot path.

Each step the book's scenarios call converts the reference's values into buffers, runs its
``..._into`` twin (``shading``, ``render``) on a small context of its own, and converts the
result back. A render is where preallocation pays: ``prepare`` builds one ``PixelTracer``
per frame (the records of the scene, the per-depth scratch, the ray and colour buffers) and
the reference's ``render_region`` calls it for every pixel.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from raytracer.camera import WHITTED, Camera, RenderSettings
from raytracer.colors import Color
from raytracer.intersections import Computations, Intersection
from raytracer.lights import Light, describe_lights
from raytracer.materials import Material, light_fraction
from raytracer.rays import Ray
from raytracer.space import Placed
from raytracer.tracer import Tracer, light_and_point, shape_lit
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.prealloc import shading
from variants.prealloc.api import (
    buffer_in,
    call_context,
    color_out,
    comps_in,
    comps_out,
    intersections_out,
    ray_in,
    ray_out,
)
from variants.prealloc.buffers import (
    ComputationsBuffer,
    IntersectionBuffer,
    Vec,
    new_color,
    new_ray,
    tuple_buffer,
)
from variants.prealloc.context import TraceContext, material_record
from variants.prealloc.records import LightRecord
from variants.prealloc.render import CameraRecord, PixelTracer, ray_for_pixel_into


def _shade(
    tracer: Tracer,
    step: Callable[[TraceContext, ComputationsBuffer, int, Vec], None],
    w: World,
    comps: Computations,
    remaining: int,
) -> Color:
    ctx = _world_context(tracer, w, remaining)
    out = new_color()
    step(ctx, comps_in(ctx, comps), remaining, out)
    return color_out(out)


def _world_context(tracer: Tracer, w: World, depth: int = 0) -> TraceContext:
    """A call's context for ``w``, at the tracer's current sample (the reference's
    ``light_for_sample`` jitters area lights by it)."""
    ctx = call_context(w, depth)
    ctx.sample = tracer._sample
    return ctx


class PreallocTracer(Tracer):
    """The book's tracer with every step on preallocated buffers (chapters 6-11)."""

    __slots__ = ()

    def lighting(
        self,
        material: Material,
        object: Placed | None,
        light: Light,
        point: Tuple,
        eyev: Tuple,
        normalv: Tuple,
        in_shadow: bool | float = False,
        ambient: bool = True,
    ) -> Color:
        """Chapters 6, 8, 10 and soft shadows: ``lighting_into`` on a new buffer (in_shadow:
        the book's true or false, or the fraction of the light that arrives)."""
        intensity = light_fraction(in_shadow)
        ctx = call_context()
        obj = None if object is None else ctx.record(shape_lit(object))
        out = new_color()
        shading.lighting_into(
            ctx,
            material_record(material),
            obj,
            LightRecord(light),
            tuple_buffer(point),
            tuple_buffer(eyev),
            tuple_buffer(normalv),
            intensity,
            out,
            bool(ambient),
        )
        return color_out(out)

    def intersect_world(self, w: World, r: Ray) -> list[Intersection]:
        """Chapter 7: ``intersect_world_into`` on a new buffer."""
        xs = IntersectionBuffer()
        shading.intersect_world_into(call_context(w), ray_in(r), xs)
        return intersections_out(xs)

    def prepare_computations(
        self, hit: Intersection, r: Ray, xs: Sequence[Intersection] | None = None
    ) -> Computations:
        """Chapters 7, 8, 11: ``prepare_computations_into`` on new buffers."""
        ctx = call_context()
        ray = ray_in(r)
        comps = ComputationsBuffer()
        if xs is None:
            only = buffer_in(ctx, [hit])
            shading.prepare_computations_into(ctx, only, 0, ray, only, 0, comps)
        else:
            buffer = buffer_in(ctx, xs)
            index = next((j for j, i in enumerate(xs) if i is hit), -1)
            hits, h = (buffer, index) if index >= 0 else (buffer_in(ctx, [hit]), 0)
            shading.prepare_computations_into(ctx, hits, h, ray, buffer, index, comps)
        return comps_out(comps)

    def shade_hit(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapters 7, 8, 11: ``shade_hit_into`` on a new buffer."""
        return _shade(self, shading.shade_hit_into, w, comps, remaining)

    def color_at(self, w: World, r: Ray, remaining: int = 5) -> Color:
        """Chapter 7: ``color_at_into`` on a new buffer."""
        out = new_color()
        shading.color_at_into(_world_context(self, w, remaining), ray_in(r), remaining, out)
        return color_out(out)

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        """Chapter 8: ``is_shadowed`` with the context's shadow buffers (both of the
        reference's forms)."""
        light_position, point = light_and_point(w, first, second, "is_shadowed")
        ctx = call_context(w)
        return shading.is_shadowed(ctx, tuple_buffer(light_position), tuple_buffer(point))

    def intensity_at(self, light: Light, point: Tuple, w: World) -> float:
        """Soft shadows: ``intensity_at`` with the context's shadow buffers; the light as
        given (its own ``jitter_by``, as the reference's)."""
        return shading.intensity_at(call_context(w), LightRecord(light), tuple_buffer(point))

    def reflected_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: ``reflected_color_into`` on a new buffer."""
        return _shade(self, shading.reflected_color_into, w, comps, remaining)

    def refracted_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: ``refracted_color_into`` on a new buffer."""
        return _shade(self, shading.refracted_color_into, w, comps, remaining)

    def schlick(self, comps: Computations) -> float:
        """Chapter 11: ``schlick`` of the buffered computations."""
        return shading.schlick(comps_in(call_context(), comps))

    def ray_for_pixel(self, c: Camera, px: float, py: float) -> Ray:
        """Chapter 7: ``ray_for_pixel_into`` on a new buffer."""
        out = new_ray()
        ray_for_pixel_into(CameraRecord(c), px, py, out)
        return ray_out(out)

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Any:
        """Chapter 7: one frame's records and buffers, reused for every pixel. The path
        integrator (chapter 21) renders through the reference's pixel loop, over this
        tracer's steps."""
        if settings.integrator != WHITTED:
            return super().prepare(c, w, settings)
        return PixelTracer(c, w, settings)

    def explain(self, w: World) -> str:
        return (
            f"{type(self).__name__}: cached's shapes traced through per-frame records and "
            f"reused buffers (one PixelTracer per frame); {len(w.objects)} objects at the top "
            f"of the world, {describe_lights(w.lights)}"
        )
