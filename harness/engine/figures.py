"""Figures derived from a measured row: median/min/max, CPU share, MRay/s, speed-up.

Speed-ups compare throughput (pixels x samples per second), so two rows measured at different
sizes (the budget rule) are compared per pixel; ``speedup`` says which basis it used.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping
from typing import Any

from variants.registry import VariantError, parse_variant_name

# a row whose CPU share is below this fraction of the cores it asked for did not get them
EXACT = 1e-6  # a picture within this of another's (max abs) counts as the same picture
BUSY_SHARE = 0.8


def pixels(row: Mapping[str, Any]) -> int:
    width, height = row["size"]
    return int(width) * int(height)


def median_wall(row: Mapping[str, Any]) -> float:
    return float(statistics.median(row["wall"]))


def cpu_share(row: Mapping[str, Any]) -> float:
    """CPU seconds per wall second over the repeats: about 1 for one busy core, 2 for two."""
    return float(sum(row["cpu"]) / sum(row["wall"]))


PARALLEL_OPTIONS = ("workers", "threads")  # options whose value is a worker or thread count
ALL_CORES_BY_DEFAULT = ("pooled", "numba", "dask")
"""Variants that use every available core unless an option of ``PARALLEL_OPTIONS`` says."""


def cores_asked(name: str, available: int) -> int:
    """The cores a variant asks for, by its name: N for a worker or thread count option
    (``PARALLEL_OPTIONS``: ``pooled[workers=N]``, whose inner variant runs in
    those workers, ``numba[threads=N]``, ``wavefront[threads=N]``), every available core for
    plain ``numba`` and ``pooled``, 1 otherwise; never more than ``available`` (a row cannot
    get cores the machine does not have)."""
    try:
        spec = parse_variant_name(name)
    except VariantError:
        return 1
    options = dict(spec.options)
    asked = available if spec.name in ALL_CORES_BY_DEFAULT else 1
    for key in PARALLEL_OPTIONS:
        if key in options:
            try:
                asked = int(options[key])
            except ValueError:
                asked = available
            break
    return max(1, min(asked, available))


def is_busy(row: Mapping[str, Any]) -> bool:
    """True when the row's CPU share is below ``BUSY_SHARE`` of the cores it asked for: the
    machine was busy (or the render left cores idle), so its time understates the variant."""
    if row.get("status") != "ok" or not row.get("wall"):
        return False
    return share_busy(str(row["name"]), cpu_share(row), int(row.get("cores") or 1))


def share_busy(name: str, share: float, available: int) -> bool:
    """True when ``share`` (cores busy) is below ``BUSY_SHARE`` of what ``name`` asks for."""
    return share < BUSY_SHARE * cores_asked(name, available)


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


def significant_text(value: float, digits: int = 3) -> str:
    """``value`` to ``digits`` significant digits, never in exponent form, with thousands
    separators and no trailing zeros: ``36,900``, ``198``, ``37.3``, ``1.6``, ``0.636``."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    decimals = digits - 1 - math.floor(math.log10(abs(value)))
    rounded = round(value, decimals)
    if decimals <= 0:
        return f"{rounded:,.0f}"
    return f"{rounded:,.{decimals}f}".rstrip("0").rstrip(".")


def speedup_text(value: float) -> str:
    """A speed-up as the report prints it: ``36,900x``, ``125x``, ``1.6x``, ``0.64x``."""
    return significant_text(value) + "x"


def per_pixel_text(seconds: float) -> str:
    """A time per pixel to 3 significant digits in the unit that fits: ``13.4 ms``,
    ``365 ns``."""
    for limit, unit in ((1.0, "s"), (1e-3, "ms"), (1e-6, "µs")):
        if seconds >= limit:
            return f"{significant_text(seconds / limit)} {unit}"
    return f"{significant_text(seconds / 1e-9)} ns"


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
