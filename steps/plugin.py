"""The pytest plugin: ``--variant``, the ``variant`` and ``book`` fixtures, the catch-all steps.

- ``--variant NAME`` (repeatable, ``all`` = the project's own available variants, default
  ``naive``) picks the tracers, named in the grammar of ``variants.registry``
  (``pooled[workers=2]:cached``); every pytest-bdd scenario runs once per variant
  (``test_x[naive]``), other tests run once.
- ``book`` is a fresh namespace per scenario, bound to the variant's API.
- One catch-all step for Given/When and one for Then hand the text to ``steps.phrases``,
  which dispatches over an ordered table of forms (so no two patterns compete).
- Each scenario's feature, file, line, chapter and variant go into
  ``request.node.user_properties``; a failing step adds ``("failed_step", {...})`` with its
  line and kind (``failed``, ``undefined``, or ``todo`` when the tracer raised
  ``NotImplementedError``: a stub not written yet), so reports can group and explain.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from pathlib import Path
from typing import Any

import pytest
from pytest_bdd import given, parsers, then, when
from pytest_bdd.exceptions import StepDefinitionNotFoundError
from pytest_bdd.parser import Feature, Scenario, Step
from pytest_bdd.scenario import scenario_wrapper_template_registry

from raytracer.api import CHAPTER_TITLES
from steps import phrases
from steps.book import Book
from steps.chapters import chapter_of, chapter_tag
from steps.errors import (
    CheckFailed,
    EvaluationError,
    NotImplementedByVariant,
    NotWrittenYet,
    StepError,
    raised_at,
)
from variants.registry import Variant, load_variant, registry

VARIANTS = pytest.StashKey[list[Variant]]()
UNAVAILABLE = pytest.StashKey[list[str]]()
UNDEFINED = "undefined"
TODO = "todo"  # the tracer raised NotImplementedError (a learner's stub): not written yet


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("rtc", "The Ray Tracer Challenge workbook")
    group.addoption(
        "--variant",
        action="append",
        dest="rtc_variants",
        default=None,
        metavar="NAME",
        help="run the book's scenarios against variant NAME (repeatable; NAME, "
        "NAME[opt=value,flag] or NAME[...]:INNER, e.g. pooled:cached; 'all' = the "
        "project's own available variants; default: naive)",
    )


def select_variants(names: list[str] | None) -> tuple[list[Variant], list[str]]:
    """The variants named (``all`` = the project's own available ones with default
    options), each once by canonical name, and notes on the unavailable ones ``all`` skipped.

    names: variant names in the grammar of ``variants.registry`` (``pooled[workers=2]:cached``).
    A malformed, unknown or unavailable name raises ``LookupError`` with a clear message.
    """
    selected: dict[str, Variant] = {}
    notes: list[str] = []
    for name in names or ["naive"]:
        if name.strip() == "all":
            for entry in registry():
                if entry.variant is not None:
                    selected.setdefault(entry.variant.name, entry.variant)
                else:
                    notes.append(f"{entry.name}: {entry.reason}")
        else:
            loaded = load_variant(name)
            selected.setdefault(loaded.name, loaded)
    if not selected:
        raise LookupError("no variant is available here: " + "; ".join(notes))
    return list(selected.values()), notes


def pytest_configure(config: pytest.Config) -> None:
    for chapter, title in CHAPTER_TITLES.items():
        config.addinivalue_line("markers", f"{chapter_tag(chapter)}: chapter {chapter}, {title}")
    try:
        variants, notes = select_variants(config.getoption("rtc_variants"))
    except LookupError as error:
        raise pytest.UsageError(f"--variant: {error.args[0]}") from None
    config.stash[VARIANTS] = variants
    config.stash[UNAVAILABLE] = notes


def pytest_report_header(config: pytest.Config) -> list[str]:
    names = ", ".join(variant.name for variant in config.stash.get(VARIANTS, []))
    lines = [f"variants: {names}"]
    lines += [f"variant unavailable: {note}" for note in config.stash.get(UNAVAILABLE, [])]
    return lines


def is_scenario_test(function: Callable[..., Any] | None) -> bool:
    """True for a test function that pytest-bdd generated from a scenario."""
    try:
        return function is not None and function in scenario_wrapper_template_registry
    except TypeError:  # an unhashable callable
        return False


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    if "variant" in metafunc.fixturenames and is_scenario_test(metafunc.function):
        names = [variant.name for variant in metafunc.config.stash[VARIANTS]]
        metafunc.parametrize("variant", names, ids=names, indirect=True)


def pytest_itemcollected(item: pytest.Item) -> None:
    """A scenario's feature file name is one of its keywords: ``-k texture_mapping``
    selects that file's scenarios."""
    function = getattr(item, "function", None)
    if function is not None and is_scenario_test(function):
        template = scenario_wrapper_template_registry[function]
        item.extra_keyword_matches.add(Path(template.feature.filename).stem)


@pytest.fixture(autouse=True)
def variant(request: pytest.FixtureRequest) -> Variant:
    """The variant under test: one per ``--variant`` for scenarios, the first for others."""
    variants = request.config.stash[VARIANTS]
    name = getattr(request, "param", variants[0].name)
    return next(v for v in variants if v.name == name)


@pytest.fixture
def book(request: pytest.FixtureRequest, variant: Variant) -> Book:
    """A fresh namespace for one scenario, bound to the variant's API."""
    feature_file = dict(request.node.user_properties).get("feature_file")
    return Book(variant.api, variant.name, Path(feature_file) if feature_file else None)


