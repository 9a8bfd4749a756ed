"""The scene-size section's plot: render time against triangle count."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.sections.scene_size import report as ssr


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Render time against triangle count (log-log), one line per variant with its fitted
    slope in the legend, and a dotted line of slope 1 (linear) for comparison."""
    lines = [(e["name"], ssr.measured(e), ssr.slopes(e)["render"]) for e in ssr.entries(run)]
    lines = [(name, points, found) for name, points, found in lines if points]
    if not lines:
        return None
    figure, axes = plt.subplots(figsize=(7.5, 5))
    for name, points, found in lines:
        xs = [p["triangles"] for p in points]
        ys = [p["render_median"] for p in points]
        axes.plot(xs, ys, marker="o", label=f"{name} (slope {ssr.slope_text(found)})")
    _, first, _ = max(lines, key=lambda line: len(line[1]))
    x0, y0 = first[0]["triangles"], first[0]["render_median"]
    x1 = max(p["triangles"] for _, points, _ in lines for p in points)
    axes.plot([x0, x1], [y0, y0 * x1 / x0], linestyle=":", color="gray", label="slope 1 (linear)")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("triangles")
    axes.set_ylabel("render time (s), frame prepared")
    w, h = run["settings"]["size"]
    axes.set_title(
        f"Render time against scene size, {w}x{h}, {run['settings']['samples']} spp "
        f"(points over the budget skipped)\n{caption(run)}",
        fontsize=9,
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return save(figure, path)
