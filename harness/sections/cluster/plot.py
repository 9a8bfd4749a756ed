"""The cluster section's plot: start-up and throughput of each configuration."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.sections.cluster import report as cluster_report


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Throughput (million rays per second) of each configuration of the cluster section
    as a bar, split into what it took to start (left, seconds) and to render (right)."""
    found = cluster_report.entries(run)
    points = [p for p in found[-1].get("points", []) if cluster_report.usable(p)] if found else []
    if not points:
        return None
    names = [p["variant"] for p in points][::-1]
    figure, (start, speed) = plt.subplots(
        1, 2, figsize=(8.5, 0.6 * len(points) + 1.6), sharey=True, width_ratios=(1, 2)
    )
    colors = ["C1" if name.startswith("dask") else "C0" for name in names]
    starts = [p["startup"] for p in points][::-1]
    rates = [p["rays_per_second"] / 1e6 for p in points][::-1]
    start.barh(names, starts, color=colors)
    start.set_xlabel("start-up (s), first render included")
    start.invert_xaxis()
    speed.barh(names, rates, color=colors)
    speed.set_xlabel("million rays per second (median render)")
    for y, rate in enumerate(rates):
        speed.annotate(f"{rate:.2f}", (rate, y), xytext=(3, 0), textcoords="offset points",
                       va="center", fontsize=8)  # fmt: skip
    entry = found[-1]
    w, h = entry["size"]
    figure.suptitle(
        f"On a cluster: {entry['scene']} at {w}x{h}, {entry.get('samples')} spp\n{caption(run)}",
        fontsize=9,
    )
    for axes in (start, speed):
        axes.grid(True, axis="x", alpha=0.3)
    return save(figure, path)
