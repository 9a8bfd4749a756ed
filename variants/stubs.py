"""The stubs of a learner's tracer (``rtc new``): what a book name not written yet is, and
how to tell one from the learner's own code.

- A function not written yet raises ``NotImplementedYet(name)``: a ``NotImplementedError``
  that names the book function and its chapter. The kata runner reports a scenario that
  reaches one as "to do", not as a failure.
- A constant not written yet (``EPSILON``, ``identity_matrix``) is ``not_written_yet(name)``:
  a placeholder that raises ``NotImplementedYet`` on any use (arithmetic, comparison,
  indexing, attributes), so a scenario touching it is "to do" too.
- ``is_stub`` tells a stub (still as generated) from the learner's own code, so reports can
  count what is written and the registry builds a learner's world without a stub.
"""

from __future__ import annotations

import dis
from typing import Any, NoReturn

from raytracer.api import BOOK_API, CHAPTER_TITLES

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
