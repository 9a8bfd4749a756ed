"""The report's section on the C++ report's workload (``harness.sections.preset.measure``'s rows of
a run): each variant's default on ``cpp-spheres`` in MRay/s, beside the C++ report's published
figure."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Table
from harness.document.runinfo import rows, settings_line, size_text, speedup_cell
from harness.engine import figures
from harness.sections.preset.measure import SECTION

Run = Mapping[str, Any]
C_PLUS_PLUS_ANCHOR = "the C++ report reached 44.9 MRay/s on this workload, on a whole lab machine"


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured the workload, if any."""
    return next((run for run in reversed(runs) if rows(run, SECTION)), None)


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """A row per variant's default on the C++ report's workload, in MRay/s."""
    found = rows(run, SECTION)
    if not found:
        return []
    body = []
    for row in found:
        if row["status"] != "ok":
            body.append([f"`{row['name']}`", "failed", row.get("error", "")[:120], "-", "-", "-"])
            continue
        note = row["budget_note"] if row.get("reduced") else ""
        body.append(
            [
                f"`{row['name']}`",
                size_text(row),
                figures.seconds_text(figures.median_wall(row)),
                f"{figures.mrays(row):.3g}",
                speedup_cell(row),
                note,
            ]
        )
    return [
        Heading(2, "The C++ report's workload (cpp-spheres)"),
        Para(context),
        Para(settings_line(run, "preset") + f" For scale: {C_PLUS_PLUS_ANCHOR}."),
        Table(["variant", "size", "median", "MRay/s", "speed-up", "note"], body, right={2, 3, 4}),
    ]


def console_lines(run: Run) -> list[str]:
    lines = []
    for row in rows(run, SECTION):
        if row["status"] == "ok":
            lines.append(
                f"cpp-spheres {row['name']:<32} {size_text(row):>9} "
                f"{figures.seconds_text(figures.median_wall(row)):>9} {'':>14} "
                f"{figures.mrays(row):>8.3g}"
            )
    return lines
