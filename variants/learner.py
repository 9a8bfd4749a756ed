"""A learner's own tracer as a variant: the stubs ``rtc new`` writes, and the factory helper.

``rtc new NAME`` scaffolds a small package whose ``tracer.py`` defines every book name
(``raytracer.api.BOOK_API``) as a stub, and whose factory calls ``learner_variant``.

- A function not written yet raises ``NotImplementedYet(name)``: a ``NotImplementedError``
  that names the book function and its chapter. The kata runner reports a scenario that
  reaches one as "to do", not as a failure.
- A constant not written yet (``EPSILON``, ``identity_matrix``) is ``not_written_yet(name)``:
  a placeholder that raises ``NotImplementedYet`` on any use (arithmetic, comparison,
  indexing, attributes), so a scenario touching it is "to do" too.
- ``is_stub`` tells a stub (still as generated) from the learner's own code, so reports can
  count what is written.
"""

from __future__ import annotations

import contextlib
import dis
import functools
import inspect
from collections.abc import Mapping
from pathlib import Path
from types import ModuleType
from typing import Any, NoReturn

from raytracer.api import BOOK_API, CHAPTER_TITLES
from raytracer.canvas import Canvas, to_byte
from variants.registry import Variant, check_options, reject_inner

CONSTANTS = frozenset({"EPSILON", "identity_matrix"})  # the book names that are values
# The instructions a generated stub's body compiles to: ``raise NotImplementedYet("x")``.
_STUB_OPCODES = frozenset(
    {"RESUME", "NOP", "CACHE", "PUSH_NULL", "LOAD_GLOBAL", "LOAD_CONST", "PRECALL", "CALL"}
    | {"CALL_FUNCTION", "KW_NAMES", "RAISE_VARARGS"}
)


def chapter_label(chapter: int | None) -> str:
    """``"chapter 1, Tuples, Points, and Vectors"`` (or ``"no chapter"``)."""
    if chapter is None:
        return "no chapter"
    title = CHAPTER_TITLES.get(chapter)
    return f"chapter {chapter}, {title}" if title else f"chapter {chapter}"


def spelled(name: str) -> str:
    """A book name as the scenarios write it: ``tuple()`` for a function, ``EPSILON``."""
    return name if name in CONSTANTS else f"{name}()"


class NotImplementedYet(NotImplementedError):
    """A book function (or constant) the learner has not written yet ("to do" in the kata).

    name: the book's name (``tuple``, ``identity_matrix``); chapter: the chapter that
    introduces it (looked up in ``BOOK_API`` when not given).
    """

    def __init__(self, name: str, chapter: int | None = None) -> None:
        self.name = name
        self.chapter = chapter if chapter is not None else BOOK_API.get(name)
        super().__init__(
            f"the book's {spelled(name)} is not written yet ({chapter_label(self.chapter)})"
        )


class NotWrittenYet:
    """A book constant the learner has not written yet: using it in any way raises
    ``NotImplementedYet``, so the scenario that needs it shows as "to do".

    Replace it with the value (``EPSILON = 0.0001``, ``identity_matrix = matrix(...)``).
    """

    __slots__ = ("chapter", "name")

    def __init__(self, name: str, chapter: int | None = None) -> None:
        self.name = name
        self.chapter = chapter if chapter is not None else BOOK_API.get(name)

    def _refuse(self, *_: object) -> NoReturn:
        raise NotImplementedYet(self.name, self.chapter)

    def __getattr__(self, attribute: str) -> Any:
        if attribute.startswith("_"):  # Python's own protocols (copy, pickle) look these up
            raise AttributeError(attribute)
        self._refuse()

    def __repr__(self) -> str:
        return f"<{self.name}: not written yet ({chapter_label(self.chapter)})>"

    __hash__ = object.__hash__
    __eq__ = __ne__ = __lt__ = __le__ = __gt__ = __ge__ = _refuse
    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = _refuse
    __truediv__ = __rtruediv__ = __floordiv__ = __rfloordiv__ = __mod__ = __rmod__ = _refuse
    __pow__ = __rpow__ = __matmul__ = __rmatmul__ = _refuse
    __neg__ = __pos__ = __abs__ = __invert__ = __round__ = _refuse
    __float__ = __int__ = __index__ = __bool__ = __len__ = __iter__ = _refuse
    __getitem__ = __contains__ = __call__ = _refuse


def not_written_yet(name: str) -> NotWrittenYet:
    """The placeholder for a book constant not written yet (its chapter from ``BOOK_API``)."""
    return NotWrittenYet(name)


def is_stub(value: object) -> bool:
    """True for a placeholder constant, and for a function whose whole body is
    ``raise NotImplementedYet(...)`` (a stub as ``rtc new`` wrote it)."""
    if isinstance(value, NotWrittenYet):
        return True
    code = getattr(value, "__code__", None)
    if code is None or set(code.co_names) != {"NotImplementedYet"}:
        return False
    opcodes = {instruction.opname for instruction in dis.get_instructions(code)}
    return "RAISE_VARARGS" in opcodes and opcodes <= _STUB_OPCODES


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
