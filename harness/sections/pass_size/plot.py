"""The pass-size section's plot: the wavefront variant's time and memory against max_mb."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.sections.pass_size import report as psr


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The wavefront variant's render time (left) and peak memory (right: tracemalloc's
    peak, the resident set's growth) against ``max_mb`` (log scale), the knee marked."""
    found = psr.entries(run)
    points = psr.sweep(found[-1]) if found else []
    if not points:
        return None
    figure, axes = plt.subplots(figsize=(7.5, 5))
    xs = [p["max_mb"] for p in points]
    axes.plot(xs, [p["render_median"] for p in points], marker="o", color="C0", label="render time")
    bend = psr.knee(points)
    if bend is not None:
        axes.axvline(
            bend["max_mb"], color="gray", linestyle=":", label=f"knee: max_mb={bend['max_mb']}"
        )
    axes.set_xscale("log", base=2)
    axes.set_xticks(xs, [str(x) for x in xs])
    axes.set_xlabel("max_mb (MiB per pass)")
    axes.set_ylabel("render time (s), median")
    axes.set_ylim(bottom=0)
    memory = axes.twinx()
    for key, label, color in (
        ("tracemalloc_peak", "tracemalloc peak", "C1"),
        ("rss_growth", "RSS growth (canvas included)", "C2"),
    ):
        ys = [(p.get(key) or 0) / psr.MIB for p in points]
        memory.plot(xs, ys, marker="s", linestyle="--", color=color, label=label)
    memory.plot(xs, xs, linestyle=":", color="C3", label="max_mb")
    memory.set_ylabel("MiB")
    memory.set_yscale("log", base=2)
    handles = axes.get_legend_handles_labels()
    more = memory.get_legend_handles_labels()
    axes.legend(handles[0] + more[0], handles[1] + more[1], fontsize=7, loc="upper center")
    entry = found[-1]
    w, h = entry["size"]
    axes.set_title(
        f"Pass size against time and memory: {entry['name']}, {entry['scene']} at {w}x{h}, "
        f"{entry['samples']} spp\n{caption(run)}",
        fontsize=9,
    )
    axes.grid(True, which="both", alpha=0.3)
    return save(figure, path)
