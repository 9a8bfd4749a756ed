"""The bench's budget rule: a render whose estimated time exceeds the budget at the requested
size is measured at the largest smaller size with the same aspect ratio that fits.

Sizes keep the aspect exactly when the width and height share a factor (640x480 steps by
4x3, 8x6 by 4x3); otherwise the height is rounded to the nearest pixel and the row records
the size used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from groundwork.sizes import Size

SMALLEST_PIXELS = 12  # never shrink below this many pixels (4x3)


def scaled(size: Size, factor: float) -> Size:
    """``size`` scaled by ``factor`` (at most 1), keeping the aspect ratio.

    Exact when width and height share a factor: the result is the largest multiple of the
    reduced ratio (4x3 for 640x480) not larger than ``factor`` times the size. Otherwise (no
    common factor, or a factor too small for one step) the width is scaled and the height
    rounded. Never below 1x1.
    """
    factor = min(factor, 1.0)
    if factor >= 1.0:
        return size
    common = math.gcd(size.width, size.height)
    step_w, step_h = size.width // common, size.height // common
    steps = math.floor(common * factor + 1e-9)
    if steps >= 1 and common >= 2:
        return Size(step_w * steps, step_h * steps)
    width = max(1, math.floor(size.width * factor + 1e-9))
    height = max(1, round(width * size.height / size.width))
    return Size(width, height)


def smaller_sizes(size: Size, count: int) -> list[Size]:
    """``count`` sizes of the same aspect, each with about a quarter of the pixels of the next
    one, ending with ``size`` (for scaling plots); duplicates dropped."""
    found: list[Size] = []
    for k in range(count - 1, -1, -1):
        candidate = scaled(size, 0.5**k)
        if candidate.pixels >= SMALLEST_PIXELS and candidate not in found:
            found.append(candidate)
    return found


@dataclass(frozen=True)
class Estimate:
    """Time of one render as ``fixed + per_pixel * pixels`` seconds (from probe renders).

    fixed: start-up cost of every render (a pool's workers, a kernel launch); per_pixel: the
    cost of one pixel with all its samples.
    """

    fixed: float
    per_pixel: float

    def seconds(self, size: Size) -> float:
        return self.fixed + self.per_pixel * size.pixels

    @classmethod
    def from_probes(cls, probes: list[tuple[Size, float]]) -> Estimate:
        """Fit the last two probes (sizes and seconds); one probe: all cost per pixel."""
        size2, t2 = probes[-1]
        if len(probes) < 2 or probes[-2][0].pixels >= size2.pixels:
            return cls(0.0, t2 / size2.pixels)
        size1, t1 = probes[-2]
        slope = (t2 - t1) / (size2.pixels - size1.pixels)
        per_pixel = max(slope, 0.25 * t2 / size2.pixels)  # noise must not make pixels free
        return cls(max(0.0, t2 - per_pixel * size2.pixels), per_pixel)


@dataclass(frozen=True)
class BudgetChoice:
    """The size the budget rule picked.

    size: the size to measure at; estimate: the estimated seconds of all renders at the
    requested size; reduced: True when ``size`` is smaller than requested; note: why.
    """

    size: Size
    estimate: float
    reduced: bool
    note: str = ""


def fit_to_budget(
    requested: Size, estimate: Estimate, renders: float, budget: float | None
) -> BudgetChoice:
    """The largest size of the requested aspect whose ``renders`` renders fit in ``budget``.

    estimate: one render's time by size (from probes); renders: how many renders will be
    made at the chosen size; budget: seconds, or None for no limit.
    """
    total = estimate.seconds(requested) * renders
    if budget is None or total <= budget:
        return BudgetChoice(requested, total, False)
    affordable = (budget / renders - estimate.fixed) / estimate.per_pixel
    factor = math.sqrt(max(affordable, SMALLEST_PIXELS) / requested.pixels)
    size = scaled(requested, factor)
    while size.pixels > SMALLEST_PIXELS and estimate.seconds(size) * renders > budget:
        factor *= 0.95
        smaller = scaled(requested, factor)
        if smaller == size:
            continue
        size = smaller
    note = (
        f"measured at {size} instead of {requested}: {renders:g} "
        f"render{'s' if renders != 1 else ''} at {requested} "
        f"{'were' if renders != 1 else 'was'} estimated at {total:.0f} s, over the "
        f"{budget:g} s budget"
    )
    if estimate.seconds(size) * renders > budget:
        note += f" (even {size}, the smallest size tried, is estimated over it)"
    return BudgetChoice(size, total, True, note)

