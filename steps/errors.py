"""What can go wrong in a step, as exception types a report can tell apart.

- ``UndefinedStep``: the step library does not understand the step (reported "undefined").
- ``NotImplementedByVariant``: the step calls a book name the variant does not provide
  (also "undefined", with the variant's name).
- ``CheckFailed`` (an ``AssertionError``): a Then step's check does not hold ("failed").
- ``EvaluationError``: an expression that the evaluator refuses or cannot resolve ("failed").
- ``StepError``: the tracer raised while a step ran ("failed"); the original is chained.
"""

from __future__ import annotations

from pytest_bdd.exceptions import StepDefinitionNotFoundError


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
