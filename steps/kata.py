"""The kata runner: a folder of ``.feature`` files through pytest, results per scenario.

``run_kata(path)`` writes a throw-away test module that calls ``scenarios(path)``, runs it
in-process with the step plugin and a small collector, and returns one ``ScenarioResult``
per scenario and variant: passed, failed, to do (the tracer raised ``NotImplementedError``,
e.g. a stub from ``rtc new``) or undefined. ``progress_table`` and ``as_json`` present them
chapter by chapter; ``next_report`` shows the first scenario not passing, in book order.
Any folder works: the project's ``features/`` or the book's own download.
"""

from __future__ import annotations

import json
import re
import sys
import tempfile
import textwrap
import uuid
from collections import Counter
from collections.abc import Generator, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Protocol

import pytest
from pytest_bdd import feature as bdd_feature
from pytest_bdd.exceptions import StepDefinitionNotFoundError
from pytest_bdd.scenario import scenario_wrapper_template_registry

from raytracer.api import BOOK_API, CHAPTER_TITLES, naive_api
from steps.chapters import chapter_of
from steps.plugin import TODO, UNDEFINED, failed_step, select_variants
from variants.learner import chapter_label, spelled, stub_names
from variants.registry import Variant

PROJECT_FEATURES = Path(__file__).resolve().parent.parent / "features"
STATUSES = ("passed", "failed", TODO, UNDEFINED)


@dataclass(frozen=True)
class ScenarioResult:
    """One scenario run against one variant.

    status: passed, failed, todo, undefined or skipped; message: the first failure's
    message; line: the scenario's line; step_line, step: the failing step's line and text;
    missing: for a to do, the book name not written yet (if known); origin: for a to do or
    an exception from the tracer, where it was raised (``file:line in function()``).
    """

    variant: str
    chapter: int | None
    feature: str
    file: str
    line: int
    title: str
    status: str
    message: str = ""
    step_line: int | None = None
    test: str = ""
    step: str = ""
    missing: str | None = None
    origin: str = ""


@dataclass
class KataRun:
    """Everything one kata run found: results, collection errors, pytest's exit code."""

    path: str
    variants: list[str]
    results: list[ScenarioResult] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    pytest_exit_code: int = 0
    warnings: list[str] = field(default_factory=list)
    own: dict[str, list[str]] = field(default_factory=dict)  # variant -> book names it overrides
    stubs: dict[str, list[str]] = field(default_factory=dict)  # variant -> names still stubs
    absent: dict[str, list[str]] = field(default_factory=dict)  # variant -> names not defined

    @property
    def ok(self) -> bool:
        """True when something ran and every scenario passed (or was skipped)."""
        return (
            bool(self.results)
            and not self.errors
            and self.pytest_exit_code in (0, 1)
            and all(result.status in ("passed", "skipped") for result in self.results)
        )


def _templated_scenario(item: pytest.Item) -> Any:
    function = getattr(item, "function", None)
    try:
        return scenario_wrapper_template_registry.get(function) if function else None
    except TypeError:
        return None


def item_chapter(item: pytest.Item) -> int | None:
    """The chapter of a collected scenario test (tags first, then the file name)."""
    templated = _templated_scenario(item)
    if templated is None:
        return None
    tags = set(templated.tags) | set(templated.feature.tags)
    return chapter_of(tags, templated.feature.filename)


class KataProgress(Protocol):
    """What ``run_kata`` reports its progress to (``groundwork.progress.Progress``): the number of
    scenario tests once they are collected, then each one as it ends."""

    def set_total(self, total: int) -> None: ...

    def __call__(self, steps: int) -> None: ...


class _Collector:
    """A pytest plugin that keeps one ``ScenarioResult`` per scenario test."""

    def __init__(
        self, chapters: Iterable[int], verbose: bool = False, progress: KataProgress | None = None
    ) -> None:
        self.chapters = set(chapters)
        self.verbose = verbose
        self.progress = progress
        self.results: list[ScenarioResult] = []
        self.errors: list[str] = []

    def pytest_runtest_logfinish(self, nodeid: str, location: tuple[str, int, str]) -> None:
        if self.progress is not None:
            self.progress(1)

    def pytest_collection_finish(self, session: pytest.Session) -> None:
        if self.progress is not None:
            self.progress.set_total(len(session.items))
        # The results come from the exceptions themselves; pytest's own long tracebacks
        # (it parses every source file of every frame) cost ~0.15 s per failing scenario,
        # which adds up for a learner whose every scenario is still "to do". Collection
        # errors, reported before this, keep pytest's short style (``_last_error`` reads it).
        if not self.verbose:
            session.config.option.tbstyle = "native"

    def pytest_collection_modifyitems(
        self, config: pytest.Config, items: list[pytest.Item]
    ) -> None:
        if not self.chapters:
            return
        keep = [item for item in items if item_chapter(item) in self.chapters]
        dropped = [item for item in items if item not in keep]
        if dropped:
            config.hook.pytest_deselected(items=dropped)
            items[:] = keep

    def pytest_collectreport(self, report: pytest.CollectReport) -> None:
        if report.failed:
            self.errors.append(_last_error(report.longreprtext))

    @pytest.hookimpl(wrapper=True)
    def pytest_runtest_makereport(
        self, item: pytest.Item, call: pytest.CallInfo[None]
    ) -> Generator[None, pytest.TestReport, pytest.TestReport]:
        report = yield
        if call.when == "call" or (call.when == "setup" and not report.passed):
            self.results.append(_result(item, call, report))
        return report


