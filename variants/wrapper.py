"""Tracers that wrap another tracer: every step is the inner tracer's, except the ones the
wrapper's class defines itself (``pooled`` defines ``render_into``: where the regions are
traced) and ``render``, which calls them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from raytracer.tracer import STEPS, Tracer, overridden_steps

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
