"""The report's own plots: each variant's time across runs, and the heat maps' colour bar."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import colormaps

from harness.document.plotting import plt, save
from harness.instruments import imagediff
from harness.report import compare


def history_plot(runs: list[Mapping[str, Any]], path: Path) -> Path | None:
    """Each table variant's mean time per pixel across the runs (oldest left, labelled by
    short commit), log scale; a ring where the change against the variant's previous run is
    significant (``harness.report.compare``: Student's t-test, 95%, the same size in both): red and
    solid when slower, green and dashed when faster; hollow markers: busy (the row did not
    get the cores it asked for)."""
    series = [s for s in compare.history(runs) if s.points]
    if not series:
        return None
    used = sorted({p.run for s in series for p in s.points})
    column = {run: i for i, run in enumerate(used)}
    figure, axes = plt.subplots(figsize=(9.5, 5.5))
    colours = [plt.get_cmap("tab10")(k) for k in range(10)]
    markers = "osD^v<>ph*"
    rings: dict[str, list[tuple[float, float]]] = {"slower": [], "faster": []}
    for i, found in enumerate(series):
        xs = [column[p.run] for p in found.points]
        ys = [p.measured.per_pixel for p in found.points]
        colour = colours[i % len(colours)]
        marker = markers[(i + 3 * (i // len(colours))) % len(markers)]
        label = found.name + (f" ({found.scene})" if found.scene != "reference" else "")
        axes.plot(xs, ys, linestyle="-" if i < len(colours) else "--", linewidth=1,
                  label=label, color=colour, marker=marker, markersize=5)  # fmt: skip
        busy = [(x, y) for x, y, p in zip(xs, ys, found.points, strict=True) if p.measured.busy]
        if busy:
            axes.plot([x for x, _ in busy], [y for _, y in busy], linestyle="none",
                      markerfacecolor="white", color=colour, marker=marker,
                      markersize=5)  # fmt: skip
        for x, y, point in zip(xs, ys, found.points, strict=True):
            change = point.change
            if change is not None and change.test.significant:
                rings[change.verdict].append((x, y))
    for verdict, edge, line in (("slower", "#cc3311", "-"), ("faster", "#228833", "--")):
        if rings[verdict]:
            axes.scatter(
                [x for x, _ in rings[verdict]], [y for _, y in rings[verdict]], s=190,
                facecolors="none", edgecolors=edge, linewidths=1.4, linestyle=line,
                zorder=4, label=f"significantly {verdict} than its previous run",
            )  # fmt: skip
    axes.set_yscale("log")
    axes.set_xticks(range(len(used)))
    labels = []
    for r in used:
        started = str(runs[r].get("started", ""))[5:16].replace("T", " ")
        labels.append(f"{compare.commit_label(runs[r])}\n{started}")
    axes.set_xticklabels(labels, fontsize=7)
    axes.set_xlim(-0.5, len(used) - 0.5)
    axes.set_xlabel("run (short commit, * dirty tree; start time UTC), oldest first")
    axes.set_ylabel("mean time per pixel (s, log scale)")
    axes.set_title(
        "Time per pixel of each variant across runs; rings: a significant change from the "
        "variant's previous run\n(Student's t-test on the timed renders, 95%, where both runs "
        "measured it at one size); hollow markers: busy",
        fontsize=9,
    )
    axes.grid(True, which="major", alpha=0.3)
    axes.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    return save(figure, path)


def heat_scale_plot(path: Path) -> Path:
    """The colour bar of the heat maps (``imagediff.heat_map``: logarithmic, black at
    ``HEAT_LOW`` and below)."""
    figure, axes = plt.subplots(figsize=(5.5, 0.75))
    ramp = np.linspace(0.0, 1.0, 256)[np.newaxis, :]
    axes.imshow(ramp, aspect="auto", cmap=colormaps[imagediff.HEAT_MAP],
                extent=(0.0, 1.0, 0.0, 1.0))  # fmt: skip
    low, high = imagediff.HEAT_LOW, imagediff.HEAT_HIGH
    decades = round(float(np.log10(high / low)))
    ticks = [low * 10**k for k in range(decades + 1)]
    axes.set_xticks([float(imagediff.heat_level(v)) for v in ticks],
                    [f"{v:.0e}" if v < 1 else f"{v:g}" for v in ticks], fontsize=7)  # fmt: skip
    step = float(imagediff.heat_level(imagediff.ONE_STEP))
    axes.axvline(step, color="white", linewidth=1)
    axes.annotate("1/255", (step, 0.5), xytext=(3, 0), textcoords="offset points",
                  color="white", fontsize=7, va="center")  # fmt: skip
    axes.set_yticks([])
    axes.set_title("difference in the largest channel (log scale)", fontsize=7)
    return save(figure, path)
