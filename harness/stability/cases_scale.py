"""Scale cases: the reference scene (camera and light with it) scaled as a whole, or moved
far from the origin. The picture should not change, so the measure is the number of pixels
that differ from the same variant's unit-scale picture by more than one 8-bit step: shadow
acne and lost hits show up here."""

from __future__ import annotations

import numpy as np

from harness.instruments.imagediff import image_error
from harness.stability.model import Case, Outcome, Probe, Verdict
from harness.stability.scenes import reference_scene, render_array

# (id, scale factor, offset)
PLACES = (
    ("scale/1e-6", 1e-6, 0.0),
    ("scale/1e-3", 1e-3, 0.0),
    ("scale/1e3", 1e3, 0.0),
    ("scale/1e6", 1e6, 0.0),
    ("scale/moved-1e6", 1.0, 1e6),
)


def _picture(probe: Probe, factor: float, offset: float) -> np.ndarray:
    camera, world = reference_scene(probe.api, probe.size, factor, offset)
    return render_array(probe.api, camera, world)


def compare_pictures(
    picture: np.ndarray, reference: np.ndarray, what: str, things: str = "pixels"
) -> Outcome:
    """Pixels of ``picture`` off ``reference`` by more than 1/255 (0: within tolerance; no
    difference at all: exact); any NaN or infinity: non-finite. ``things``: what the
    array's entries are (pixels of a render, or colors along a grid of rays)."""
    bad = int(np.count_nonzero(~np.isfinite(picture).all(axis=2)))
    if bad:
        return Outcome(Verdict.NONFINITE, None, 0, f"{bad} {things} NaN or infinite")
    error = image_error(picture, reference)
    detail = (
        f"{error.pixels_over_one_step} of {error.pixels} {things} off {what} by more than "
        f"1/255 (largest difference {error.max_abs:.3g})"
    )
    count = float(error.pixels_over_one_step)
    if error.max_abs == 0:
        return Outcome(Verdict.EXACT, 0.0, 0, detail)
    verdict = Verdict.WITHIN if count == 0 else Verdict.WRONG
    return Outcome(verdict, count, 0, detail)


def scale_case(case_id: str, factor: float, offset: float) -> Case:
    if offset == 0:
        where = f"scaled by {factor:g}"
    else:
        where = f"moved by ({offset:g}, {offset:g}, {offset:g})"

    def check(probe: Probe) -> Outcome:
        unit = probe.cached("scale/unit", lambda: _picture(probe, 1.0, 0.0))
        moved = _picture(probe, factor, offset)
        return compare_pictures(moved, unit, "the unit-scale picture")

    return Case(
        id=case_id,
        title=f"the reference scene {where}, camera and light with it",
        measure="pixels off the unit-scale picture by > 1/255",
        unit="px",
        tolerance="0 pixels",
        check=check,
    )


CASES = [scale_case(*place) for place in PLACES]
