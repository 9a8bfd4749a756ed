"""What can go wrong in a step, as exception types a report can tell apart.

- ``UndefinedStep``: the step library does not understand the step (reported "undefined").
- ``NotImplementedByVariant``: the step calls a book name the variant does not provide
  (also "undefined", with the variant's name).
- ``CheckFailed`` (an ``AssertionError``): a Then step's check does not hold ("failed").
- ``EvaluationError``: an expression that the evaluator refuses or cannot resolve ("failed").
- ``StepError``: the tracer raised while a step ran ("failed"); the original is chained.
- ``NotWrittenYet``: the tracer raised ``NotImplementedError``, e.g. a learner's stub from
  ``rtc new`` ("to do"); the original is chained.
"""

from __future__ import annotations

import traceback

from pytest_bdd.exceptions import StepDefinitionNotFoundError

from raytracer.api import BOOK_API, book_name


class UndefinedStep(StepDefinitionNotFoundError):
    """A step text that none of the step library's forms understands."""


class NotImplementedByVariant(UndefinedStep):
    """A step that calls a name the variant under test does not provide."""

    def __init__(self, name: str, variant: str, message: str) -> None:
        super().__init__(message)
        self.name = name
        self.variant = variant


class CheckFailed(AssertionError):
    """A Then step whose check does not hold; the message names the step and both sides."""


class EvaluationError(Exception):
    """An expression the evaluator cannot evaluate: unknown name, forbidden syntax."""


class NotAllowed(EvaluationError):
    """Syntax outside the book's notation (lambdas, comprehensions, dunder attributes...)."""


class StepError(Exception):
    """The tracer raised an exception while a step ran."""


class NotWrittenYet(Exception):
    """The tracer raised ``NotImplementedError``: code not written yet ("to do", not failed).

    name: the book name not written (the error's ``name``, else the function that raised,
    if it is a book name), or None; chapter: its chapter, or None.
    """

    def __init__(self, message: str, name: str | None = None, chapter: int | None = None):
        super().__init__(message)
        self.name = name
        self.chapter = chapter

    @classmethod
    def from_error(cls, step: str, error: NotImplementedError) -> NotWrittenYet:
        """The "to do" for ``error`` raised while ``step`` ran."""
        name = getattr(error, "name", None)
        frame = raised_at(error)
        if not isinstance(name, str) and frame is not None:
            name = book_name(frame[2]) if book_name(frame[2]) in BOOK_API else None
        chapter = getattr(error, "chapter", None)
        if not isinstance(chapter, int):
            chapter = BOOK_API.get(name) if name else None
        text = str(error) or (
            f"{frame[2]}() raises NotImplementedError" if frame else "NotImplementedError"
        )
        return cls(f"{step}: {text}", name, chapter)


def raised_at(error: BaseException) -> tuple[str, int, str] | None:
    """Where ``error`` was raised: the innermost frame's file, line and function."""
    frames = traceback.extract_tb(error.__traceback__) if error.__traceback__ else []
    if not frames:
        return None
    last = frames[-1]
    return last.filename, last.lineno or 0, last.name
