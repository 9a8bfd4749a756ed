"""The light-samples section's plot: soft shadows' error against time, the Pareto front
circled."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.sections.light_samples import report as lsr


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Soft shadows: RMSE against render time, one line per light sampling (cells, jitter)
    through its samples per pixel, the Pareto front circled (log-log)."""
    entries = [(e, lsr.measured(e)) for e in lsr.entries(run)]
    entries = [(e, points) for e, points in entries if points]
    if not entries:
        return None
    on_front = lsr.front(run)
    figure, axes = plt.subplots(figsize=(7.5, 5))
    front_points: list[tuple[float, float]] = []
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    cell_counts = sorted({int(e.get("cells", 0)) for e, _ in entries})
    for entry, points in entries:
        xs = [p["wall"] for p in points]
        ys = [max(p["error"]["rmse"], 1e-7) for p in points]
        jittered = bool(entry.get("jitter"))
        color = palette[cell_counts.index(int(entry.get("cells", 0))) % len(palette)]
        axes.plot(
            xs, ys, marker="o" if jittered else "s", linestyle="-" if jittered else "--",
            color=color, label=entry["name"],
        )  # fmt: skip
        for p, x, y in zip(points, xs, ys, strict=True):
            axes.annotate(
                str(p["samples"]), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7
            )
            if (entry["name"], p["samples"]) in on_front:
                front_points.append((x, y))
    front_points.sort()
    axes.plot(
        [x for x, _ in front_points], [y for _, y in front_points], color="black",
        linestyle=":", linewidth=1.2, label="Pareto front", zorder=0,
    )  # fmt: skip
    axes.scatter(
        [x for x, _ in front_points], [y for _, y in front_points], s=120,
        facecolors="none", edgecolors="black", zorder=3,
    )  # fmt: skip
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("render time (s)")
    axes.set_ylabel("RMSE against the ground truth")
    truth = lsr.truth_entry(run)
    if truth is not None and truth.get("points"):
        t = truth["points"][0]
        axes.set_title(
            f"Soft shadows: light cells (colour; dashed: centred, solid: jittered) against "
            f"samples per pixel (labels), {t['size'][0]}x{t['size'][1]}\n"
            f"ground truth {truth['name']} at {t['samples']} spp through {truth['variant']}; "
            f"{caption(run)}",
            fontsize=9,
        )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return save(figure, path)
