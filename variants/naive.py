"""The reference tracer as a variant: the book as written, naive on purpose (chapters 1-16)."""

from __future__ import annotations

from raytracer.tracer import TRACER
from variants.registry import Variant, check_options, reject_inner, tracer_variant

NAME = "naive"


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The reference; it takes no options and wraps nothing."""
    reject_inner(NAME, inner)
    check_options(NAME, options)
    return tracer_variant(
        NAME,
        "the reference: the book's tracer, immutable values, inverses recomputed on use",
        TRACER,
    )
