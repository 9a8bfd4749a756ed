"""The table's plot: the speed-ups over naive as bars."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.document.plotting import caption, plt, save
from harness.engine import figures


def plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The table's speed-ups over naive as horizontal bars (log scale)."""
    rows = [r for r in run["rows"] if r["section"] == "table" and r.get("speedup")]
    if not rows:
        return None
    rows.sort(key=lambda r: -r["speedup"]["value"])  # fastest first (at the top)
    figure, axes = plt.subplots(figsize=(7.5, 0.4 * len(rows) + 1.2))
    names = [r["name"] for r in rows]
    values = [r["speedup"]["value"] for r in rows]
    busy = [figures.is_busy(r) for r in rows]
    axes.barh(
        names, values, color=["white" if b else "#4477aa" for b in busy],
        edgecolor="#4477aa", hatch=["//" if b else "" for b in busy],
    )  # fmt: skip
    axes.set_xscale("log")
    axes.invert_yaxis()
    axes.set_xlabel("speed-up over naive (throughput ratio, log scale)")
    for i, (row, value, hollow) in enumerate(zip(rows, values, busy, strict=True)):
        mark = "" if row["speedup"]["basis"] == "same size" else " *"
        axes.annotate(
            f"{figures.speedup_text(value)}{mark}{' busy' if hollow else ''}",
            (value, i),
            xytext=(3, -3),
            textcoords="offset points",
            fontsize=7,
        )
    hollow_note = (
        f"\nhollow bars: busy (CPU under {figures.BUSY_SHARE:.0%} of the cores asked)"
        if any(busy)
        else ""
    )
    axes.set_title(
        "Speed-up over naive, same run (* measured at another size than naive: per pixel)"
        f"{hollow_note}\n" + caption(run),
        fontsize=9,
    )
    axes.grid(True, axis="x", which="both", alpha=0.3)
    return save(figure, path)
