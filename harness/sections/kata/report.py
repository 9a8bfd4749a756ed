"""The report's "Chapter progress" section (``harness.sections.kata.measure``'s figures of a run):
the scenarios passed per chapter and variant."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Table

Run = Mapping[str, Any]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that ran the chapter progress, if any."""
    return next((run for run in reversed(runs) if (run.get("kata") or {}).get("summary")), None)


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """Scenarios passed per chapter and variant."""
    kata = run.get("kata")
    if not kata or not kata.get("summary"):
        return []
    variants = list(kata.get("variants") or [])
    chapters: dict[Any, dict[str, Mapping[str, Any]]] = {}
    titles: dict[Any, str] = {}
    for entry in kata["summary"]:
        chapters.setdefault(entry["chapter"], {})[entry["variant"]] = entry
        titles[entry["chapter"]] = entry["title"]
    body = []
    for chapter, by_variant in chapters.items():
        cells = []
        for variant in variants:
            e = by_variant.get(variant)
            if e is None:
                cells.append("-")
                continue
            total = e["passed"] + e["failed"] + e["undefined"] + e.get("skipped", 0)
            total += e.get("todo", 0)  # stubs not written yet (rtc new)
            mark = "✓" if e["passed"] == total else "✗"
            cells.append(f"{mark} {e['passed']}/{total}")
        body.append([f"{chapter or '?'} {titles[chapter]}", *cells])
    return [
        Heading(2, "Chapter progress"),
        Para(
            "Scenarios passed per chapter and variant (`rtc kata --variant all`), "
            "at the commit of the latest run."
        ),
        Table(["chapter", *[f"`{v}`" for v in variants]], body),
    ]


def console_lines(run: Run) -> list[str]:
    return []
