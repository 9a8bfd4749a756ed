"""``rtc kata --next``: the one scenario to make pass next, in the book's order.

The first scenario of a kata run that does not pass, taking chapters in order, within a
chapter the book's feature files in the order the book introduces them, then the lines of
each file. ``next_report`` shows its feature file and line, its steps (the one that stopped
marked), and what went wrong: the failed check with both values, the book function not
written yet with its chapter and where its stub is, or the step nobody understands.
"""

from __future__ import annotations

import json
import re
from dataclasses import asdict
from pathlib import Path
from typing import Any

from steps.chapters import CHAPTER_BY_FILE_NAME
from steps.kata import TODO, UNDEFINED, KataRun, ScenarioResult, summary
from variants.learner import chapter_label

_FILE_RANK = {name: rank for rank, name in enumerate(CHAPTER_BY_FILE_NAME)}
_BLOCK_START = re.compile(
    r"^\s*(?:@|Scenario(?: Outline| Template)?:|Example:|Rule:|Background:|Feature:)"
)
_DOC_STRING = re.compile(r'^\s*(?:"""|```)')


def book_order(result: ScenarioResult) -> tuple[int, int, str, int]:
    """Sort key: chapter, the file's place in the book, the file, the scenario's line."""
    stem = Path(result.file).stem
    rank = _FILE_RANK.get(stem, _FILE_RANK.get(stem.replace("_", "-"), len(_FILE_RANK)))
    chapter = result.chapter if result.chapter is not None else 10_000
    return chapter, rank, result.file, result.line


def next_scenario(run: KataRun, variant: str) -> ScenarioResult | None:
    """The first result of ``variant`` in book order that neither passed nor was skipped."""
    pending = [
        r for r in run.results if r.variant == variant and r.status not in ("passed", "skipped")
    ]
    return min(pending, key=book_order, default=None)


def scenario_text(file: str, line: int) -> list[tuple[int, str]]:
    """The scenario starting at ``line`` of ``file``: (line number, text) up to the next
    scenario, rule or tag line, without trailing blank lines. Empty if unreadable."""
    try:
        lines = Path(file).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return []
    block: list[tuple[int, str]] = []
    in_doc_string = False
    for number in range(line, len(lines) + 1):
        text = lines[number - 1]
        if number > line and not in_doc_string and _BLOCK_START.match(text):
            break
        if _DOC_STRING.match(text):
            in_doc_string = not in_doc_string
        block.append((number, text))
    while block and not block[-1][1].strip():
        block.pop()
    return block


def _relative(file: str) -> str:
    try:
        return str(Path(file).resolve().relative_to(Path.cwd()))
    except ValueError:
        return file


def problem(result: ScenarioResult) -> str:
    """The message without the exception's type and without a repeat of the step."""
    message = result.message
    kind, colon, rest = message.partition(": ")
    if colon and re.fullmatch(r"[A-Za-z_][\w.]*", kind):
        message = rest
    step = result.step.split(" ", 1)[1] if " " in result.step else result.step
    if step and message.startswith(step):
        message = message[len(step) :].removeprefix(":").lstrip(" ").removeprefix("\n")
    return message.rstrip()


def what_went_wrong(result: ScenarioResult) -> list[str]:
    """Lines that say why ``result`` did not pass and where to look."""
    text = problem(result).splitlines() or [""]
    if result.status == TODO:
        lines = [f"to do: {text[0]}", *text[1:]]
        if result.origin:
            lines.append(f"  write it in {_relative_origin(result.origin)}")
        return lines
    if result.status == UNDEFINED:
        return [f"undefined: {text[0]}", *text[1:]]
    lines = [f"{result.status}: {result.step}" if result.step else f"{result.status}:"]
    lines += [f"  {line.strip()}" if line.strip() else "" for line in text]
    if result.origin:
        lines.append(f"  raised at {_relative_origin(result.origin)}")
    return lines


def _relative_origin(origin: str) -> str:
    """``file:line in f()`` with the file relative to the working folder when inside it."""
    location, _, function = origin.partition(" in ")
    file, _, line = location.rpartition(":")
    shown = f"{_relative(file)}:{line}" if file else location
    return f"{shown} in {function}" if function else shown


def chapter_progress(run: KataRun, variant: str, chapter: int | None) -> str:
    """``"chapter 1, Tuples, Points, and Vectors: 3 passed, 1 failed, 18 to do"``."""
    for row in summary(run):
        if row["variant"] == variant and row["chapter"] == chapter:
            counts = [
                f"{row[status]} {'to do' if status == TODO else status}"
                for status in ("passed", "failed", TODO, UNDEFINED)
                if row[status] or status == "passed"
            ]
            return f"{chapter_label(chapter)}: {', '.join(counts)}"
    return chapter_label(chapter)


def next_report(run: KataRun, variant: str) -> str:
    """The next scenario to make pass for ``variant``, or a line saying none is left."""
    lines = [f"collection error: {error.strip()}" for error in run.errors]
    result = next_scenario(run, variant)
    if result is None:
        count = sum(1 for r in run.results if r.variant == variant)
        if count:
            lines.append(f"{variant}: all {count} scenarios pass; nothing left to do here")
        else:
            lines.append(f"no scenarios found under {run.path}")
        return "\n".join(lines)
    lines.append(f"next for {variant}: {chapter_progress(run, variant, result.chapter)}")
    lines.append("")
    lines.append(f"{_relative(result.file)}:{result.line}")
    for number, text in scenario_text(result.file, result.line):
        marker = "→" if number == result.step_line else " "
        lines.append(f"{marker} {number:>4} {text}")
    lines.append("")
    lines += what_went_wrong(result)
    return "\n".join(lines)


def next_json(run: KataRun, variant: str) -> str:
    """The same as JSON: ``done``, the result and its scenario's lines."""
    result = next_scenario(run, variant)
    data: dict[str, Any] = {
        "variant": variant,
        "done": result is None and bool(run.results) and not run.errors,
        "errors": run.errors,
        "next": None,
    }
    if result is not None:
        data["next"] = {
            **asdict(result),
            "scenario_text": [text for _, text in scenario_text(result.file, result.line)],
        }
    return json.dumps(data, indent=2, ensure_ascii=False)
