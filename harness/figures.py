"""Figures derived from a measured row: median/min/max, CPU share, MRay/s, speed-up.

Speed-ups compare throughput (pixels x samples per second), so two rows measured at different
sizes (the budget rule) are compared per pixel; ``speedup`` says which basis it used.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping
from typing import Any


def pixels(row: Mapping[str, Any]) -> int:
    width, height = row["size"]
    return int(width) * int(height)


def median_wall(row: Mapping[str, Any]) -> float:
    return float(statistics.median(row["wall"]))


def cpu_share(row: Mapping[str, Any]) -> float:
    """CPU seconds per wall second over the repeats: about 1 for one busy core, 2 for two."""
    return float(sum(row["cpu"]) / sum(row["wall"]))


def samples_per_second(row: Mapping[str, Any]) -> float:
    return pixels(row) * int(row["samples"]) / median_wall(row)


def mrays(row: Mapping[str, Any]) -> float:
    """Million camera samples per second (width x height x samples / time), as the C++
    report counts."""
    return samples_per_second(row) / 1e6


def speedup(row: Mapping[str, Any], baseline: Mapping[str, Any] | None) -> dict[str, Any] | None:
    """Throughput of ``row`` over the baseline's; ``basis`` says whether the sizes matched."""
    if baseline is None or baseline.get("status") != "ok" or row.get("status") != "ok":
        return None
    value = samples_per_second(row) / samples_per_second(baseline)
    if list(row["size"]) == list(baseline["size"]):
        basis = "same size"
    else:
        w, h = baseline["size"]
        basis = f"per pixel (naive measured at {w}x{h})"
    return {"value": value, "basis": basis}


def pareto_front(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points no other point beats in both coordinates (lower is better)."""
    front = []
    for i, (x, y) in enumerate(points):
        dominated = any(
            (ox <= x and oy <= y) and (ox < x or oy < y)
            for j, (ox, oy) in enumerate(points)
            if j != i
        )
        if not dominated:
            front.append(i)
    return front


def seconds_text(value: float) -> str:
    if value >= 100:
        return f"{value:.0f} s"
    if value >= 1:
        return f"{value:.2f} s"
    if value >= 1e-3:
        return f"{value * 1e3:.1f} ms"
    return f"{value * 1e6:.0f} µs"


def rough_seconds(value: float) -> str:
    """An estimate in seconds, to the precision it deserves: ``2.4 s``, ``106 s``."""
    return f"{value:.1f} s" if value < 10 else f"{value:.0f} s"


def count_text(value: float | None) -> str:
    if value is None:
        return "-"
    for limit, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(value) >= limit:
            return f"{value / limit:.3g}{suffix}"
    return f"{value:.0f}"


def bytes_text(value: float | None) -> str:
    if value is None:
        return "-"
    for limit, suffix in ((2**30, "GiB"), (2**20, "MiB"), (2**10, "KiB")):
        if abs(value) >= limit:
            return f"{value / limit:.3g} {suffix}"
    return f"{value:.0f} B"
