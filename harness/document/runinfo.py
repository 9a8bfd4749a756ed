"""What a run says about itself, for every section of the report: its rows and series
entries by section, the machine and settings lines printed beside each section's figures,
and the report's folder names."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from harness.engine import figures, sharing

Run = Mapping[str, Any]
REPORT_DIR = "report"  # the plots' folder in the results folder
HEAT_SCALE_PNG = "heat-scale.png"  # the heat maps' colour bar, in REPORT_DIR


def rows(run: Run, section: str) -> list[Mapping[str, Any]]:
    """The rows of ``run`` that ``section`` measured."""
    return [r for r in run.get("rows") or [] if r["section"] == section]


def part(run: Run, section: str, name: str | None = None) -> list[Mapping[str, Any]]:
    """The series entries of ``run`` that ``section`` wrote, those of one ``part`` of it
    when named (the sweep's ground truth is part ``truth``; None: the entries of no part)."""
    found = run.get("series") or []
    return [e for e in found if e["section"] == section and e.get("part") == name]


def size_text(row: Mapping[str, Any]) -> str:
    return "x".join(str(v) for v in row["size"])


def git_text(run: Run) -> str:
    m = run["machine"]
    commit = (m.get("commit") or "unknown")[:10]
    return f"{commit}{' (dirty tree)' if m.get('dirty') else ''}"


def machine_line(run: Run) -> str:
    m = run["machine"]
    load = m.get("load_average")
    load_text = f", load average {load[0]:.2f} at start" if load else ""
    return (
        f"Machine: `{m['hostname']}`, {m['cpu_model']}, {m['cores_available']} of "
        f"{m['cpu_count']} cores{load_text}; Python {m['python']}, numpy {m.get('numpy')}, "
        f"numba {m.get('numba')}; commit {git_text(run)}; run `{run['stem']}` started "
        f"{run['started'][:19]} UTC, took {run['seconds']:.0f} s."
        + (f" **Shared machine:** {run['shared']}" if run.get("shared") else "")
    )


def context_line(run: Run) -> str:
    """The machine and run in one line, repeated beside every section's numbers."""
    m = run["machine"]
    load = m.get("load_average")
    load_text = f", load {load[0]:.1f} at start" if load else ""
    return (
        f"Measured on `{m['hostname']}` ({m['cpu_model']}, {m['cores_available']} cores"
        f"{load_text}), Python {m['python']}, numba {m.get('numba')}, commit {git_text(run)}, "
        f"run `{run['stem']}`, budget {run['settings']['budget'] or 0:g} s per row "
        f"(naive: 3x), mode {run['settings']['mode']['name']}."
        + (f" **Shared machine** ({sharing.brief(run.get('load'))})." if run.get("shared") else "")
    )


def settings_line(run: Run, section: str = "table") -> str:
    s = run["settings"]
    threads = s["threads"] or "all"
    budget = f"{s['budget']:g} s" if s["budget"] else "none"
    if section == "preset":
        scene = s.get("preset", "cpp-spheres")
        return (
            f"Settings: scene `{scene}`, requested {s['mode']['preset_size'][0]}x"
            f"{s['mode']['preset_size'][1]}, 8 samples per pixel, depth 5, "
            f"{s['mode']['side_repeat']} timed render(s) per row, budget {budget} per row, "
            f"CPUs: {threads}."
        )
    return (
        f"Settings: scene `{s['scene']['name']}`, requested {s['size'][0]}x{s['size'][1]}, "
        f"{s['samples']} sample(s) per pixel, depth {s['depth']}, seed {s['seed']}, "
        f"the {s.get('integrator', 'whitted')} integrator, "
        f"epsilon {s.get('epsilon') or 'the book default (0.0001)'}, "
        f"{s['repeat']} timed renders per row, budget {budget} per row (naive: 3x), mode "
        f"{s['mode']['name']}, CPUs: {threads}."
    )


def speedup_cell(row: Mapping[str, Any]) -> str:
    """A row's speed-up over naive, ``(per pixel)`` where the two were measured at other
    sizes."""
    found = row.get("speedup")
    if not found:
        return "-"
    mark = "" if found["basis"] == "same size" else " (per pixel)"
    return f"{figures.speedup_text(found['value'])}{mark}"


def skip_reason(points: list[Mapping[str, Any]]) -> str:
    """One reason for several skipped points: the first one's (the cheapest)."""
    reason = str(points[0]["skipped"])
    return reason if len(points) == 1 else f"{reason} (the cheapest of them)"
