"""The ladder's plot: each step's time per pixel, POV-Ray's beside."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.engine import figures
from harness.sections.ladder import report as lr


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The ladder (``harness.sections.ladder.report``): each step's time per pixel as a bar (log
    scale), labelled with its factor over naive and its own over the step before; POV-Ray's
    points as dashed lines across (whole process), when the run had them."""
    found = lr.rows(run)
    steps = [r for r in found if r.get("status") == "ok" and r.get("wall")]
    if not steps:
        return None
    figure, axes = plt.subplots(figsize=(10, 2.1))
    names = [str(r.get("step") or r["name"]).replace("[", "\n[") for r in steps]
    values = [lr.per_pixel(r) for r in steps]
    busy = [figures.is_busy(r) for r in steps]
    colours = ["#cc6677" if r.get("option") else "#4477aa" for r in steps]
    axes.bar(
        range(len(steps)), values, color=["white" if b else c for b, c in zip(busy, colours,
        strict=True)], edgecolor=colours, hatch=["//" if b else "" for b in busy],
    )  # fmt: skip
    for i, row in enumerate(steps):
        total = lr.cumulative(row, found)
        own = lr.own_factor(row, found)
        label = "naive" if total is None else figures.speedup_text(total)
        if own is not None:
            label += f"\n({figures.speedup_text(own)} own)"
        axes.annotate(label, (i, values[i]), xytext=(0, 2), textcoords="offset points",
                      ha="center", va="bottom", fontsize=7)  # fmt: skip
    anchor = lr.anchor(run)
    for point in (anchor or {}).get("points", []) if (anchor or {}).get("status") == "ok" else []:
        if not point.get("wall"):
            continue
        w, h = point["size"]
        dashes = "--" if point["threads"] > 1 else ":"
        axes.axhline(
            point["wall"] / (w * h), color="#228833", linestyle=dashes, linewidth=1, zorder=0,
            label=f"POV-Ray (C++), {point['threads']} thread(s), whole process",
        )  # fmt: skip
        axes.legend(fontsize=6, loc="upper right")
    axes.set_yscale("log")
    axes.set_xticks(range(len(steps)), names, fontsize=7)
    axes.set_ylabel("time per pixel (s, log)", fontsize=8)
    axes.tick_params(axis="y", labelsize=7)
    top = max(values)
    axes.set_ylim(min(values) / 3, top * 12)
    axes.set_title(
        "Step by step: time per pixel; labels: factor over naive (own factor over the step "
        f"before); red: options; hatched: busy. {caption(run)}",
        fontsize=8,
    )
    axes.grid(True, axis="y", which="major", alpha=0.3)
    return save(figure, path)