def _last_error(traceback_text: str) -> str:
    """The final ``E   ...`` block of a pytest traceback, as one line."""
    blocks: list[list[str]] = [[]]
    for line in traceback_text.splitlines():
        if line.startswith("E "):
            blocks[-1].append(line[1:].strip())
        elif blocks[-1]:
            blocks.append([])
    found = [block for block in blocks if block]
    return "; ".join(found[-1]) if found else traceback_text.strip()


def _result(
    item: pytest.Item, call: pytest.CallInfo[None], report: pytest.TestReport
) -> ScenarioResult:
    properties: dict[str, Any] = dict(report.user_properties)
    templated = _templated_scenario(item)
    detail = failed_step(report)
    if report.passed:
        status = "passed"
    elif report.skipped:
        status = "skipped"
    elif detail is not None and detail["kind"] == TODO:
        status = TODO
    elif (detail is not None and detail["kind"] == UNDEFINED) or (
        call.excinfo is not None and call.excinfo.errisinstance(StepDefinitionNotFoundError)
    ):
        status = UNDEFINED
    else:
        status = "failed"
    message = ""
    if not report.passed and call.excinfo is not None:
        message = f"{call.excinfo.typename}: {call.excinfo.value}"
    callspec = getattr(item, "callspec", None)
    variant = properties.get("variant") or (callspec.params.get("variant") if callspec else "")
    return ScenarioResult(
        variant=str(variant),
        chapter=properties.get("chapter", item_chapter(item)),
        feature=properties.get("feature", templated.feature.name if templated else ""),
        file=properties.get("feature_file", templated.feature.filename if templated else ""),
        line=properties.get("scenario_line", templated.line_number if templated else 0),
        title=properties.get("scenario", templated.name if templated else item.name),
        status=status,
        message=message,
        step_line=detail["line"] if detail else None,
        test=item.name,
        step=detail["step"] if detail else "",
        missing=detail.get("missing") if detail else None,
        origin=detail.get("origin", "") if detail else "",
    )


def _code(value: Any) -> Any:
    """A bound method's function (a new bound method is made on every lookup); else
    ``value``."""
    return getattr(value, "__func__", value)


def own_names(variant: Variant) -> list[str]:
    """The book names whose code is the variant's own: those it declares in ``overrides``,
    and any whose callable is not the reference's (so an undeclared override still counts);
    a stub not written yet (``variants.learner.is_stub``) does not count. Bound methods
    (the pipeline's names) compare by their function, whatever tracer they are bound to."""
    reference = naive_api()
    differing = {
        name
        for name, value in variant.api.items()
        if name in BOOK_API
        and (name not in reference or _code(value) is not _code(reference[name]))
    }
    own = (set(variant.overrides) & set(BOOK_API)) | differing
    return sorted(own - set(stub_names(variant.api)))


