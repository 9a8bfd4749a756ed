"""Paired micro-benchmarks: each optimization of ``cached`` and ``prealloc`` against its
naive twin, like the Go write-up's ``TransformRay`` against ``TransformRayPtr``.

In the normal test run each benchmark runs once, untimed (``--benchmark-disable`` is in
pyproject's addopts), so the twins' agreement is still checked. Time them with::

    .venv/bin/python -m pytest tests/benchmarks --benchmark-enable \\
        --benchmark-group-by=group --benchmark-columns=min,median,mean,stddev,rounds

Each pair is one benchmark group with two tests, ``naive`` and ``optimized``. Every
benchmark first checks that the two twins give the same answer, exactly, so they cannot
drift apart; ``test_twins_agree`` makes the same check in the normal test run.

The pairs:

- ``transform ray``: ``transform(r, m)`` (a new Ray of new Tuples) against
  ``transform_ray_into(m, ray, out)`` (a reused 8-float buffer);
- ``inverse transform``: a reference shape's ``inverse_transform`` (inverted on every
  access) against ``cached``'s (computed when the transform was set);
- ``intersection list``: ``intersections(...)`` of new ``Intersection`` values (a new
  sorted list) against a reused ``IntersectionBuffer`` reset to zero length and sorted in
  place;
- ``sphere intersection``: ``intersect(sphere, r)`` on ``cached``'s sphere against
  ``intersect_into`` on its record;
- ``shade one hit``: ``shade_hit(w, prepare_computations(hit, r, xs))`` on ``cached``'s
  default world against ``prepare_computations_into`` + ``shade_hit_into`` on a context.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import pytest

import raytracer as rt
from variants.cached import to_twins
from variants.prealloc.buffers import (
    ComputationsBuffer,
    IntersectionBuffer,
    add_intersection,
    hit_index,
    new_color,
    new_ray,
    sort_intersections,
)
from variants.prealloc.context import TraceContext
from variants.prealloc.geometry import flat_matrix, transform_ray_into
from variants.prealloc.shading import (
    intersect_world_into,
    prepare_computations_into,
    shade_hit_into,
)
from variants.prealloc.shapes import intersect_into

TRANSFORM = rt.translation(1, -2, 3) * rt.rotation_y(0.7) * rt.scaling(2, 0.5, 1.5)
RAY = rt.ray(rt.point(0.1, 0.2, -5), rt.normalize(rt.vector(0.02, -0.01, 1)))


def ray_buffer(r: rt.Ray) -> list[float]:
    o, d = r.origin, r.direction
    return [o.x, o.y, o.z, o.w, d.x, d.y, d.z, d.w]


@dataclass
class Twins:
    """Two ways to compute one thing. ``naive`` and ``optimized`` are what is timed;
    ``naive_answer`` and ``optimized_answer`` run them and return comparable values."""

    naive: Callable[[], Any]
    optimized: Callable[[], Any]
    naive_answer: Callable[[], Any]
    optimized_answer: Callable[[], Any]

    def agree(self) -> bool:
        return bool(self.naive_answer() == self.optimized_answer())


def transform_ray() -> Twins:
    m, flat = TRANSFORM, flat_matrix(TRANSFORM)
    ray, out = ray_buffer(RAY), new_ray()

    def naive() -> rt.Ray:
        return rt.transform(RAY, m)

    def optimized() -> None:
        transform_ray_into(flat, ray, out)

    def optimized_answer() -> list[float]:
        optimized()
        return list(out)

    return Twins(naive, optimized, lambda: ray_buffer(naive()), optimized_answer)


def inverse_transform() -> Twins:
    plain = rt.sphere()
    rt.set_transform(plain, TRANSFORM)
    twin = to_twins(plain)
    assert type(twin) is not type(plain)

    def naive() -> rt.Matrix:
        return plain.inverse_transform

    def optimized() -> rt.Matrix:
        return twin.inverse_transform

    return Twins(naive, optimized, naive, optimized)


def intersection_list() -> Twins:
    s1, s2 = rt.sphere(), rt.sphere()
    found = [(4.0, s1), (6.0, s1), (4.5, s2), (5.5, s2)]  # the default world's, object order
    xs = IntersectionBuffer()

    def naive() -> list[rt.Intersection]:
        return rt.intersections(*[rt.intersection(t, obj) for t, obj in found])

    def optimized() -> None:
        xs.count = 0
        for t, obj in found:
            add_intersection(xs, t, obj)
        sort_intersections(xs)

    def naive_answer() -> list[tuple[float, int]]:
        return [(i.t, id(i.object)) for i in naive()]

    def optimized_answer() -> list[tuple[float, int]]:
        optimized()
        return [(xs.ts[i], id(xs.objects[i])) for i in range(xs.count)]

    return Twins(naive, optimized, naive_answer, optimized_answer)


def sphere_intersection() -> Twins:
    s = rt.sphere()
    rt.set_transform(s, TRANSFORM)
    s = to_twins(s)
    rec = TraceContext(rt.EPSILON).record(s)
    ray, xs = ray_buffer(RAY), IntersectionBuffer()

    def naive() -> list[rt.Intersection]:
        return rt.intersect(s, RAY)

    def optimized() -> None:
        xs.count = 0
        intersect_into(rec, ray, xs)

    def optimized_answer() -> list[float]:
        optimized()
        return xs.ts[: xs.count]

    return Twins(naive, optimized, lambda: [i.t for i in naive()], optimized_answer)


def shade_one_hit() -> Twins:
    w = to_twins(rt.default_world())
    r = rt.ray(rt.point(0, 0, -5), rt.vector(0, 0, 1))
    xs = rt.intersect_world(w, r)
    h = rt.hit(xs)
    assert h is not None
    ctx = TraceContext.for_world(w, rt.EPSILON, 5)
    ray, buffer, comps, out = ray_buffer(r), IntersectionBuffer(), ComputationsBuffer(), new_color()
    intersect_world_into(ctx, ray, buffer)
    index = hit_index(buffer)

    def naive() -> rt.Color:
        return rt.shade_hit(w, rt.prepare_computations(h, r, xs))

    def optimized() -> None:
        prepare_computations_into(ctx, buffer, index, ray, buffer, index, comps)
        shade_hit_into(ctx, comps, 5, out)

    def naive_answer() -> list[float]:
        c = naive()
        return [c.red, c.green, c.blue]

    def optimized_answer() -> list[float]:
        optimized()
        return list(out)

    return Twins(naive, optimized, naive_answer, optimized_answer)


PAIRS: dict[str, Callable[[], Twins]] = {
    "transform ray": transform_ray,
    "inverse transform": inverse_transform,
    "intersection list": intersection_list,
    "sphere intersection": sphere_intersection,
    "shade one hit": shade_one_hit,
}


@pytest.mark.parametrize("pair", PAIRS)
def test_twins_agree(pair: str) -> None:
    twins = PAIRS[pair]()
    assert twins.agree(), f"{pair}: {twins.naive_answer()} != {twins.optimized_answer()}"


@pytest.mark.parametrize("twin", ["naive", "optimized"])
@pytest.mark.parametrize("pair", PAIRS)
def test_benchmark(benchmark: Any, pair: str, twin: str) -> None:
    twins = PAIRS[pair]()
    assert twins.agree(), f"{pair}: {twins.naive_answer()} != {twins.optimized_answer()}"
    benchmark.group = pair
    benchmark(getattr(twins, twin))
