"""The report's "Pass size against time" section (``harness.sections.pass_size.measure``'s entry of
a run): a table of batch size, passes, render time and memory per ``max_mb``, where the knee is, the
big point against the issue's memory target, and lines for the terminal."""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Picture, Table
from harness.engine import figures
from harness.sections.pass_size.measure import BIG_MAX_MB, SECTION

Run = Mapping[str, Any]
MIB = 1 << 20
KNEE = 1.10  # the knee: the smallest max_mb within 10% of the fastest time
TARGET_EXTRA = 200 * MIB  # the target: within max_mb + 200 MiB of the baseline


def entries(run: Run) -> list[Mapping[str, Any]]:
    return [e for e in run.get("series", []) if e["section"] == SECTION]


def has_section(run: Run) -> bool:
    return bool(entries(run))


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured this section, if any."""
    return next((run for run in reversed(runs) if has_section(run)), None)


def sweep(entry: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """The points of the ``max_mb`` sweep that rendered, smallest ``max_mb`` first."""
    found = [
        p for p in entry.get("points", [])
        if not p.get("big") and p.get("render") and "error" not in p
    ]  # fmt: skip
    return sorted(found, key=lambda p: p["max_mb"])


def big_point(entry: Mapping[str, Any]) -> Mapping[str, Any] | None:
    return next((p for p in entry.get("points", []) if p.get("big")), None)


def knee(points: list[Mapping[str, Any]]) -> Mapping[str, Any] | None:
    """The smallest ``max_mb`` whose median time is within ``KNEE`` of the fastest."""
    if not points:
        return None
    fastest = min(p["render_median"] for p in points)
    return next(p for p in points if p["render_median"] <= fastest * KNEE)


def _mib(value: float | None) -> str:
    return "-" if value is None else f"{value / MIB:.1f} MiB"


def _picture(point: Mapping[str, Any]) -> str:
    found = point.get("difference")
    if not found:
        return "(the first)"
    if found["max_abs"] == 0:
        return "identical"
    return f"max {found['max_abs']:.2g} vs `{found['against']}`"


def table(entry: Mapping[str, Any]) -> Table:
    body: list[list[str]] = []
    for p in entry.get("points", []):
        if p.get("big"):
            continue
        if "error" in p or not p.get("render"):
            body.append([str(p["max_mb"]), "failed: " + str(p.get("error"))[:160], *["-"] * 6])
            continue
        walls = p["render"]
        body.append(
            [
                str(p["max_mb"]),
                f"{p.get('batch') or 0:,}",
                str(p.get("passes", "-")),
                f"{figures.seconds_text(p['render_median'])} "
                f"({figures.seconds_text(min(walls))}-{figures.seconds_text(max(walls))}, "
                f"{len(walls)})",
                f"{statistics.median(p.get('cpu') or [0.0]):.2f}",
                _mib(p.get("tracemalloc_peak")),
                _mib(p.get("rss_growth")),
                _picture(p),
            ]
        )
    header = [
        "max_mb", "rays per batch", "passes", "render (median, range, renders)", "CPU (cores)",
        "tracemalloc peak", "RSS growth (canvas included)", "picture",
    ]  # fmt: skip
    return Table(header, body, right={0, 1, 2, 3, 4, 5, 6})


def big_text(point: Mapping[str, Any]) -> str:
    """The big point against the target, in a sentence."""
    w, h = point["size"]
    where = f"{w}x{h}, {point['samples']} samples per pixel, `{point['variant']}`"
    if point.get("skipped"):
        return f"The memory point ({where}) was skipped: {point['skipped']}."
    if "error" in point or not point.get("render"):
        return f"The memory point ({where}) failed: {str(point.get('error'))[:200]}."
    rss = point.get("rss_growth")
    limit = BIG_MAX_MB * MIB + TARGET_EXTRA
    verdict = (
        "-"
        if rss is None
        else f"{'within' if rss <= limit else 'over'} the target of {BIG_MAX_MB} + 200 MiB"
    )
    return (
        f"Memory at {where}: one render of {figures.seconds_text(point['render_median'])} "
        f"(CPU share {statistics.median(point.get('cpu') or [0.0]):.2f}, tracemalloc on), "
        f"{point.get('passes', '-')} passes of {point.get('batch') or 0:,} rays; the resident "
        f"set grew by {_mib(rss)} over the process's baseline of "
        f"{_mib(point.get('rss_before'))} ({point.get('rss_method', 'VmHWM')}; the float32 "
        f"canvas is {_mib(point.get('canvas'))} of it): {verdict}. tracemalloc's peak (the "
        f"arrays the passes allocate, the canvas made before it): "
        f"{_mib(point.get('tracemalloc_peak'))}."
    )


def blocks(run: Run, plot: Any, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The report's section for ``run`` (nothing if it has none); ``plot``: the plot's path
    relative to the results folder, or None; ``context``: the machine and run line."""
    found = entries(run)
    if not found:
        return []
    entry = found[-1]
    out: list[Block] = [Heading(2, "Pass size against time"), Para(context)]
    if entry.get("status") != "ok":
        out.append(Para(f"`{entry['name']}` was not run: {entry.get('error', '')}"))
        return out
    w, h = entry["size"]
    points = sweep(entry)
    bend = knee(points)
    s = run["settings"]
    threads = s.get("threads") or "all the process may use"
    out.append(
        Para(
            f"`wavefront` traces its rays in passes whose arrays stay under `max_mb` MiB: the "
            f"scene {entry['scene']} at {w}x{h}, {entry['samples']} sample(s) per pixel, "
            f"depth {s['depth']}, through `{entry['name']}` with each `max_mb`, one fresh "
            f"process per value after a warm-up render; CPUs: {threads}. Render: "
            f"`render_into` of a prepared frame, median of up to {s['repeat']} renders. "
            f"tracemalloc peak: one more render under `tracemalloc` (NumPy's arrays included, "
            f"the canvas made before it not). RSS growth: the resident set's high-water mark "
            f"over the timed renders less the resident set before them. Timings on a shared "
            f"machine are noisy: medians, with the CPU share each render got."
        )
    )
    if plot is not None:
        out.append(Picture(str(plot), "render time and memory against max_mb"))
    out.append(table(entry))
    if bend is not None:
        fastest = min(points, key=lambda p: p["render_median"])
        out.append(
            Para(
                f"The knee: `max_mb={bend['max_mb']}` ({bend.get('batch') or 0:,} rays per "
                f"batch) is within {round((KNEE - 1) * 100)}% of the fastest time "
                f"({figures.seconds_text(fastest['render_median'])} at "
                f"`max_mb={fastest['max_mb']}`): smaller passes pay NumPy's cost per call on "
                f"too few rays; bigger ones only take more memory (and leave the caches)."
            )
        )
    big = big_point(entry)
    if big is not None:
        out.append(Para(big_text(big)))
    return out


def console_lines(run: Run) -> list[str]:
    """The section in a few terminal lines."""
    lines: list[str] = []
    for entry in entries(run):
        if entry.get("status") != "ok":
            lines.append(f"{SECTION} {entry['name']}: not run: {entry.get('error', '')[:80]}")
            continue
        for p in sweep(entry):
            lines.append(
                f"{SECTION} max_mb={p['max_mb']:<5} {p.get('batch') or 0:>9,} rays/batch "
                f"{figures.seconds_text(p['render_median']):>9} "
                f"tracemalloc {_mib(p.get('tracemalloc_peak')):>11} "
                f"RSS +{_mib(p.get('rss_growth')):>11}"
            )
        big = big_point(entry)
        if big is not None:
            lines.append(f"{SECTION}: {big_text(big)}")
    return lines
