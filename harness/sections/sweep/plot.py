"""The sweep's plot: error against time, the Pareto front joined."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.document.runinfo import part
from harness.engine import figures


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Each (configuration, samples) as a point of time against RMSE from the ground truth;
    the Pareto front (nothing both faster and more accurate) joined by a line."""
    entries = [e for e in part(run, "sweep") if e["status"] == "ok"]
    points: list[tuple[float, float]] = []
    labels: list[str] = []
    figure, axes = plt.subplots(figsize=(7.5, 5))
    for entry in entries:
        measured = [p for p in entry["points"] if "wall" in p and p.get("error")]
        if not measured:
            continue
        xs = [p["wall"] for p in measured]
        ys = [max(p["error"]["rmse"], 1e-7) for p in measured]
        axes.plot(xs, ys, marker="o", label=entry["name"])
        for p, x, y in zip(measured, xs, ys, strict=True):
            axes.annotate(
                str(p["samples"]), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7
            )
            points.append((x, y))
            labels.append(f"{entry['name']} {p['samples']} spp")
    if not points:
        plt.close(figure)
        return None
    front = sorted((points[i] for i in figures.pareto_front(points)), key=lambda p: p[0])
    axes.plot(
        [p[0] for p in front],
        [p[1] for p in front],
        color="black",
        linestyle="--",
        linewidth=1.2,
        label="Pareto front",
        zorder=0,
    )
    axes.scatter(
        [p[0] for p in front],
        [p[1] for p in front],
        s=120,
        facecolors="none",
        edgecolors="black",
        zorder=3,
    )
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("render time (s)")
    axes.set_ylabel("RMSE against the ground truth")
    truth = next(iter(part(run, "sweep", "truth")), None)
    if truth is not None:
        w, h = truth["points"][0]["size"]
        axes.set_title(
            f"Error against time, {w}x{h}, labels = samples per pixel\n"
            f"ground truth: {truth['name']} at {truth['points'][0]['samples']} spp; "
            f"{caption(run)}",
            fontsize=9,
        )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return save(figure, path)