def run_kata(
    path: str | Path = PROJECT_FEATURES,
    variants: Sequence[str] = ("naive",),
    chapters: Iterable[int] = (),
    verbose: bool = False,
    progress: KataProgress | None = None,
) -> KataRun:
    """Run every scenario under ``path`` (a folder or one ``.feature`` file) for each variant.

    variants: variant names (``all`` = every available one); an unknown one raises
    ``LookupError`` before anything runs. chapters: only these chapters (empty = all).
    verbose: show pytest's own output (``-v``); otherwise pytest stays silent. progress:
    told how many scenario tests there are (a scenario per variant) and each one's end.
    """
    folder = Path(path).resolve()
    if not folder.exists():
        raise FileNotFoundError(f"no such feature file or folder: {folder}")
    selected, _ = select_variants(list(variants))
    names = [variant.name for variant in selected]
    _forget_parsed_features(folder)
    collector = _Collector(chapters, verbose, progress)
    with tempfile.TemporaryDirectory(prefix="rtc-kata-") as scratch:
        # A fresh module name per run: pytest would reuse an imported module of the same name.
        module = Path(scratch) / f"test_kata_{uuid.uuid4().hex}.py"
        module.write_text(
            f'"""Generated by rtc kata."""\nfrom pytest_bdd import scenarios\n\n'
            f"scenarios({str(folder)!r})\n",
            encoding="utf-8",
        )
        ini = Path(scratch) / "pytest.ini"
        ini.write_text(
            "[pytest]\nfilterwarnings =\n    ignore::pytest.PytestUnknownMarkWarning\n"
            "    ignore::pytest.PytestAssertRewriteWarning\n",
            encoding="utf-8",
        )
        arguments = [str(module), "-c", str(ini), "--rootdir", scratch]
        arguments += ["-p", "steps.plugin", "-p", "no:cacheprovider", "--import-mode=importlib"]
        arguments += ["-v"] if verbose else ["-p", "no:terminal"]
        for name in names:
            arguments += ["--variant", name]
        try:
            exit_code = int(pytest.main(arguments, plugins=[collector]))
        finally:
            sys.modules.pop(module.stem, None)
    warnings = duplicate_titles(folder)
    own = {variant.name: own_names(variant) for variant in selected}
    stubs = {variant.name: stub_names(variant.api) for variant in selected}
    absent = {variant.name: [n for n in BOOK_API if n not in variant.api] for variant in selected}
    return KataRun(
        str(folder),
        names,
        collector.results,
        collector.errors,
        exit_code,
        warnings,
        own,
        stubs,
        absent,
    )


SCENARIO_LINE = re.compile(r"^\s*(?:Scenario(?: Outline| Template)?|Example):\s*(?P<title>.*?)\s*$")


def duplicate_titles(path: Path) -> list[str]:
    """Scenario titles used twice in one file: pytest-bdd silently runs only one of them."""
    files = [path] if path.is_file() else sorted(path.rglob("*.feature"))
    found: list[str] = []
    for feature_file in files:
        seen: dict[str, int] = {}
        lines = feature_file.read_text(encoding="utf-8").splitlines()
        for number, line in enumerate(lines, start=1):
            match = SCENARIO_LINE.match(line)
            if not match:
                continue
            title = match["title"]
            if title in seen:
                found.append(
                    f"{_relative(str(feature_file))}:{number}: the title {title!r} is also used"
                    f" on line {seen[title]}; only one of the two scenarios runs"
                )
            seen.setdefault(title, number)
    return found


def _forget_parsed_features(folder: Path) -> None:
    """Drop pytest-bdd's cached parses of these files, so edits between runs are seen."""
    for filename in list(bdd_feature.features):
        if Path(filename).is_relative_to(folder):
            del bdd_feature.features[filename]


# ----------------------------------------------------------------------------- presenting


def _chapter_key(chapter: int | None) -> int:
    return chapter if chapter is not None else 10_000


def _relative(file: str) -> str:
    try:
        return str(Path(file).resolve().relative_to(Path.cwd()))
    except ValueError:
        return file


def summary(run: KataRun) -> list[dict[str, Any]]:
    """One row per chapter and variant, in book order: counts, the first failed (else
    undefined) scenario, and ``to_write``: the book names its to-do scenarios reached."""
    rows: list[dict[str, Any]] = []
    chapters = sorted({result.chapter for result in run.results}, key=_chapter_key)
    for chapter in chapters:
        for variant in run.variants:
            mine = [r for r in run.results if r.chapter == chapter and r.variant == variant]
            if not mine:
                continue
            counts = Counter(result.status for result in mine)
            first = next((r for r in mine if r.status == "failed"), None) or next(
                (r for r in mine if r.status == UNDEFINED), None
            )
            rows.append(
                {
                    "chapter": chapter,
                    "title": CHAPTER_TITLES.get(chapter, "") if chapter else "(no chapter)",
                    "variant": variant,
                    **chapter_code(run, variant, chapter),
                    **{status: counts.get(status, 0) for status in (*STATUSES, "skipped")},
                    "first_failure": None if first is None else _failure(first),
                    "to_write": to_write(mine),
                }
            )
    return rows


def to_write(results: Iterable[ScenarioResult]) -> list[str]:
    """The book names the to-do scenarios reached, in chapter order (unknown ones last)."""
    names = {r.missing for r in results if r.status == TODO and r.missing}
    order = list(BOOK_API)
    return sorted(
        names, key=lambda name: (order.index(name) if name in order else len(order), name)
    )


