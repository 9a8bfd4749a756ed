"""The figures the project's README quotes, written by ``rtc report`` between two markers so
that they are always those of the newest run in ``results/`` (a test checks the README
against the committed runs): the optimizations step by step (the ladder), each as a factor
over naive, with the machine and the run they come from.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from groundwork.files import read_text, write_atomically
from harness.engine import figures
from harness.report import choice
from harness.sections.ladder import report as ladder_report

START = "<!-- figures: written by `rtc report` from results/runs/; do not edit -->"
END = "<!-- end of figures -->"

Run = Mapping[str, Any]


def block(runs: Sequence[Run]) -> str:
    """The text between the markers: one paragraph from the run the report's ladder shows
    (the newest whole run: ``choice.shown``)."""
    run = choice.shown("ladder", runs)
    if run is None:
        return "No run has measured the optimizations step by step yet (`rtc bench`)."
    found = ladder_report.rows(run)
    naive = next((r for r in found if r["name"] == "naive" and ladder_report._ok(r)), None)
    steps = []
    for row in found:
        factor = ladder_report.cumulative(row, found)
        if row["name"] == "naive" or factor is None:
            continue
        step = ladder_report.spelled(row["name"], found)
        steps.append(f"`{step}` {figures.speedup_text(factor)}")
    machine = run["machine"]
    busy = " (some steps did not get the cores they asked for: see the report)" if any(
        figures.is_busy(r) for r in found if ladder_report._ok(r)
    ) else ""  # fmt: skip
    head = "The reference scene, step by step, as throughput over naive's"
    if naive is not None:
        head += f" ({figures.per_pixel_text(ladder_report.per_pixel(naive))} per pixel)"
    return (
        f"{head}: {', '.join(steps)}{busy}. Measured by run `{run['stem']}` "
        f"({run['started'][:10]}, {machine.get('cpu_model') or 'a CPU'}, "
        f"{machine.get('cores_available') or machine.get('cpu_count')} cores, commit "
        f"{str(machine.get('commit') or '?')[:10]}); every figure, with its image error and "
        "allocations, is in [results/README.md](results/README.md)."
    )


def rewrite(readme: Path, runs: Sequence[Run]) -> bool:
    """Replace what lies between the markers in ``readme`` with ``block(runs)``, atomically;
    False (nothing written) when the file or its markers are missing or it is unchanged."""
    try:
        text = read_text(readme, 16 << 20)  # never a wait on a pipe, nor all of a device
    except (OSError, UnicodeDecodeError):
        return False
    start, end = text.find(START), text.find(END)
    if start < 0 or end < start:
        return False
    new = text[: start + len(START)] + "\n" + block(runs) + "\n" + text[end:]
    if new == text:
        return False
    write_atomically(readme, new)
    return True


def quoted(readme_text: str) -> str | None:
    """What ``readme_text`` holds between the markers (None: no markers)."""
    start, end = readme_text.find(START), readme_text.find(END)
    if start < 0 or end < start:
        return None
    return readme_text[start + len(START) : end].strip()
