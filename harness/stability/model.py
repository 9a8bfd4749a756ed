"""The stability suite's vocabulary: a case, what running it on one variant gave, and how
that is classified against the case's oracle.

Verdicts, from best to worst:

- ``exact``: the oracle's answer (floats: the exactly computed value correctly rounded; a
  picture: identical pixels; an expected error: raised, clear, naming the object);
- ``within tolerance``: off by a measured error no larger than the case's tolerance;
- ``wrong``: off by more (a lost hit, acne pixels, an error that does not say what is wrong,
  no error where one is due);
- ``non-finite``: NaN or infinity where a finite answer is due;
- ``crashed``: an exception the case did not ask for (a ZeroDivisionError deep in a render);
- ``not implemented``: the variant says in one line it has not what the case needs (a
  path integrator), before rendering: no verdict on its numerics.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

from variants.registry import Variant, parse_variant_name


class Verdict(StrEnum):
    EXACT = "exact"
    WITHIN = "within tolerance"
    WRONG = "wrong"
    NONFINITE = "non-finite"
    CRASHED = "crashed"
    UNSUPPORTED = "not implemented"


PASSING = (Verdict.EXACT, Verdict.WITHIN)


@dataclass(frozen=True)
class Outcome:
    """What one case gave on one variant.

    verdict: the classification; error: the measured error in the case's unit (None when
    there is no number, e.g. a crash); tolerance: the tolerance it was judged by (some
    depend on the variant's precision); detail: one line saying what was seen; note: a word
    or two for the table where there is no number ("lost hit", "unclear error").
    """

    verdict: Verdict
    error: float | None = None
    tolerance: float | None = None
    detail: str = ""
    note: str = ""


@dataclass
class Probe:
    """One variant under test, with what its cases share.

    size: (width, height) of the renders; cache: renders and other results reused between
    cases of this variant (the unit-scale picture for the scale cases).
    """

    variant: Variant
    size: tuple[int, int]
    cache: dict[str, Any] = field(default_factory=dict)

    @property
    def api(self) -> Mapping[str, Any]:
        return self.variant.api

    @property
    def unit_roundoff(self) -> float:
        """2**-24 for a variant computing in float32 (a ``float32`` option), else 2**-53."""
        options = dict(parse_variant_name(self.variant.name).options)
        return 2.0**-24 if "float32" in options else 2.0**-53

    def cached(self, key: str, make: Callable[[], Any]) -> Any:
        if key not in self.cache:
            self.cache[key] = make()
        return self.cache[key]


@dataclass(frozen=True)
class Case:
    """One stability case.

    id: ``group/name``, e.g. ``scale/1e-6``; title: what it does, one line; measure: what
    the error is and its unit; tolerance: the tolerance in words (numbers per result);
    check: runs the case on a probe and classifies the outcome; unit: for an error that
    counts things (pixels, rays, points), their short name for the table.
    """

    id: str
    title: str
    measure: str
    tolerance: str
    check: Callable[[Probe], Outcome] = field(repr=False, compare=False)
    unit: str = ""

    @property
    def group(self) -> str:
        return self.id.split("/", 1)[0]


def graded(error: float, tolerance: float, detail: str, *, exact: bool) -> Outcome:
    """``exact`` when ``exact`` is true, else within tolerance or wrong by ``error``;
    non-finite when the error is NaN or infinite."""
    if not math.isfinite(error):
        return Outcome(Verdict.NONFINITE, None, tolerance, detail)
    if exact:
        return Outcome(Verdict.EXACT, 0.0, tolerance, detail)
    verdict = Verdict.WITHIN if error <= tolerance else Verdict.WRONG
    return Outcome(verdict, error, tolerance, detail)


def crashed(error: BaseException) -> Outcome:
    """An exception the case did not ask for."""
    return Outcome(Verdict.CRASHED, None, None, f"{type(error).__name__}: {one_line(error)}")


def message_of(error: BaseException) -> str:
    """What an exception says: its message, or for a message carrying a traceback (a worker's
    error), the first line and the traceback's last line (the exception itself)."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    if len(lines) <= 1:
        return " ".join(str(error).split())
    return f"{lines[0]} ... {lines[-1]}"


def one_line(error: BaseException, limit: int = 160) -> str:
    """``message_of`` an exception, shortened to ``limit`` characters."""
    text = message_of(error)
    return text if len(text) <= limit else text[: limit - 3] + "..."


# exceptions that are a crash deep in the code, never the clear error a case asks for
DEEP_ERRORS = (
    ZeroDivisionError,
    ArithmeticError,
    IndexError,
    KeyError,
    AttributeError,
    TypeError,
    RecursionError,
)


def expected_error(action: Callable[[], object], names: tuple[str, ...], what: str) -> Outcome:
    """Run ``action``, which must fail with a clear error: a ``ValueError`` (or a
    ``RuntimeError`` from a worker) whose message mentions one of ``names`` (the object,
    case-insensitively). No error is wrong; an unclear one is wrong; a deep one crashed."""
    try:
        action()
    except DEEP_ERRORS as error:
        return crashed(error)
    except (ValueError, RuntimeError) as error:
        message = one_line(error, 240)
        if any(name.lower() in message_of(error).lower() for name in names):
            return Outcome(Verdict.EXACT, 0.0, None, f"{type(error).__name__}: {message}")
        return Outcome(
            Verdict.WRONG, None, None, f"unclear ({type(error).__name__}: {message}); "
            f"expected it to name {what}", "unclear error",
        )  # fmt: skip
    return Outcome(Verdict.WRONG, None, None, f"no error; expected one naming {what}", "no error")
