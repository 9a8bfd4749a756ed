"""Counting every ray a render casts: camera rays, shadow rays, reflected and refracted rays.

Two ways, tried in order:

1. The variant's own hook, ``Variant.count_rays(camera, world, settings) -> {kind: count}``
   (see ``variants.registry``): it renders once with counting on and returns counts by kind,
   e.g. ``{"camera": ..., "shadow": ..., "secondary": ...}``.
2. For a variant that renders through the reference's own ``render`` (``naive`` and variants
   that only replace shapes or values), the harness instruments the reference for one render:
   chapter 7's ``color_at`` called by the camera is a camera ray, called by chapter 11's
   ``reflected_color``/``refracted_color`` a secondary ray, and every chapter 8
   ``is_shadowed`` a shadow ray.

Other variants cannot be counted and their rows say so. Counting runs in a separate render,
never in a timed one.
"""

from __future__ import annotations

import importlib
from collections import Counter
from collections.abc import Callable, Mapping
from typing import Any

# by path: ``raytracer.camera`` and ``raytracer.world`` are also the package's functions
reference_camera: Any = importlib.import_module("raytracer.camera")
reference_world: Any = importlib.import_module("raytracer.world")

HOOK = "variant hook count_rays"
INSTRUMENTED = "the reference instrumented (render goes through raytracer.world)"


def counting_method(variant: Any) -> str | None:
    """How rays of ``variant`` can be counted, or None."""
    if callable(getattr(variant, "count_rays", None)):
        return HOOK
    if variant.api.get("render") is reference_camera.render:
        return INSTRUMENTED
    return None


def _count_reference(render: Callable[[], Any]) -> dict[str, int]:
    counts: Counter[str] = Counter()
    color_at = reference_world.color_at
    is_shadowed = reference_world.is_shadowed

    def camera_color_at(w: Any, r: Any, remaining: int = 5) -> Any:
        counts["camera"] += 1
        return color_at(w, r, remaining)

    def secondary_color_at(w: Any, r: Any, remaining: int = 5) -> Any:
        counts["secondary"] += 1
        return color_at(w, r, remaining)

    def counted_is_shadowed(w: Any, p: Any, *args: Any, **kwargs: Any) -> Any:
        counts["shadow"] += 1
        return is_shadowed(w, p, *args, **kwargs)

    saved = (reference_camera.color_at, reference_world.color_at, reference_world.is_shadowed)
    reference_camera.color_at = camera_color_at
    reference_world.color_at = secondary_color_at
    reference_world.is_shadowed = counted_is_shadowed
    try:
        render()
    finally:
        reference_camera.color_at, reference_world.color_at, reference_world.is_shadowed = saved
    return {kind: counts[kind] for kind in ("camera", "shadow", "secondary")}


def count_rays(variant: Any, camera: Any, world: Any, settings: Any) -> dict[str, Any] | None:
    """Every ray one render of ``variant`` casts, by kind, with ``total`` and ``method``;
    None when the variant cannot be counted."""
    method = counting_method(variant)
    if method is None:
        return None
    if method == HOOK:
        found: Mapping[str, int] = variant.count_rays(camera, world, settings)
        counts = {str(kind): int(n) for kind, n in found.items()}
    else:
        counts = _count_reference(lambda: variant.api["render"](camera, world, settings))
    return {**counts, "total": sum(counts.values()), "method": method}
