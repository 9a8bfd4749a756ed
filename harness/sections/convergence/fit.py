"""Power laws fitted to a path tracer's error (chapter 21 here): RMSE = c x^slope on log-log
axes, x the samples per pixel or the wall time, and the time to a target RMSE read off the
fit. Monte Carlo with independent samples gives a slope of about -1/2."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

TARGET_RMSE = 0.01  # the headline: the time to this RMSE against the converged picture
LONGEST = 1e9  # seconds (about 32 years): a time to the target beyond this is "beyond"


@dataclass(frozen=True)
class PowerLaw:
    """log10(y) = intercept + slope * log10(x), fitted by least squares over ``points``
    (how many (x, y) it rests on) between ``low`` and ``high`` (the smallest and largest x)."""

    slope: float
    intercept: float
    points: int
    low: float
    high: float

    def at(self, x: float) -> float:
        return float(10 ** (self.intercept + self.slope * math.log10(x)))

    def solve(self, y: float) -> float | None:
        """The x where the fit reaches ``y``; None when it does not fall (slope 0 or up)."""
        if self.slope >= 0:
            return None
        return float(10 ** ((math.log10(y) - self.intercept) / self.slope))

    def as_dict(self) -> dict[str, float | int]:
        return {"slope": self.slope, "intercept": self.intercept, "points": self.points,
                "low": self.low, "high": self.high}  # fmt: skip


def power_law(xs: Sequence[float], ys: Sequence[float]) -> PowerLaw | None:
    """The least-squares line through (log10 x, log10 y) for positive pairs; None for fewer
    than two distinct x."""
    pairs = [(x, y) for x, y in zip(xs, ys, strict=True) if x > 0 and y > 0]
    if len({x for x, _ in pairs}) < 2:
        return None
    lx = np.log10([x for x, _ in pairs])
    ly = np.log10([y for _, y in pairs])
    slope, intercept = np.polyfit(lx, ly, 1)
    return PowerLaw(float(slope), float(intercept), len(pairs), min(p[0] for p in pairs),
                    max(p[0] for p in pairs))  # fmt: skip


def time_to(law: PowerLaw | None, target: float = TARGET_RMSE) -> dict[str, object] | None:
    """The wall time at which the time fit ``law`` reaches ``target``, and whether that lies
    outside the measured times (``extrapolated``); None without a falling fit. A time over
    ``LONGEST`` is kept as ``seconds`` None, ``beyond`` ``LONGEST``."""
    if law is None:
        return None
    seconds = law.solve(target)
    if seconds is None:
        return None
    if seconds > LONGEST:
        return {"target": target, "seconds": None, "beyond": LONGEST, "extrapolated": True}
    inside = law.low <= seconds <= law.high
    return {"target": target, "seconds": seconds, "extrapolated": not inside}
