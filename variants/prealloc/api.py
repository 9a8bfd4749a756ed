"""The book's API on top of the ``prealloc`` hot path: each function converts the
reference's values into buffers, runs the ``..._into`` implementation, and converts the
result back (chapters 5-16).

These are the functions the book's scenarios call, so the scenarios exercise the variant's
code, not the reference's. Each call builds its own small ``TraceContext``; only
``render`` reuses one context for a whole image, which is where preallocation pays.
``OVERRIDES`` lists exactly the book names defined here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from raytracer.camera import Camera, RenderSettings
from raytracer.canvas import Canvas
from raytracer.colors import Color
from raytracer.intersections import Computations, Intersection
from raytracer.lights import PointLight
from raytracer.materials import Material
from raytracer.matrices import Matrix
from raytracer.patterns import Pattern
from raytracer.rays import Ray
from raytracer.shapes.shape import Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.prealloc import render as _render
from variants.prealloc import shading
from variants.prealloc.buffers import (
    ComputationsBuffer,
    IntersectionBuffer,
    Vec,
    add_intersection,
    hit_index,
    new_color,
    new_ray,
    new_tuple,
    sort_intersections,
)
from variants.prealloc.context import TraceContext, material_record
from variants.prealloc.geometry import (
    flat_matrix,
    normal_to_world_into,
    position_into,
    reflect_into,
    transform_ray_into,
    world_to_object_into,
)
from variants.prealloc.patterns import pattern_record
from variants.prealloc.records import LightRecord, PreallocUnsupported
from variants.prealloc.shapes import (
    CSGRecord,
    filter_intersections_into,
    intersect_into,
    normal_at_into,
)

# ------------------------------------------------------------------- values in and out


def _tuple_in(t: Tuple) -> Vec:
    return [float(t.x), float(t.y), float(t.z), float(t.w)]


def _tuple_out(v: Vec) -> Tuple:
    return Tuple(v[0], v[1], v[2], v[3])


def _ray_in(r: Ray) -> Vec:
    return _tuple_in(r.origin) + _tuple_in(r.direction)


def _ray_out(v: Vec) -> Ray:
    return Ray(Tuple(v[0], v[1], v[2], v[3]), Tuple(v[4], v[5], v[6], v[7]))


def _color_out(c: Vec) -> Color:
    return Color(c[0], c[1], c[2])


def _buffer_in(ctx: TraceContext, xs: Sequence[Intersection]) -> IntersectionBuffer:
    buffer = IntersectionBuffer()
    for i in xs:
        add_intersection(buffer, float(i.t), ctx.record(i.object), i.u, i.v)
    return buffer


def _intersections_out(xs: IntersectionBuffer) -> list[Intersection]:
    return [
        Intersection(xs.ts[i], xs.objects[i].shape, xs.us[i], xs.vs[i]) for i in range(xs.count)
    ]


def _comps_in(ctx: TraceContext, comps: Computations) -> ComputationsBuffer:
    buffer = ComputationsBuffer()
    buffer.t = float(comps.t)
    buffer.object = ctx.record(comps.object)
    buffer.point = _tuple_in(comps.point)
    buffer.eyev = _tuple_in(comps.eyev)
    buffer.normalv = _tuple_in(comps.normalv)
    buffer.inside = comps.inside
    buffer.over_point = _tuple_in(comps.over_point)
    buffer.under_point = _tuple_in(comps.under_point)
    buffer.reflectv = _tuple_in(comps.reflectv)
    buffer.n1 = float(comps.n1)
    buffer.n2 = float(comps.n2)
    return buffer


def _comps_out(comps: ComputationsBuffer) -> Computations:
    return Computations(
        t=comps.t,
        object=comps.object.shape,
        point=_tuple_out(comps.point),
        eyev=_tuple_out(comps.eyev),
        normalv=_tuple_out(comps.normalv),
        inside=comps.inside,
        over_point=_tuple_out(comps.over_point),
        under_point=_tuple_out(comps.under_point),
        reflectv=_tuple_out(comps.reflectv),
        n1=comps.n1,
        n2=comps.n2,
    )


def _context(w: World | None = None, depth: int = 0) -> TraceContext:
    """A context for one API call, with the offset epsilon in effect."""
    if w is None:
        return TraceContext(epsilon(), None, depth)
    return TraceContext.for_world(w, epsilon(), depth)


# ------------------------------------------------------------ chapters 5, 6, 9, 14, 16


def transform(r: Ray, m: Matrix) -> Ray:
    """Chapter 5: ``transform_ray_into`` on a new buffer."""
    out = new_ray()
    transform_ray_into(flat_matrix(m), _ray_in(r), out)
    return _ray_out(out)


def position(r: Ray, t: float) -> Tuple:
    """Chapter 5: ``position_into`` on a new buffer."""
    out = new_tuple()
    position_into(_ray_in(r), t, out)
    return _tuple_out(out)


def reflect(v: Tuple, n: Tuple) -> Tuple:
    """Chapter 6: ``reflect_into`` on a new buffer."""
    out = new_tuple()
    reflect_into(_tuple_in(v), _tuple_in(n), out)
    return _tuple_out(out)


def intersect(shape: Shape, r: Ray) -> list[Intersection]:
    """Chapters 5, 9: ``intersect_into`` on a new buffer."""
    ctx = _context()
    xs = IntersectionBuffer()
    intersect_into(ctx.record(shape), _ray_in(r), xs)
    return _intersections_out(xs)


def local_intersect(shape: Shape, local_ray: Ray) -> list[Intersection]:
    """Chapter 9: the record's ``local_intersect_into`` on a new buffer."""
    ctx = _context()
    xs = IntersectionBuffer()
    ctx.record(shape).local_intersect_into(_ray_in(local_ray), xs)
    return _intersections_out(xs)


