"""The convergence plot: per scene, RMSE against samples per pixel and against wall time on
log-log axes, each variant's points with its fitted line and slope, the 0.01 target."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from matplotlib.ticker import NullFormatter

from harness.document.plotting import caption, plt, save
from harness.document.runinfo import part
from harness.sections.convergence.fit import TARGET_RMSE
from harness.sections.convergence.measure import SECTION
from harness.sections.convergence.measure import label as entry_label


def _panel(axes: Any, entries: list[Mapping[str, Any]], key: str, label: str) -> None:
    """One panel: x is ``samples`` or ``wall``; the fit of ``fit[key]`` dashed."""
    for index, entry in enumerate(entries):
        done = [p for p in entry["points"] if "wall" in p and p.get("error")]
        if not done:
            continue
        colour = f"C{index % 10}"
        xs = [p["samples" if key == "samples" else "wall"] for p in done]
        ys = [max(p["error"]["rmse"], 1e-7) for p in done]
        law = (entry.get("fit") or {}).get(key)
        slope = "" if not law else f" (slope {law['slope']:+.2f})"
        axes.plot(xs, ys, "o", color=colour, label=f"{entry_label(entry)}{slope}")
        loose = [(x, y) for p, x, y in zip(done, xs, ys, strict=True) if not p.get("fitted", True)]
        if loose:  # too near the converged picture's samples: shown, not fitted
            axes.plot(*zip(*loose, strict=True), "o", color="white", markeredgecolor=colour)
        if law:
            low, high = law["low"], law["high"]
            line = [low * (high / low) ** (k / 20) for k in range(21)]
            fit = [10 ** (law["intercept"] + law["slope"] * math.log10(x)) for x in line]
            axes.plot(line, fit, "--", color=colour, linewidth=1)
    axes.axhline(TARGET_RMSE, color="grey", linewidth=0.8, linestyle=":")
    axes.set_xscale("log")
    axes.set_yscale("log")
    if key == "samples":  # the counts themselves, as plain numbers
        axes.xaxis.set_minor_formatter(NullFormatter())
        counts = sorted({p["samples"] for e in entries for p in e["points"] if "wall" in p})
        axes.set_xticks(counts, [str(n) for n in counts])
    axes.set_xlabel(label)
    axes.set_ylabel("RMSE against the converged picture")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """A row of two panels per scene (samples, time); None when nothing was measured."""
    entries = [e for e in part(run, SECTION) if e["status"] == "ok"]
    scenes = list(dict.fromkeys(e["scene"] for e in entries))
    if not scenes:
        return None
    figure, grid = plt.subplots(len(scenes), 2, figsize=(11, 4.2 * len(scenes)), squeeze=False)
    for row, scene in enumerate(scenes):
        mine = [e for e in entries if e["scene"] == scene]
        _panel(grid[row][0], mine, "samples", "samples per pixel")
        _panel(grid[row][1], mine, "time", "render time (s)")
        sizes = sorted({"x".join(map(str, p["size"])) for e in mine for p in e["points"]})
        grid[row][0].set_title(f"{scene} ({', '.join(sizes)}), path-traced, depth 5", fontsize=9)
        grid[row][1].set_title(f"{scene}: dotted line RMSE {TARGET_RMSE:g}", fontsize=9)
    figure.suptitle(f"Convergence; {caption(run)}", fontsize=9)
    return save(figure, path)
