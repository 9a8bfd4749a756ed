"""The reference tracer as a variant: the book as written, naive on purpose (chapters 1-16)."""

from __future__ import annotations

from raytracer.api import naive_api
from variants.registry import Variant, check_options, reject_inner

NAME = "naive"


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The reference; it takes no options and wraps nothing."""
    reject_inner(NAME, inner)
    check_options(NAME, options)
    return Variant(
        name=NAME,
        summary="the reference: the book's tracer, immutable values, inverses recomputed on use",
        api=naive_api(),
    )
