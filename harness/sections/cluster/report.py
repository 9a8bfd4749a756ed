"""The report's "On a cluster" section (``harness.sections.cluster.measure``'s entry of a run):
throughput of numba on 1 and 2 threads and of 1 and 2 local Dask workers, the cluster's start-up and
its cost per tile, and lines for the terminal."""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Picture, Table
from harness.engine import figures
from harness.sections.cluster.measure import SECTION

Run = Mapping[str, Any]
TARGET = 1.7  # the issue's: two local workers at >= 1.7x the throughput of one


def entries(run: Run) -> list[Mapping[str, Any]]:
    return [e for e in run.get("series", []) if e["section"] == SECTION]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured this section, if any."""
    return next((run for run in reversed(runs) if entries(run)), None)


def usable(point: Mapping[str, Any]) -> bool:
    return "error" not in point and bool(point.get("render"))


def _point(entry: Mapping[str, Any], name: str) -> Mapping[str, Any] | None:
    return next((p for p in entry.get("points", []) if p["variant"] == name and usable(p)), None)


def _cpu(point: Mapping[str, Any], cores: int) -> str:
    share = statistics.median(point.get("cpu") or [0.0])
    return f"{share:.2f} of {figures.cores_asked(point['variant'], cores)}"


def _picture(point: Mapping[str, Any]) -> str:
    found = point.get("difference")
    if not found:
        return "(the first)"
    return "identical" if found["max_abs"] == 0 else f"max {found['max_abs']:.2g} vs the first"


def speedups(entry: Mapping[str, Any]) -> dict[str, float]:
    """Throughput ratios measured side by side in the entry: ``workers`` (dask 2 over 1),
    ``threads`` (numba 2 over 1), ``dask-vs-numba`` (dask on 2 workers over numba on 2
    threads)."""
    pairs = {
        "workers": ("dask[workers=2]:numba[threads=1]", "dask[workers=1]:numba[threads=1]"),
        "threads": ("numba[threads=2]", "numba[threads=1]"),
        "dask-vs-numba": ("dask[workers=2]:numba[threads=1]", "numba[threads=2]"),
    }
    out: dict[str, float] = {}
    for key, (fast, slow) in pairs.items():
        a, b = _point(entry, fast), _point(entry, slow)
        if a is not None and b is not None and a["render_median"] > 0:
            out[key] = b["render_median"] / a["render_median"]
    return out


def per_tile(entry: Mapping[str, Any]) -> float | None:
    """Seconds a tile costs on one Dask worker beyond tracing it: (one worker's render less
    one-thread numba's) / tiles."""
    dask = _point(entry, "dask[workers=1]:numba[threads=1]")
    numba = _point(entry, "numba[threads=1]")
    if dask is None or numba is None or not dask.get("tiles"):
        return None
    return float((dask["render_median"] - numba["render_median"]) / dask["tiles"])


def table(entry: Mapping[str, Any], cores: int) -> Table:
    body: list[list[str]] = []
    for p in entry.get("points", []):
        if not usable(p):
            body.append([f"`{p['variant']}`", "failed: " + str(p.get("error"))[:160], *["-"] * 5])
            continue
        walls = p["render"]
        body.append(
            [
                f"`{p['variant']}`",
                figures.seconds_text(p["startup"]),
                f"{figures.seconds_text(p['render_median'])} "
                f"({figures.seconds_text(min(walls))}-{figures.seconds_text(max(walls))}, "
                f"{len(walls)})",
                _cpu(p, cores),
                f"{p['rays_per_second'] / 1e6:.3g} M",
                str(p.get("tiles", "-")),
                _picture(p),
            ]
        )
    header = [
        "configuration", "start-up (first render included)", "render (median, range, renders)",
        "CPU (cores)", "rays/s", "tiles", "picture",
    ]  # fmt: skip
    return Table(header, body, right={1, 2, 3, 4, 5})


def verdict(entry: Mapping[str, Any]) -> str:
    """The issue's target, in a sentence."""
    ratio = speedups(entry).get("workers")
    if ratio is None:
        return "The target (2 workers at >= 1.7x one) could not be judged: a render failed."
    met = "meets" if ratio >= TARGET else "misses"
    return f"2 local workers give {ratio:.2f}x the throughput of 1: this {met} the target of 1.7x."


def blocks(run: Run, plot: Any, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The report's section for ``run`` (nothing if it has none); ``plot``: the plot's path
    relative to the results folder, or None; ``context``: the machine and run line."""
    found = entries(run)
    if not found:
        return []
    entry = found[-1]
    out: list[Block] = [Heading(2, "On a cluster"), Para(context)]
    if entry.get("status") != "ok":
        out.append(Para(f"The section was not run: {entry.get('error', '')}"))
        return out
    w, h = entry["size"]
    cores = int(run["machine"].get("cores_available") or 1)
    out.append(
        Para(
            f"The scene {entry['scene']} at {w}x{h}, {entry.get('samples')} samples per pixel "
            f"(chosen so that one thread takes about 6 s), through numba on 1 and 2 threads "
            f"and through `dask` on a LocalCluster of 1 and 2 single-threaded worker "
            f"processes, each worker tracing its tiles with `numba[threads=1]`; one fresh "
            f"process per configuration. Start-up: loading the variant, starting the cluster "
            f"and loading numba on its workers, and a first render at 16x12 (the kernels "
            f"loaded from their cache). Render: median of {run['settings']['repeat']} renders "
            f"in that session. CPU: this process and its descendants (the workers), per wall "
            f"second, of the cores the configuration asks for."
        )
    )
    if plot is not None:
        out.append(Picture(str(plot), "start-up and throughput of each configuration"))
    out.append(table(entry, cores))
    ratios = speedups(entry)
    lines = [verdict(entry)]
    if "threads" in ratios:
        lines.append(f"numba's second thread gives {ratios['threads']:.2f}x.")
    if "dask-vs-numba" in ratios:
        lines.append(
            f"Two Dask workers render at {ratios['dask-vs-numba']:.2f}x numba's two threads' "
            "throughput in one process."
        )
    tile = per_tile(entry)
    one = _point(entry, "dask[workers=1]:numba[threads=1]")
    numba = _point(entry, "numba[threads=1]")
    if tile is not None and one is not None and numba is not None:
        side = f"{one.get('tile')}x{one.get('tile')}"
        per = (
            f"{figures.seconds_text(tile)} per {side} tile ({one['tiles']} tiles: one "
            "worker's render less numba's own on one thread)"
            if tile > 0
            else f"no cost per {side} tile that the renders tell apart from their noise (one "
            f"worker's {one['tiles']} tiles took {figures.seconds_text(-tile * one['tiles'])} "
            "less than numba's own render on one thread)"
        )
        lines.append(
            f"What the cluster costs: {figures.seconds_text(one['startup'] - numba['startup'])} "
            f"more start-up than numba alone (its LocalCluster and loading numba in the worker: "
            f"{figures.seconds_text(one.get('session', 0.0))}), and {per}."
        )
    out.append(Para(" ".join(lines)))
    return out


def console_lines(run: Run) -> list[str]:
    """The section in a few terminal lines."""
    lines: list[str] = []
    cores = int(run.get("machine", {}).get("cores_available") or 1)
    for entry in entries(run):
        if entry.get("status") != "ok":
            lines.append(f"{SECTION}: not run: {entry.get('error', '')[:80]}")
            continue
        for p in entry.get("points", []):
            if not usable(p):
                lines.append(f"{SECTION} {p['variant']:<34} failed: {str(p.get('error'))[:60]}")
                continue
            lines.append(
                f"{SECTION} {p['variant']:<34} start-up {figures.seconds_text(p['startup']):>9} "
                f"render {figures.seconds_text(p['render_median']):>9} CPU {_cpu(p, cores)}"
            )
        lines.append(f"{SECTION}: {verdict(entry)}")
    return lines
