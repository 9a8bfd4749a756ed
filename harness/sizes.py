"""Canvas sizes for benchmarks: parsing ``WxH`` and the budget rule (smaller, same aspect).

The budget rule: a render whose estimated time exceeds the budget at the requested size is
measured at the largest smaller size with the same aspect ratio that fits. Sizes keep the
aspect exactly when the width and height share a factor (640x480 steps by 4x3, 8x6 by 4x3);
otherwise the height is rounded to the nearest pixel and the row records the size used.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

MAX_SIDE = 16384  # the canvas's own limit
SMALLEST_PIXELS = 12  # never shrink below this many pixels (4x3)


@dataclass(frozen=True, order=True)
class Size:
    """A canvas size in pixels."""

    width: int
    height: int

    @property
    def pixels(self) -> int:
        return self.width * self.height

    def __str__(self) -> str:
        return f"{self.width}x{self.height}"


def parse_size(text: str) -> Size:
    """``"160x120"`` -> ``Size(160, 120)``; a ``ValueError`` naming the text otherwise."""
    match = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text)
    if not match:
        raise ValueError(f"bad size {text!r}: expected WIDTHxHEIGHT, e.g. 160x120")
    size = Size(int(match.group(1)), int(match.group(2)))
    if not (1 <= size.width <= MAX_SIDE and 1 <= size.height <= MAX_SIDE):
        raise ValueError(f"bad size {text!r}: width and height must be 1 to {MAX_SIDE}")
    return size


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


# What one pixel of a render costs at the peak (the canvas, and the image written from it),
# measured: a canvas of ``Color`` values (the book's tracer and the variants built on it,
# a learner's) about 140 bytes a pixel once every pixel holds its own color; numba's arrays
# about 60; wavefront's passes about 175. Rounded up.
BYTES_PER_PIXEL = {"numba": 80, "wavefront": 200}
DEFAULT_BYTES_PER_PIXEL = 160


def render_bytes(variant: str, width: int, height: int) -> int:
    """About how much memory a ``width`` x ``height`` render with ``variant`` (a registry
    name, wrappers included: the costliest part counts) needs."""
    names = re.findall(r"[A-Za-z_][A-Za-z0-9_]*(?=\[|:|$)", variant) or [variant]
    per_pixel = max(BYTES_PER_PIXEL.get(name, DEFAULT_BYTES_PER_PIXEL) for name in names)
    return per_pixel * width * height
