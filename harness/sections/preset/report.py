"""The report's section on the C++ report's workload (``harness.sections.preset.measure``'s rows of
a run): each variant's default on ``cpp-spheres`` in MRay/s with the book's Whitted integrator,
then path-traced as the C++ report ran it (``cpp-spheres-path``), beside that report's published
figures."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Table
from harness.document.runinfo import rows, settings_line, size_text, speedup_cell
from harness.engine import figures
from harness.scenery.presets import PATH_PRESET
from harness.sections.preset.measure import SECTION

Run = Mapping[str, Any]
C_PLUS_PLUS_ANCHOR = "the C++ report reached 44.9 MRay/s on this workload, on a whole lab machine"
C_PLUS_PLUS_PUBLISHED = (
    ("C++ report, before its optimizations (published)", 0.22),
    ("C++ report, after them (published)", 44.9),
)
"""The C++ report's own table (500x500, 8 rays per pixel, 5 bounces, 8 spheres, path-traced,
on a lab machine with all its hardware threads): a citation, not a measurement here."""
PATH_ABOUT = (
    "Path-traced as the C++ report ran it: 500x500 requested, 8 rays per pixel, at most 5 "
    "bounces, the scene's sky and light (`cpp-spheres-path`). MRay/s is its definition: "
    "pixels x rays per pixel / seconds, so a row measured at a smaller size (a Python "
    "variant within the budget: see its note) compares per ray. The C++ report's published "
    "figures are cited below ours, from its lab machine, not measured here."
)


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured the workload, if any."""
    return next((run for run in reversed(runs) if rows(run, SECTION)), None)


def _body(found: Sequence[Mapping[str, Any]]) -> list[list[str]]:
    body = []
    for row in found:
        if row["status"] == "refused":
            body.append([f"`{row['name']}`", "not run", "-", "-", "-", row.get("error", "")])
            continue
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
    return body


HEADER = ["variant", "size", "median", "MRay/s", "speed-up", "note"]


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """A row per variant's default on the C++ report's workload, in MRay/s: the book's
    integrator, then path-traced beside the C++ report's published figures."""
    found = rows(run, SECTION)
    if not found:
        return []
    whitted = [r for r in found if r.get("preset", r["scene"]) != PATH_PRESET]
    path = [r for r in found if r.get("preset", r["scene"]) == PATH_PRESET]
    out: list[Block] = [Heading(2, "The C++ report's workload (cpp-spheres)"), Para(context)]
    if whitted:
        out += [
            Para(settings_line(run, "preset") + " The book's Whitted integrator. For scale: "
                 f"{C_PLUS_PLUS_ANCHOR}."),
            Table(HEADER, _body(whitted), right={2, 3, 4}),
        ]  # fmt: skip
    if path:
        cited = [[name, "500x500", "-", f"{value:g}", "-", "cited, not measured here"]
                 for name, value in C_PLUS_PLUS_PUBLISHED]  # fmt: skip
        out += [
            Heading(3, "Path-traced, as the C++ report ran it"),
            Para(PATH_ABOUT),
            Table(HEADER, [*_body(path), *cited], right={2, 3, 4}),
        ]
    return out


def console_lines(run: Run) -> list[str]:
    lines = []
    for row in rows(run, SECTION):
        if row["status"] == "ok":
            lines.append(
                f"{row['scene']:<16} {row['name']:<28} {size_text(row):>9} "
                f"{figures.seconds_text(figures.median_wall(row)):>9} {'':>14} "
                f"{figures.mrays(row):>8.3g}"
            )
    return lines
