"""Which of the reference's leaf classes an object is, for the variants that number the
shapes and patterns they compile or vectorize (``numba``, ``wavefront``): each keeps its own
table of (class, kind), most derived first; the lookup and the "inherits the reference's
methods unchanged" check are here, once."""

from __future__ import annotations

from collections.abc import Sequence

SHAPE_METHODS = ("local_intersect", "local_normal_at")
PATTERN_METHODS = ("local_pattern_at",)


def unchanged(cls: type, base: type, methods: Sequence[str]) -> bool:
    """True when ``cls`` inherits every one of ``methods`` from ``base`` unchanged."""
    return all(getattr(cls, name) is getattr(base, name) for name in methods)


def reference_kind(
    obj: object, table: Sequence[tuple[type, int]], methods: Sequence[str]
) -> tuple[int | None, type | None]:
    """``(kind, None)`` when ``obj`` is an instance of a class of ``table`` and keeps its
    ``methods``; ``(None, cls)`` when it is one but overrides them; ``(None, None)`` when it
    is none of them."""
    for cls, kind in table:
        if isinstance(obj, cls):
            return (kind, None) if unchanged(type(obj), cls, methods) else (None, cls)
    return None, None
