"""The scaling section's plot: time against pixel count, throughput against workers and
threads."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document import summary
from harness.document.plotting import caption, plt, save
from harness.document.runinfo import part, rows
from harness.engine import figures


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The scaling section's two panels, side by side where the run has both: time against
    pixel count (``_pixels_axes``) and throughput against workers or threads
    (``_threads_axes``)."""
    sizes = [e for e in part(run, "scaling", "sizes") if e["status"] == "ok"]
    sizes = [e for e in sizes if any("wall" in p for p in e["points"])]
    threads = [r for r in rows(run, "scaling") if r["status"] == "ok"]
    groups: dict[str, list[Mapping[str, Any]]] = {}
    for row in threads:
        groups.setdefault(row["group"], []).append(row)
    groups = {k: v for k, v in groups.items() if any(r["count"] == 1 for r in v)}
    panels = int(bool(sizes)) + int(bool(groups))
    if not panels:
        return None
    figure, found = plt.subplots(1, panels, figsize=(7.5 * panels, 5), squeeze=False)
    axes = list(found[0])
    if sizes:
        _pixels_axes(run, sizes, axes.pop(0))
    if groups:
        _threads_axes(run, groups, axes.pop(0))
    return save(figure, path)


def _pixels_axes(run: Mapping[str, Any], entries: list[Mapping[str, Any]], axes: Any) -> None:
    """Render time against pixel count, one line per variant (log-log)."""
    any_busy = False
    for entry in entries:
        measured = [p for p in entry["points"] if "wall" in p]
        xs = [p["size"][0] * p["size"][1] for p in measured]
        ys = [p["wall"] for p in measured]
        (line,) = axes.plot(xs, ys, marker="o", label=entry["name"])
        for x, y, p in zip(xs, ys, measured, strict=True):
            if summary.point_busy(entry, p):  # hollow, drawn over the filled marker
                any_busy = True
                axes.plot([x], [y], marker="o", markersize=8, color=line.get_color(),
                          markerfacecolor="white")  # fmt: skip
    if any_busy:
        note = f"hollow: busy (CPU under {figures.BUSY_SHARE:.0%} of the cores asked)"
        axes.plot([], [], marker="o", linestyle="none", color="gray", markerfacecolor="white",
                  label=note)  # fmt: skip
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("pixels")
    axes.set_ylabel("render time (s)")
    axes.set_title(
        f"Time against pixel count (points over the budget skipped)\n{caption(run)}", fontsize=9
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)


def _threads_axes(
    run: Mapping[str, Any], groups: dict[str, list[Mapping[str, Any]]], axes: Any
) -> None:
    """Throughput relative to one worker or thread against the count, one line per variant
    option, with the linear ideal dotted (absolute MRay/s are in the report's table)."""
    counts = sorted({r["count"] for members in groups.values() for r in members})
    axes.plot(counts, counts, linestyle=":", color="gray", label="linear (ideal)")
    any_busy = False
    for label, members in groups.items():
        members = sorted(members, key=lambda r: r["count"])
        one = figures.mrays(next(r for r in members if r["count"] == 1))
        xs = [r["count"] for r in members]
        ys = [figures.mrays(r) / one for r in members]
        (line,) = axes.plot(xs, ys, marker="o", label=f"{label}: {one:.3g} MRay/s with 1")
        busy = [figures.is_busy(r) for r in members]
        any_busy = any_busy or any(busy)
        for x, y, hollow in zip(xs, ys, busy, strict=True):
            if hollow:  # drawn over the filled marker
                axes.plot([x], [y], marker="o", markersize=8, color=line.get_color(),
                          markerfacecolor="white")  # fmt: skip
                axes.annotate("busy", (x, y), textcoords="offset points", xytext=(6, -10),
                              fontsize=7, color=line.get_color())  # fmt: skip
    if any_busy:
        note = f"hollow: busy (CPU under {figures.BUSY_SHARE:.0%} of the count)"
        axes.plot([], [], marker="o", linestyle="none", color="gray", markerfacecolor="white",
                  label=note)  # fmt: skip
    axes.set_xlabel("workers / threads")
    axes.set_ylabel("throughput relative to 1 worker / thread")
    axes.set_xticks(counts)
    axes.set_title(
        f"Throughput against parallelism (sizes may differ: per-pixel ratios)\n{caption(run)}",
        fontsize=9,
    )
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=7)
