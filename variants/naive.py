"""The reference tracer as a variant: the book as written, naive on purpose (chapters 1-16)."""

from __future__ import annotations

from raytracer.api import naive_api
from variants.registry import Variant


def variant() -> Variant:
    return Variant(
        name="naive",
        summary="the reference: the book's tracer, immutable values, inverses recomputed on use",
        api=naive_api(),
    )