def chapter_code(run: KataRun, variant: str, chapter: int | None) -> dict[str, Any]:
    """Whose code a chapter's scenarios ran for a variant: ``code`` is ``reference`` (the
    reference itself), ``own k/n`` (the variant's own code for k of the chapter's n book
    names, listed in ``own``; the others are the reference's, stubs not written yet, listed
    in ``stubs``, or not defined) or ``inherited`` (all n are the reference's)."""
    if chapter is None or variant not in run.own:
        return {"code": "-", "own": [], "stubs": []}
    names = [name for name, introduced in BOOK_API.items() if introduced == chapter]
    own = [name for name in run.own[variant] if name in names]
    stubs = [name for name in run.stubs.get(variant, []) if name in names]
    absent = [name for name in run.absent.get(variant, []) if name in names]
    if variant == "naive":
        code = "reference"
    elif own or stubs or absent:
        code = f"own {len(own)}/{len(names)}"
    else:
        code = "inherited"
    return {"code": code, "own": own, "stubs": stubs}


CODE_LEGEND = (
    "code: whose code ran. reference = the reference tracer; own k/n = the variant's own code "
    "for k of the chapter's n book names (the others: the reference's, or stubs not written "
    "yet); inherited = all n are the reference's, so passing re-tests it. to do = the scenario "
    "reached code that raises NotImplementedError (a stub from rtc new); undefined = a step "
    "the step library cannot read, or a book name the variant does not define."
)


def _failure(result: ScenarioResult) -> dict[str, Any]:
    line = result.step_line or result.line
    return {
        "where": f"{_relative(result.file)}:{line}",
        "scenario": result.title,
        "status": result.status,
        "message": result.message,
    }


def first_unfinished(run: KataRun, variant: str) -> dict[str, Any] | None:
    """The first summary row (book order) of ``variant`` where not every scenario passed."""
    for row in summary(run):
        if row["variant"] == variant and any(row[status] for status in STATUSES[1:]):
            return row
    return None


def progress_table(run: KataRun) -> str:
    """The progress table: chapter by chapter in book order, variant by variant, with whose
    code ran; under a row its first failure (expected and actual) and what is to write."""
    width = max([len("variant"), *(len(name) for name in run.variants)])
    rows = summary(run)
    chapters = [f"{row['chapter'] or '?':>2} {row['title']}" for row in rows]
    first = max([40, *(len(label) for label in chapters)])  # the bonus chapter's long title
    header = f"{'chapter':<{first}} {'variant':<{width}} {'code':<10}"
    lines = [f"{header} {'passed':>6} {'failed':>6} {'to do':>6} {'undefined':>9}"]
    shown_chapter: object = object()
    for row, chapter in zip(rows, chapters, strict=True):
        label = chapter if row["chapter"] != shown_chapter else ""
        shown_chapter = row["chapter"]
        lines.append(
            f"{label:<{first}} {row['variant']:<{width}} {row['code']:<10} {row['passed']:>6}"
            f" {row['failed']:>6} {row[TODO]:>6} {row[UNDEFINED]:>9}"
        )
        failure = row["first_failure"]
        if failure:
            first_line = failure["message"].strip().splitlines()[:3]
            lines.append(
                f"     first {failure['status']}: {failure['where']}  {failure['scenario']}"
            )
            lines += [f"       {text}" for text in first_line]
        if row["to_write"]:
            names = ", ".join(spelled(name) for name in row["to_write"])
            lines += textwrap.wrap(
                f"to write: {names}", 100, initial_indent="     ", subsequent_indent="       "
            )
    for number, variant in enumerate(run.variants):
        totals = Counter(result.status for result in run.results if result.variant == variant)
        label = "total" if number == 0 else ""
        lines.append(
            f"{label:<{first}} {variant:<{width}} {'':<10} {totals['passed']:>6}"
            f" {totals['failed']:>6} {totals[TODO]:>6} {totals[UNDEFINED]:>9}"
        )
    for error in run.errors:
        lines.append(
            f"collection error: {error.strip().splitlines()[-1] if error.strip() else error}"
        )
    if not run.results and not run.errors:
        lines.append(f"no scenarios found under {run.path}")
    elif run.own:
        lines += textwrap.wrap(CODE_LEGEND, 100)
    for variant in run.variants:
        unfinished = first_unfinished(run, variant)
        if unfinished is not None:
            lines.append(
                f"next for {variant}: {chapter_label(unfinished['chapter'])}"
                f"  (rtc kata --variant {variant} --next)"
            )
    return "\n".join(lines)


def as_json(run: KataRun) -> str:
    """The same data as JSON: every result, the per-chapter summary, errors, ``ok``."""
    data = {
        "path": run.path,
        "variants": run.variants,
        "ok": run.ok,
        "summary": summary(run),
        "results": [asdict(result) for result in run.results],
        "errors": run.errors,
        "warnings": run.warnings,
        "own": run.own,
        "stubs": run.stubs,
    }
    return json.dumps(data, indent=2, ensure_ascii=False)
