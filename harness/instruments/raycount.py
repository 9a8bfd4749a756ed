"""Counting every ray a render casts: camera rays, shadow rays, reflected and refracted rays.

Two ways, tried in order:

1. A tracer with its own ``count_rays(camera, world, settings) -> {kind: count}`` (numba's)
   is asked: it renders once with counting on.
2. A tracer whose render goes through the pipeline's steps (it overrides none of
   ``prepare``, ``render_region``, ``render``: naive, cached, robust) renders once as a
   copy of itself whose class is a counting subclass: every ``ray_for_pixel`` is a camera
   ray, every ``color_at`` or ``path_color_at`` a traced ray (secondary: traced minus
   camera, the reflected and refracted ones, or a path's bounces) and every
   ``is_shadowed`` a shadow ray. Nothing global is changed.

Either way ``camera`` is what MRay/s divides by (width x height x samples, as the C++
report counts): the path integrator's bounces and shadow rays are the other kinds.

Other variants (prealloc, pooled, a learner's) cannot be counted and their rows say so.
Counting runs in a separate render, never in a timed one.
"""

from __future__ import annotations

import copy
from collections import Counter
from collections.abc import Mapping
from typing import Any

from raytracer.tracer import Tracer
from variants.wrapper import Wrapper, steps_overridden

HOOK = "the tracer's count_rays"
INSTRUMENTED = "a counting subclass of the tracer (its render goes through the pipeline)"
OWN_LOOP = ("prepare", "render_region", "render")  # steps that bypass the counted ones


class CountingMixin:
    """Counts camera rays, traced rays and shadow rays in the class's ``counts``."""

    __slots__ = ()
    counts: Counter[str]

    def ray_for_pixel(self, *args: Any, **kwargs: Any) -> Any:
        self.counts["camera"] += 1
        return super().ray_for_pixel(*args, **kwargs)  # type: ignore[misc]

    def color_at(self, *args: Any, **kwargs: Any) -> Any:
        self.counts["traced"] += 1
        return super().color_at(*args, **kwargs)  # type: ignore[misc]

    def path_color_at(self, *args: Any, **kwargs: Any) -> Any:
        self.counts["traced"] += 1
        return super().path_color_at(*args, **kwargs)  # type: ignore[misc]

    def is_shadowed(self, *args: Any, **kwargs: Any) -> Any:
        self.counts["shadow"] += 1
        return super().is_shadowed(*args, **kwargs)  # type: ignore[misc]


def counting_method(variant: Any) -> str | None:
    """How rays of ``variant`` can be counted, or None."""
    tracer = getattr(variant, "tracer", None)
    if not isinstance(tracer, Tracer):
        return None
    if callable(getattr(tracer, "count_rays", None)):
        return HOOK
    # a wrapper's steps run in its inner tracer, which the counting copy does not reach
    if isinstance(tracer, Wrapper) or set(steps_overridden(tracer)) & set(OWN_LOOP):
        return None
    return INSTRUMENTED


def counting_copy(tracer: Tracer) -> Any:
    """A copy of ``tracer`` whose class counts its rays (in ``type(copy).counts``)."""
    cls = type(tracer)
    namespace: dict[str, Any] = {"__slots__": (), "counts": Counter()}
    counting = type(f"Counting{cls.__name__}", (CountingMixin, cls), namespace)
    counted = copy.copy(tracer)
    counted.__class__ = counting
    return counted


def count_rays(variant: Any, camera: Any, world: Any, settings: Any) -> dict[str, Any] | None:
    """Every ray one render of ``variant`` casts, by kind, with ``total`` and ``method``;
    None when the variant cannot be counted."""
    method = counting_method(variant)
    if method is None:
        return None
    if method == HOOK:
        found: Mapping[str, int] = variant.tracer.count_rays(camera, world, settings)
        counts = {str(kind): int(n) for kind, n in found.items()}
    else:
        tracer = counting_copy(variant.tracer)
        tracer.render(camera, world, settings)
        seen = tracer.counts
        counts = {
            "camera": seen["camera"],
            "shadow": seen["shadow"],
            "secondary": seen["traced"] - seen["camera"],
        }
    return {**counts, "total": sum(counts.values()), "method": method}
