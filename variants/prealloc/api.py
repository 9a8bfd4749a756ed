"""The book's functions outside the tracer on top of the ``prealloc`` hot path (chapters 5,
6, 9, 10, 14, 16): each converts the reference's values into buffers, runs the ``..._into``
implementation, and converts the result back. The pipeline's functions are the methods of
``variants.prealloc.tracer.PreallocTracer``, which converts the same way.

These are the functions the book's scenarios call, so the scenarios exercise the variant's
code, not the reference's. Each call builds its own small ``TraceContext``; only a render
reuses one for a whole frame (``PixelTracer``), which is where preallocation pays.
``OVERRIDES`` lists exactly the book names defined here.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from raytracer.bounds import BoundingBox
from raytracer.bounds import transform as transform_value
from raytracer.colors import Color
from raytracer.intersections import Computations, Intersection
from raytracer.matrices import Matrix
from raytracer.patterns import Pattern
from raytracer.rays import Ray
from raytracer.shapes.shape import Shape
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple
from raytracer.world import World
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
    tuple_buffer,
)
from variants.prealloc.context import TraceContext
from variants.prealloc.errors import PreallocUnsupported
from variants.prealloc.geometry import flat_matrix, position_into, reflect_into, transform_ray_into
from variants.prealloc.groups import CSGRecord, filter_intersections_into
from variants.prealloc.patterns import pattern_record
from variants.prealloc.shapes import (
    intersect_into,
    normal_at_into,
    normal_to_world_into,
    world_to_object_into,
)

# ------------------------------------------------------------------- values in and out
# (shared with ``PreallocTracer``)


def tuple_out(v: Vec) -> Tuple:
    return Tuple(v[0], v[1], v[2], v[3])


def ray_in(r: Ray) -> Vec:
    return tuple_buffer(r.origin) + tuple_buffer(r.direction)


def ray_out(v: Vec) -> Ray:
    return Ray(Tuple(v[0], v[1], v[2], v[3]), Tuple(v[4], v[5], v[6], v[7]))


def color_out(c: Vec) -> Color:
    return Color(c[0], c[1], c[2])


def buffer_in(ctx: TraceContext, xs: Sequence[Intersection]) -> IntersectionBuffer:
    buffer = IntersectionBuffer()
    for i in xs:
        add_intersection(buffer, float(i.t), ctx.record(i.object), i.u, i.v)
    return buffer


def intersections_out(xs: IntersectionBuffer) -> list[Intersection]:
    return [
        Intersection(xs.ts[i], xs.objects[i].shape, xs.us[i], xs.vs[i]) for i in range(xs.count)
    ]


def comps_in(ctx: TraceContext, comps: Computations) -> ComputationsBuffer:
    buffer = ComputationsBuffer()
    buffer.t = float(comps.t)
    buffer.object = ctx.record(comps.object)
    buffer.point = tuple_buffer(comps.point)
    buffer.eyev = tuple_buffer(comps.eyev)
    buffer.normalv = tuple_buffer(comps.normalv)
    buffer.inside = comps.inside
    buffer.over_point = tuple_buffer(comps.over_point)
    buffer.under_point = tuple_buffer(comps.under_point)
    buffer.reflectv = tuple_buffer(comps.reflectv)
    buffer.n1 = float(comps.n1)
    buffer.n2 = float(comps.n2)
    return buffer


def comps_out(comps: ComputationsBuffer) -> Computations:
    return Computations(
        t=comps.t,
        object=comps.object.shape,
        point=tuple_out(comps.point),
        eyev=tuple_out(comps.eyev),
        normalv=tuple_out(comps.normalv),
        inside=comps.inside,
        over_point=tuple_out(comps.over_point),
        under_point=tuple_out(comps.under_point),
        reflectv=tuple_out(comps.reflectv),
        n1=comps.n1,
        n2=comps.n2,
    )


def call_context(w: World | None = None, depth: int = 0) -> TraceContext:
    """A context for one API call, with the offset epsilon in effect."""
    if w is None:
        return TraceContext(epsilon(), (), depth)
    return TraceContext.for_world(w, epsilon(), depth)


# ------------------------------------------------------------ chapters 5, 6, 9, 14, 16


def transform(r: Ray | BoundingBox, m: Matrix) -> Ray | BoundingBox:
    """Chapter 5: ``transform_ray_into`` on a new buffer. A bounding box (the bonus chapter
    'Bounding boxes and hierarchies'), or anything else, goes to the reference's
    ``transform``, which transforms boxes and refuses the rest."""
    if not isinstance(r, Ray):
        return transform_value(r, m)
    out = new_ray()
    transform_ray_into(flat_matrix(m), ray_in(r), out)
    return ray_out(out)


def position(r: Ray, t: float) -> Tuple:
    """Chapter 5: ``position_into`` on a new buffer."""
    out = new_tuple()
    position_into(ray_in(r), t, out)
    return tuple_out(out)


def reflect(v: Tuple, n: Tuple) -> Tuple:
    """Chapter 6: ``reflect_into`` on a new buffer."""
    out = new_tuple()
    reflect_into(tuple_buffer(v), tuple_buffer(n), out)
    return tuple_out(out)


def intersect(shape: Shape, r: Ray) -> list[Intersection]:
    """Chapters 5, 9: ``intersect_into`` on a new buffer."""
    ctx = call_context()
    xs = IntersectionBuffer()
    intersect_into(ctx.record(shape), ray_in(r), xs)
    return intersections_out(xs)


def local_intersect(shape: Shape, local_ray: Ray) -> list[Intersection]:
    """Chapter 9: the record's ``local_intersect_into`` on a new buffer."""
    ctx = call_context()
    xs = IntersectionBuffer()
    ctx.record(shape).local_intersect_into(ray_in(local_ray), xs)
    return intersections_out(xs)


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
    normal_at_into(call_context().record(shape), tuple_buffer(world_point), u, v, out)
    return tuple_out(out)