@given(parsers.re(r"(?P<text>.+)"))
@when(parsers.re(r"(?P<text>.+)"))
def _given_or_when(
    book: Book, text: str, datatable: list[list[str]] | None = None, docstring: str | None = None
) -> None:
    __tracebackhide__ = True
    phrases.given_or_when(book, text, datatable, docstring)


@then(parsers.re(r"(?P<text>.+)"))
def _then(
    book: Book, text: str, datatable: list[list[str]] | None = None, docstring: str | None = None
) -> None:
    __tracebackhide__ = True
    phrases.then(book, text, datatable, docstring)


def pytest_bdd_before_scenario(
    request: pytest.FixtureRequest, feature: Feature, scenario: Scenario
) -> None:
    tags = set(scenario.tags) | set(feature.tags)
    if scenario.rule is not None:
        tags |= set(scenario.rule.tags)
    variant: Variant = request.getfixturevalue("variant")
    request.node.user_properties.extend(
        [
            ("feature", feature.name),
            ("feature_file", feature.filename),
            ("scenario", scenario.name),
            ("scenario_line", scenario.line_number),
            ("chapter", chapter_of(tags, feature.filename)),
            ("variant", variant.name),
        ]
    )


def _record_failed_step(request: pytest.FixtureRequest, step: Step, error: BaseException) -> None:
    if isinstance(error, NotWrittenYet):
        kind = TODO
    elif isinstance(error, StepDefinitionNotFoundError):
        kind = UNDEFINED
    else:
        kind = "failed"
    detail = {
        "line": step.line_number,
        "step": f"{step.keyword} {step.name}".strip(),
        "kind": kind,
        "reason": (
            f"not implemented by variant {error.variant}"
            if isinstance(error, NotImplementedByVariant)
            else ""
        ),
        "message": str(error),
    }
    if isinstance(error, NotWrittenYet):
        detail["missing"] = error.name
        detail["chapter"] = error.chapter
    cause = error.__cause__
    if isinstance(error, NotWrittenYet | StepError) and cause is not None:
        where = raised_at(cause)
        if where is not None:
            detail["origin"] = f"{where[0]}:{where[1]} in {where[2]}()"
    request.node.user_properties.append(("failed_step", detail))


def pytest_bdd_step_error(
    request: pytest.FixtureRequest,
    feature: Feature,
    scenario: Scenario,
    step: Step,
    step_func: Callable[..., Any],
    step_func_args: dict[str, Any],
    exception: Exception,
) -> None:
    _record_failed_step(request, step, exception)


def pytest_bdd_step_func_lookup_error(
    request: pytest.FixtureRequest,
    feature: Feature,
    scenario: Scenario,
    step: Step,
    exception: Exception,
) -> None:
    _record_failed_step(request, step, exception)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(
    item: pytest.Item, call: pytest.CallInfo[None]
) -> Generator[None, pytest.TestReport, pytest.TestReport]:
    """A failed check or an unreadable step is shown as the step and the message alone;
    an exception from the tracer keeps its traceback."""
    report = yield
    concise = (CheckFailed, StepDefinitionNotFoundError, EvaluationError, NotWrittenYet)
    if (
        report.failed
        and call.excinfo is not None
        and call.excinfo.errisinstance(concise)
        and item.config.getoption("tbstyle", "auto") == "auto"
    ):
        detail = failed_step(report)
        if detail is not None:
            feature_file = dict(report.user_properties).get("feature_file", "?")
            message = _without_prefix(str(call.excinfo.value), detail["step"])
            report.longrepr = f"{feature_file}:{detail['line']}: {detail['step']}\n{message}"
    return report


def _without_prefix(message: str, step: str) -> str:
    """The message without a repeat of the step text it starts with."""
    name = step.split(" ", 1)[1] if " " in step else step
    if not message.startswith(name):
        return message
    rest = message[len(name) :]
    return rest[1:] if rest.startswith("\n") else rest.removeprefix(":").lstrip()


def failed_step(report: pytest.TestReport) -> dict[str, Any] | None:
    """The ``failed_step`` record of a scenario's report, if a step failed."""
    for key, value in report.user_properties:
        if key == "failed_step":
            return value if isinstance(value, dict) else None
    return None


@pytest.hookimpl(tryfirst=True)
def pytest_report_teststatus(
    report: pytest.TestReport, config: pytest.Config
) -> tuple[str, str, str] | None:
    """An undefined step is reported as ``undefined`` (U), a step that reached code not
    written yet as ``todo`` (T), not as plain failures."""
    if report.when == "call" and report.failed:
        detail = failed_step(report)
        if detail is not None and detail["kind"] == UNDEFINED:
            return UNDEFINED, "U", "UNDEFINED"
        if detail is not None and detail["kind"] == TODO:
            return TODO, "T", "TO DO"
    return None


def pytest_terminal_summary(terminalreporter: Any) -> None:
    """List the undefined steps (pytest's failure section does not show them)."""
    reports = terminalreporter.stats.get(UNDEFINED, [])
    if not reports:
        return
    terminalreporter.section("undefined steps", sep="=", yellow=True)
    for report in reports:
        detail = failed_step(report) or {}
        feature_file = dict(report.user_properties).get("feature_file", "?")
        reason = f" ({detail['reason']})" if detail.get("reason") else ""
        terminalreporter.line(f"{report.nodeid}")
        terminalreporter.line(f"  {feature_file}:{detail.get('line', '?')}{reason}")
        terminalreporter.line(f"  {detail.get('message', '')}")
