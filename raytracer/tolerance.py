"""How close is close enough (chapter 1), and the offset that keeps surfaces from shadowing
themselves (chapter 8, "acne").

``EPSILON`` is the book's constant. Comparisons (``equal``) always use it. The offsets the
tracer applies (``over_point``, ``under_point``, the plane's parallel-ray test, and later the
cube and cylinder tests) read ``epsilon()`` instead, so a render can choose a different offset
with ``using_epsilon`` (``RenderSettings.epsilon``, ``rtc render --epsilon 0.001``).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

# 0.0001 rather than a smaller value: several of the book's expected values are printed with
# four decimals, so comparisons need this tolerance to pass.
EPSILON = 0.0001

_offset: ContextVar[float] = ContextVar("raytracer_epsilon", default=EPSILON)


def epsilon() -> float:
    """The offset epsilon in effect: ``EPSILON`` unless ``using_epsilon`` overrides it."""
    return _offset.get()


@contextmanager
def using_epsilon(value: float) -> Iterator[float]:
    """Use ``value`` as the offset epsilon inside the ``with`` block (per thread/context).

    value: a positive, finite offset, e.g. 0.001 for large scenes.
    """
    value = float(value)
    if not (value > 0.0 and value < float("inf")):
        raise ValueError(f"using_epsilon({value!r}): epsilon must be a positive, finite number")
    token = _offset.set(value)
    try:
        yield value
    finally:
        _offset.reset(token)
