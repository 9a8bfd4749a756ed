"""The kata runner: a folder of ``.feature`` files through pytest, results per scenario.

``run_kata(path)`` writes a throw-away test module that calls ``scenarios(path)``, runs it
in-process with the step plugin and a small collector, and returns one ``ScenarioResult``
per scenario and variant. ``progress_table`` and ``as_json`` present them chapter by chapter.
Any folder works: the project's ``features/`` or the book's own download.
"""

from __future__ import annotations

import json
import re
import sys
import tempfile
import uuid
from collections import Counter
from collections.abc import Generator, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import pytest
from pytest_bdd.exceptions import StepDefinitionNotFoundError
from pytest_bdd.scenario import scenario_wrapper_template_registry

from raytracer.api import CHAPTER_TITLES
from steps.chapters import chapter_of
from steps.plugin import UNDEFINED, failed_step, select_variants

PROJECT_FEATURES = Path(__file__).resolve().parent.parent / "features"
STATUSES = ("passed", "failed", UNDEFINED)


@dataclass(frozen=True)
class ScenarioResult:
    """One scenario run against one variant.

    status: passed, failed, undefined or skipped; message: the first failure's message;
    line: the scenario's line; step_line: the failing step's line, if a step failed.
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


@dataclass
class KataRun:
    """Everything one kata run found: results, collection errors, pytest's exit code."""

    path: str
    variants: list[str]
    results: list[ScenarioResult] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    pytest_exit_code: int = 0
    warnings: list[str] = field(default_factory=list)

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


class _Collector:
    """A pytest plugin that keeps one ``ScenarioResult`` per scenario test."""

    def __init__(self, chapters: Iterable[int]) -> None:
        self.chapters = set(chapters)
        self.results: list[ScenarioResult] = []
        self.errors: list[str] = []

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
    )


def run_kata(
    path: str | Path = PROJECT_FEATURES,
    variants: Sequence[str] = ("naive",),
    chapters: Iterable[int] = (),
    verbose: bool = False,
) -> KataRun:
    """Run every scenario under ``path`` (a folder or one ``.feature`` file) for each variant.

    variants: variant names (``all`` = every available one); an unknown one raises
    ``LookupError`` before anything runs. chapters: only these chapters (empty = all).
    verbose: show pytest's own output (``-v``); otherwise pytest stays silent.
    """
    folder = Path(path).resolve()
    if not folder.exists():
        raise FileNotFoundError(f"no such feature file or folder: {folder}")
    selected, _ = select_variants(list(variants))
    names = [variant.name for variant in selected]
    _forget_parsed_features(folder)
    collector = _Collector(chapters)
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
    return KataRun(str(folder), names, collector.results, collector.errors, exit_code, warnings)


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
    from pytest_bdd import feature as bdd_feature

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
    """One row per chapter and variant: counts and the first failure, in book order."""
    rows: list[dict[str, Any]] = []
    chapters = sorted({result.chapter for result in run.results}, key=_chapter_key)
    for chapter in chapters:
        for variant in run.variants:
            mine = [r for r in run.results if r.chapter == chapter and r.variant == variant]
            if not mine:
                continue
            counts = Counter(result.status for result in mine)
            first = next((r for r in mine if r.status in ("failed", UNDEFINED)), None)
            rows.append(
                {
                    "chapter": chapter,
                    "title": CHAPTER_TITLES.get(chapter, "") if chapter else "(no chapter)",
                    "variant": variant,
                    **{status: counts.get(status, 0) for status in (*STATUSES, "skipped")},
                    "first_failure": None if first is None else _failure(first),
                }
            )
    return rows


def _failure(result: ScenarioResult) -> dict[str, Any]:
    line = result.step_line or result.line
    return {
        "where": f"{_relative(result.file)}:{line}",
        "scenario": result.title,
        "status": result.status,
        "message": result.message,
    }


def progress_table(run: KataRun) -> str:
    """The progress table: chapter by chapter, variant by variant."""
    lines = [f"{'chapter':<40} {'variant':<12} {'passed':>6} {'failed':>6} {'undefined':>9}"]
    for row in summary(run):
        label = f"{row['chapter'] or '?':>2} {row['title']}"
        lines.append(
            f"{label:<40} {row['variant']:<12} {row['passed']:>6} {row['failed']:>6}"
            f" {row[UNDEFINED]:>9}"
        )
        failure = row["first_failure"]
        if failure:
            first_line = failure["message"].strip().splitlines()[:3]
            lines.append(
                f"     first {failure['status']}: {failure['where']}  {failure['scenario']}"
            )
            lines += [f"       {text}" for text in first_line]
    totals = Counter(result.status for result in run.results)
    lines.append(
        f"{'total':<40} {', '.join(run.variants):<12} {totals['passed']:>6}"
        f" {totals['failed']:>6} {totals[UNDEFINED]:>9}"
    )
    for error in run.errors:
        lines.append(
            f"collection error: {error.strip().splitlines()[-1] if error.strip() else error}"
        )
    if not run.results and not run.errors:
        lines.append(f"no scenarios found under {run.path}")
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
    }
    return json.dumps(data, indent=2, ensure_ascii=False)