def intersections(*xs: Intersection) -> list[Intersection]:
    """Chapter 5: ``sort_intersections`` (the same stable order as ``sorted``); the
    buffer's object column carries the given intersections themselves."""
    buffer = IntersectionBuffer()
    for i in xs:
        add_intersection(buffer, i.t, i)
    sort_intersections(buffer)
    return buffer.objects[: buffer.count]


def hit(xs: Sequence[Intersection]) -> Intersection | None:
    """Chapter 5: ``hit_index`` over the t values; the given intersection itself."""
    buffer = IntersectionBuffer()
    for i in xs:
        add_intersection(buffer, i.t, None)
    index = hit_index(buffer)
    return xs[index] if index >= 0 else None


def normal_at(shape: Shape, world_point: Tuple, hit: Intersection | None = None) -> Tuple:
    """Chapters 6, 9, 14: ``normal_at_into`` on a new buffer."""
    out = new_tuple()
    u, v = (None, None) if hit is None else (hit.u, hit.v)
    normal_at_into(_context().record(shape), _tuple_in(world_point), u, v, out)
    return _tuple_out(out)


def local_normal_at(shape: Shape, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
    """Chapter 9: the record's ``local_normal_at_into`` on a new buffer."""
    out = new_tuple()
    u, v = (None, None) if hit is None else (hit.u, hit.v)
    _context().record(shape).local_normal_at_into(_tuple_in(local_point), u, v, out)
    return _tuple_out(out)


def world_to_object(shape: Shape, point: Tuple) -> Tuple:
    """Chapter 14: ``world_to_object_into`` on a new buffer."""
    out = new_tuple()
    world_to_object_into(_context().record(shape), _tuple_in(point), out)
    return _tuple_out(out)


def normal_to_world(shape: Shape, normal: Tuple) -> Tuple:
    """Chapter 14: ``normal_to_world_into`` on a new buffer."""
    out = new_tuple()
    normal_to_world_into(_context().record(shape), _tuple_in(normal), out)
    return _tuple_out(out)


def filter_intersections(c: Shape, xs: Sequence[Intersection]) -> list[Intersection]:
    """Chapter 16: ``filter_intersections_into`` on new buffers."""
    ctx = _context()
    rec = ctx.record(c)
    if not isinstance(rec, CSGRecord):
        raise PreallocUnsupported(
            f"filter_intersections: expected a CSG shape, got {type(c).__name__}"
        )
    out = IntersectionBuffer()
    filter_intersections_into(rec, _buffer_in(ctx, xs), out)
    return _intersections_out(out)


# ---------------------------------------------------------------------- chapter 10


def pattern_at(pattern: Pattern, point: Tuple) -> Color:
    """Chapter 10: the pattern record's ``pattern_at_into`` on a new buffer."""
    out = new_color()
    pattern_record(pattern).pattern_at_into(_tuple_in(point), out)
    return _color_out(out)


def pattern_at_shape(pattern: Pattern, shape: Shape, world_point: Tuple) -> Color:
    """Chapters 10, 14: ``pattern_at_shape_into`` on a new buffer."""
    ctx = _context()
    out = new_color()
    shading.pattern_at_shape_into(
        ctx, pattern_record(pattern), ctx.record(shape), _tuple_in(world_point), out
    )
    return _color_out(out)


# ------------------------------------------------------------- chapters 6, 7, 8, 11


def lighting(
    material: Material,
    object: Shape | None,
    light: PointLight,
    point: Tuple,
    eyev: Tuple,
    normalv: Tuple,
    in_shadow: bool = False,
) -> Color:
    """Chapters 6, 8, 10: ``lighting_into`` on a new buffer."""
    ctx = _context()
    obj = None if object is None else ctx.record(object)
    out = new_color()
    shading.lighting_into(
        ctx,
        material_record(material),
        obj,
        LightRecord(light),
        _tuple_in(point),
        _tuple_in(eyev),
        _tuple_in(normalv),
        bool(in_shadow),
        out,
    )
    return _color_out(out)


def intersect_world(w: World, r: Ray) -> list[Intersection]:
    """Chapter 7: ``intersect_world_into`` on a new buffer."""
    xs = IntersectionBuffer()
    shading.intersect_world_into(_context(w), _ray_in(r), xs)
    return _intersections_out(xs)


def prepare_computations(
    hit: Intersection, r: Ray, xs: Sequence[Intersection] | None = None
) -> Computations:
    """Chapters 7, 8, 11: ``prepare_computations_into`` on new buffers."""
    ctx = _context()
    ray = _ray_in(r)
    comps = ComputationsBuffer()
    if xs is None:
        only = _buffer_in(ctx, [hit])
        shading.prepare_computations_into(ctx, only, 0, ray, only, 0, comps)
    else:
        buffer = _buffer_in(ctx, xs)
        index = next((j for j, i in enumerate(xs) if i is hit), -1)
        hits, h = (buffer, index) if index >= 0 else (_buffer_in(ctx, [hit]), 0)
        shading.prepare_computations_into(ctx, hits, h, ray, buffer, index, comps)
    return _comps_out(comps)


def schlick(comps: Computations) -> float:
    """Chapter 11: ``schlick`` of the buffered computations."""
    return shading.schlick(_comps_in(_context(), comps))


def is_shadowed(w: World, point: Tuple) -> bool:
    """Chapter 8: ``is_shadowed`` with the context's shadow buffers."""
    return shading.is_shadowed(_context(w), _tuple_in(point))


def _shade(
    step: Callable[[TraceContext, ComputationsBuffer, int, Vec], None],
    w: World,
    comps: Computations,
    remaining: int,
) -> Color:
    ctx = _context(w, remaining)
    out = new_color()
    step(ctx, _comps_in(ctx, comps), remaining, out)
    return _color_out(out)


def shade_hit(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapters 7, 8, 11: ``shade_hit_into`` on a new buffer."""
    return _shade(shading.shade_hit_into, w, comps, remaining)


def reflected_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: ``reflected_color_into`` on a new buffer."""
    return _shade(shading.reflected_color_into, w, comps, remaining)


def refracted_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: ``refracted_color_into`` on a new buffer."""
    return _shade(shading.refracted_color_into, w, comps, remaining)


def color_at(w: World, r: Ray, remaining: int = 5) -> Color:
    """Chapter 7: ``color_at_into`` on a new buffer."""
    out = new_color()
    shading.color_at_into(_context(w, remaining), _ray_in(r), remaining, out)
    return _color_out(out)


def ray_for_pixel(c: Camera, px: float, py: float) -> Ray:
    """Chapter 7: ``ray_for_pixel_into`` on a new buffer."""
    out = new_ray()
    _render.ray_for_pixel_into(_render.CameraRecord(c), px, py, out)
    return _ray_out(out)


def render(
    c: Camera,
    w: World,
    settings: RenderSettings | None = None,
    progress: Callable[[int], object] | None = None,
) -> Canvas:
    """Chapter 7: the whole image through one reused context (``prealloc.render``)."""
    return _render.render(c, w, settings, progress)


API: dict[str, Any] = {
    "transform": transform,
    "position": position,
    "reflect": reflect,
    "intersect": intersect,
    "local_intersect": local_intersect,
    "intersections": intersections,
    "hit": hit,
    "normal_at": normal_at,
    "local_normal_at": local_normal_at,
    "world_to_object": world_to_object,
    "normal_to_world": normal_to_world,
    "filter_intersections": filter_intersections,
    "pattern_at": pattern_at,
    "stripe_at": pattern_at,
    "pattern_at_shape": pattern_at_shape,
    "stripe_at_object": pattern_at_shape,
    "lighting": lighting,
    "intersect_world": intersect_world,
    "prepare_computations": prepare_computations,
    "schlick": schlick,
    "is_shadowed": is_shadowed,
    "shade_hit": shade_hit,
    "reflected_color": reflected_color,
    "refracted_color": refracted_color,
    "color_at": color_at,
    "ray_for_pixel": ray_for_pixel,
    "render": render,
}
"""The book names the ``prealloc`` variant implements itself (everything else: ``cached``)."""

OVERRIDES = frozenset(API)