def local_normal_at(shape: Shape, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
    """Chapter 9: the record's ``local_normal_at_into`` on a new buffer."""
    out = new_tuple()
    u, v = (None, None) if hit is None else (hit.u, hit.v)
    call_context().record(shape).local_normal_at_into(tuple_buffer(local_point), u, v, out)
    return tuple_out(out)


def world_to_object(shape: Shape, point: Tuple) -> Tuple:
    """Chapter 14: ``world_to_object_into`` on a new buffer."""
    out = new_tuple()
    world_to_object_into(call_context().record(shape), tuple_buffer(point), out)
    return tuple_out(out)


def normal_to_world(shape: Shape, normal: Tuple) -> Tuple:
    """Chapter 14: ``normal_to_world_into`` on a new buffer."""
    out = new_tuple()
    normal_to_world_into(call_context().record(shape), tuple_buffer(normal), out)
    return tuple_out(out)


def filter_intersections(c: Shape, xs: Sequence[Intersection]) -> list[Intersection]:
    """Chapter 16: ``filter_intersections_into`` on new buffers."""
    ctx = call_context()
    rec = ctx.record(c)
    if not isinstance(rec, CSGRecord):
        raise PreallocUnsupported(
            f"filter_intersections: expected a CSG shape, got {type(c).__name__}"
        )
    out = IntersectionBuffer()
    filter_intersections_into(rec, buffer_in(ctx, xs), out)
    return intersections_out(out)


# ---------------------------------------------------------------------- chapter 10


def pattern_at(pattern: Pattern, point: Tuple) -> Color:
    """Chapter 10: the pattern record's ``pattern_at_into`` on a new buffer."""
    out = new_color()
    pattern_record(pattern).pattern_at_into(tuple_buffer(point), out)
    return color_out(out)


def pattern_at_shape(pattern: Pattern, shape: Shape, world_point: Tuple) -> Color:
    """Chapters 10, 14: ``pattern_at_shape_into`` on a new buffer."""
    ctx = call_context()
    out = new_color()
    shading.pattern_at_shape_into(
        ctx, pattern_record(pattern), ctx.record(shape), tuple_buffer(world_point), out
    )
    return color_out(out)


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
}
"""The book names ``prealloc`` implements outside its tracer (the rest: ``PreallocTracer``'s
methods and ``cached``'s constructors)."""

OVERRIDES = frozenset(API)
