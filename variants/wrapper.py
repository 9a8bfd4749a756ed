"""Tracers that wrap another tracer: every step is the inner tracer's, except the ones the
wrapper's class defines itself (``pooled`` defines ``render_into``: where the regions are
traced) and ``render``, which calls them.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

from raytracer.tracer import STEPS, Progress, Region, Tracer, overridden_steps
from variants.registry import Variant, VariantError

# ``render`` stays the reference's: it calls ``render_into`` through ``self``, which a
# wrapper overrides to change where the regions are traced
FORWARDED = (*(step for step in STEPS if step != "render"), "prepared", "forget", "explain")


def _forward(name: str) -> Callable[..., Any]:
    def forwarded(self: Wrapper, *args: Any, **kwargs: Any) -> Any:
        return getattr(self.inner, name)(*args, **kwargs)

    forwarded.__name__ = name
    forwarded.__doc__ = f"The inner tracer's ``{name}``."
    forwarded.forwards = True  # type: ignore[attr-defined]
    return forwarded


class Wrapper(Tracer):
    """A tracer around ``inner``; a subclass overrides the steps it changes."""

    def __init__(self, inner: Tracer) -> None:
        super().__init__()
        self.inner = inner


for _name in FORWARDED:
    setattr(Wrapper, _name, _forward(_name))


def steps_overridden(tracer: Tracer) -> tuple[str, ...]:
    """The ``Tracer`` steps whose code differs from the reference's: a plain tracer's own
    overrides; a wrapper's, plus its inner tracer's."""
    if not isinstance(tracer, Wrapper):
        return overridden_steps(tracer)
    cls = type(tracer)
    own = [
        name
        for name in STEPS
        if getattr(cls, name) is not getattr(Tracer, name)
        and not getattr(getattr(cls, name), "forwards", False)
    ]
    inner = steps_overridden(tracer.inner)
    return tuple(name for name in STEPS if name in own or name in inner)


def recursion_limit_at_least(limit: int) -> None:
    """In a worker: the recursion limit its parent had (the scene loader raises it for a
    deeply nested scene, ``RTC_SCENE_MAX_DEPTH``), so the worker traces what the parent
    loaded; never lowered."""
    if sys.getrecursionlimit() < limit:
        sys.setrecursionlimit(limit)


class RowProgress:
    """``progress(rows)`` called as image rows finish, while regions of a ``width`` x
    ``height`` image complete in any order (a pool's or a cluster's)."""

    def __init__(self, width: int, height: int, progress: Progress | None) -> None:
        self.left_in_row = [width] * height
        self.progress = progress

    def done(self, region: Region) -> None:
        """``region`` (x0, y0, x1, y1) is written: report the rows it finished."""
        x0, y0, x1, y1 = region
        finished = 0
        for y in range(y0, y1):
            self.left_in_row[y] -= x1 - x0
            finished += self.left_in_row[y] == 0
        if self.progress is not None and finished:
            self.progress(finished)


def tracer_of(wrapper: str, inner: Variant) -> Tracer:
    """The inner variant's tracer, which a wrapper named ``wrapper`` hands regions to; a
    ``VariantError`` for a variant without one."""
    if not isinstance(inner.tracer, Tracer):
        raise VariantError(
            f"variant {wrapper!r} cannot wrap {inner.name!r}: it has no tracer (a "
            "raytracer.tracer.Tracer whose render_region the workers call); a variant that "
            "answers through its api alone can only render in one process"
        )
    return inner.tracer
