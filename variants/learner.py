"""A learner's own tracer as a variant: the factory helper.

``rtc new NAME`` scaffolds a small package whose ``tracer.py`` defines every book name
(``raytracer.api.BOOK_API``) as a stub (``variants.stubs``: its package imports
``NotImplementedYet`` and ``not_written_yet`` from here), and whose factory calls
``learner_variant``.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
from collections.abc import Mapping
from pathlib import Path
from types import ModuleType
from typing import Any

from raytracer.api import BOOK_API
from raytracer.canvas import Canvas, to_byte
from variants.registry import Variant, check_options, reject_inner
from variants.stubs import (
    CONSTANTS,
    NotImplementedYet,
    NotWrittenYet,
    chapter_label,
    is_stub,
    not_written_yet,
    spelled,
)

# a learner's package (``rtc new``) and the command line import the stubs' names from here
__all__ = [
    "CONSTANTS",
    "NotImplementedYet",
    "NotWrittenYet",
    "chapter_label",
    "is_stub",
    "learner_variant",
    "module_api",
    "not_written_yet",
    "python_names",
    "rgb8_of",
    "spelled",
    "stub_names",
]


def python_names(book_name: str) -> tuple[str, str]:
    """Where a module may define a book name: ``tuple`` or ``tuple_`` (the latter avoids
    shadowing Python's own ``tuple``)."""
    return book_name, f"{book_name}_"


def module_api(module: ModuleType) -> dict[str, Any]:
    """The book names a module defines (stubs included), in chapter order."""
    api: dict[str, Any] = {}
    for name in BOOK_API:
        for python_name in python_names(name):
            if hasattr(module, python_name):
                api[name] = getattr(module, python_name)
                break
    return api


def stub_names(api: Mapping[str, Any]) -> list[str]:
    """The book names in ``api`` that are still stubs, in chapter order."""
    return [name for name in BOOK_API if name in api and is_stub(api[name])]


def learner_variant(
    name: str,
    module: ModuleType,
    inner: Variant | None = None,
    options: Mapping[str, str] | None = None,
) -> Variant:
    """The variant for a learner's tracer module: every book name it defines (stubs too).

    ``overrides`` lists the names the learner has written (not the stubs); a name the module
    does not define at all is left out, so a scenario that calls it is "undefined".
    """
    reject_inner(name, inner)
    check_options(name, options or {})
    api = module_api(module)
    stubs = set(stub_names(api))
    written = frozenset(api) - stubs
    source = inspect.getsourcefile(module) or getattr(module, "__file__", None) or module.__name__
    summary = f"your own tracer ({_shown(source)}): {len(written)} of {len(BOOK_API)} book names"
    summary += " written"
    missing = len(BOOK_API) - len(api)
    if missing:
        summary += f", {missing} not defined"
    if "render" in written and "pixel_at" in api:
        api["render"] = _readable_render(api["render"], api["pixel_at"])
    return Variant(name=name, summary=summary, api=api, overrides=written, usage="none")


def _readable_render(render: Any, pixel_at: Any) -> Any:
    """The learner's ``render``, whose canvas (a type of the learner's own) also gets a
    ``to_rgb8()`` read through the learner's ``pixel_at``, so ``rtc render`` and ``rtc
    bench`` can write and compare its image (``groundwork.images.rgb8`` uses ``to_rgb8``)."""

    @functools.wraps(render)
    def render_readably(*args: Any, **kwargs: Any) -> Any:
        canvas = render(*args, **kwargs)
        if not isinstance(canvas, Canvas) and not hasattr(canvas, "to_rgb8"):
            with contextlib.suppress(AttributeError, TypeError):  # slotted or frozen: as it is
                canvas.to_rgb8 = functools.partial(rgb8_of, canvas, pixel_at)
        return canvas

    return render_readably


def rgb8_of(canvas: Any, pixel_at: Any) -> bytes:
    """Row-major RGB bytes of any canvas, read with ``pixel_at(canvas, x, y)`` (chapter 2),
    each channel clamped and scaled to 0..255 as in the book's PPM."""
    out = bytearray()
    for y in range(canvas.height):
        for x in range(canvas.width):
            pixel = pixel_at(canvas, x, y)
            out += bytes((to_byte(pixel.red), to_byte(pixel.green), to_byte(pixel.blue)))
    return bytes(out)


def _shown(path: str) -> str:
    """A path relative to the working folder when it is inside it."""
    try:
        return str(Path(path).resolve().relative_to(Path.cwd()))
    except ValueError:
        return path
