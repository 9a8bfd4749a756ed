"""The ``prealloc`` variant: the Go write-up's second step, replayed in Python.

On top of ``cached`` (inverses computed once per shape), the hot path stops creating
Tuple, Matrix, Ray, Intersection, Computations, Color and list objects per operation:

- points, vectors and colours are preallocated float lists, matrices flat 16-float lists
  kept per shape record (``buffers``, ``geometry``);
- results go into caller-owned buffers, ``transform_ray_into(m, ray, out)`` being the
  write-up's ``TransformRayPtr``;
- intersection lists are reused and reset to zero length (``IntersectionBuffer``);
- the shading scratch of each recursion level (computations, colours, spawned rays) is
  made once per render (``TraceContext.level``).

Every ``..._into`` function does its naive twin's arithmetic in the same order, so the
pictures are the reference's, bit for bit. Python still creates a float object per
arithmetic result; what is measured is the cost of everything else.

Paired micro-benchmarks of each change against its naive twin: see
``tests/benchmarks/test_prealloc_twins.py`` (untimed in the normal run; time them with
``.venv/bin/python -m pytest tests/benchmarks --benchmark-enable --benchmark-group-by=group``).

Modules: ``buffers`` (the reused containers), ``geometry`` (matrix and tuple arithmetic),
``records``/``patterns``/``shapes`` (flat per-render copies of the scene), ``context`` (one
render's records and scratch), ``shading`` (chapters 6-11), ``render`` (the camera and
``PixelTracer``, one per frame), ``tracer`` (``PreallocTracer``: the pipeline's steps,
converting at the boundary, and ``prepare``), ``api`` (the book's other functions). The
pixel loop is the reference ``Tracer.render_region``.
"""

from __future__ import annotations

from variants.cached import cached_api
from variants.prealloc.api import API, OVERRIDES
from variants.prealloc.tracer import PreallocTracer
from variants.registry import Variant, check_options, reject_inner, tracer_variant

NAME = "prealloc"


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The ``prealloc`` variant; it takes no options and wraps nothing (it builds on
    ``cached``: wrap it instead, e.g. ``pooled:prealloc``)."""
    reject_inner(NAME, inner)
    check_options(NAME, options)
    api, constructors = cached_api()
    return tracer_variant(
        NAME,
        "cached, plus a hot path that reuses preallocated buffers instead of making "
        "Tuple/Ray/Intersection/Color objects",
        PreallocTracer(),
        api={**api, **API},
        # besides the tracer's steps: the functions of ``api`` and cached's constructors
        overrides=OVERRIDES | constructors,
        base="cached",
    )
