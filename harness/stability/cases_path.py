"""Path-integrator cases (chapter 21 here, beyond the book): exact oracles for Monte Carlo
path tracing, whatever its random numbers.

- The white furnace: a sphere that keeps all the light it gets (a diffuse albedo of 1, or
  clear glass) inside a uniform sky of radiance L, no other light. Every path returns
  exactly L, so every pixel is L to rounding and the sphere vanishes (a dark disc: light
  lost; a bright one: light made up).
- Energy never created: surfaces that keep less than all (grey diffuse, a mirror, glass)
  under the same sky: no pixel brighter than L, and the grey sphere darker.
- The closed box of radius-1e5 walls (``scenes/spheres-box.yml``, lit only by its glowing
  spheres; rendered at most ``BOX_PIXELS`` pixels) scaled as a whole by 1e-3 and 1e3:
  finite, not black, and the unit-scale picture (the random numbers are a function of the
  pixel and the sample, never of the scene, so only rounding may differ).

A variant without a path integrator is listed as such (its one line), not failed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import yaml

from harness.engine.plan import refusal
from harness.instruments.imagediff import canvas_array, image_error
from harness.scenery import SCENES
from harness.stability.model import Case, Outcome, Probe, Verdict, graded
from harness.stability.scenes import scaled_scene_text
from raytracer.camera import MAX_DEPTH, PATH, RenderSettings
from scene import load_scene_text

SKY = 0.5  # L, the furnace's radiance: a power of two, so L times 1 is L exactly
SAMPLES = 4
FURNACE_DEPTH = MAX_DEPTH  # glass may reflect inside many times: no path is cut short
BOX_SCENE = SCENES / "spheres-box.yml"
BOX_SAMPLES = 2
BOX_DEPTH = 5
BOX_PIXELS = 192  # the box's renders: the probe's size scaled down to at most this many pixels
BOX_TOLERANCE = 0.05  # RMSE against the unit-scale picture
BLACK_MEAN = 0.01  # a box picture darker than this on average has lost its light
ROUNDING_ULPS = 64  # the furnace's tolerance: this many unit roundoffs of L

WHITE_DIFFUSE = {"color": [1, 1, 1], "diffuse": 1, "ambient": 0, "specular": 0}
CLEAR_GLASS = {
    "color": [1, 1, 1], "diffuse": 0, "ambient": 0, "specular": 0, "transparency": 1,
    "refractive-index": 1.5,
}  # fmt: skip
GREY_DIFFUSE = {"color": [0.7, 0.7, 0.7], "diffuse": 1, "ambient": 0, "specular": 0}
MIRROR = {"color": [0, 0, 0], "diffuse": 0, "ambient": 0, "specular": 0, "reflective": 1}


def _sphere(material: dict[str, Any], at: tuple[float, float, float], size: float) -> Any:
    return {"add": "sphere", "material": material,
            "transform": [["scale", size, size, size], ["translate", *at]]}  # fmt: skip


def furnace_text(spheres: list[dict[str, Any]]) -> str:
    """A scene file: ``spheres`` seen from -z under a uniform sky of radiance ``SKY``."""
    items: list[dict[str, Any]] = [
        {"add": "camera", "width": 8, "height": 8, "field-of-view": 0.9, "from": [0, 0, -4],
         "to": [0, 0, 0], "up": [0, 1, 0]},
        {"add": "sky", "color": [SKY, SKY, SKY]},
        *spheres,
    ]  # fmt: skip
    return yaml.safe_dump(items, sort_keys=False)


def scaled_box_text(factor: float) -> str:
    """``scenes/spheres-box.yml`` as if written ``factor`` times larger."""
    return scaled_scene_text(BOX_SCENE.read_text(encoding="utf-8"), factor)


def path_render(
    probe: Probe, text: str, name: str, samples: int, depth: int, pixels: int | None = None
) -> np.ndarray:
    """The variant's path-traced picture of a scene file's ``text`` at the probe's size
    (scaled down to at most ``pixels`` pixels, when given)."""
    api = probe.api
    width, height = probe.size
    if pixels is not None and width * height > pixels:
        shrink = math.sqrt(pixels / (width * height))
        width, height = max(1, int(width * shrink)), max(1, int(height * shrink))
    scene = load_scene_text(text, api, path=name).resized(width, height)
    world = probe.variant.world_for(scene)
    settings = RenderSettings(depth=depth, samples=samples, integrator=PATH)
    return canvas_array(api["render"](scene.camera, world, settings), api["pixel_at"])


def refused(probe: Probe) -> Outcome | None:
    """The outcome of a variant that has no path integrator (its one line), else None."""
    why = refusal(probe.variant, PATH)
    if why is None:
        return None
    return Outcome(Verdict.UNSUPPORTED, None, None, why, "no path integrator")


def _unless_refused(check: Callable[[Probe], Outcome]) -> Callable[[Probe], Outcome]:
    """``check``, for a variant that path-traces (``refused`` for one that does not)."""
    return lambda probe: refused(probe) or check(probe)


def _nonfinite(picture: np.ndarray) -> Outcome | None:
    bad = int(np.count_nonzero(~np.isfinite(picture).all(axis=2)))
    return Outcome(Verdict.NONFINITE, None, 0, f"{bad} pixels NaN or infinite") if bad else None


def furnace_case(case_id: str, what: str, material: dict[str, Any]) -> Case:
    """Every pixel must be ``SKY``: exact, or within ``ROUNDING_ULPS`` unit roundoffs."""

    def check(probe: Probe) -> Outcome:
        text = furnace_text([_sphere(material, (0, 0, 0), 1.0)])
        picture = path_render(probe, text, "furnace.yml", SAMPLES, FURNACE_DEPTH)
        bad = _nonfinite(picture)
        if bad is not None:
            return bad
        error = float(np.max(np.abs(picture - SKY)))
        tolerance = ROUNDING_ULPS * probe.unit_roundoff * SKY
        off = int(np.count_nonzero(np.abs(picture - SKY).max(axis=2) > tolerance))
        detail = (
            f"largest |pixel - L| {error:.3g} (L = {SKY}); {off} of "
            f"{picture.shape[0] * picture.shape[1]} pixels off by more than {tolerance:.2g}"
        )
        return graded(error, tolerance, detail, exact=error == 0)

    return Case(
        id=case_id,
        title=f"white furnace: {what} in a uniform sky L = {SKY}, {SAMPLES} paths per pixel",
        measure="largest |pixel - L|",
        tolerance=f"{ROUNDING_ULPS} unit roundoffs of L",
        check=_unless_refused(check),
    )


def energy_case() -> Case:
    """No pixel brighter than L; the grey sphere's pixels darker (light is absorbed)."""

    def check(probe: Probe) -> Outcome:
        spheres = [
            _sphere(GREY_DIFFUSE, (-1.1, 0, 0), 0.8),
            _sphere(MIRROR, (1.1, 0.6, 0.5), 0.6),
            _sphere(CLEAR_GLASS, (0.9, -0.9, -0.4), 0.5),
        ]
        picture = path_render(probe, furnace_text(spheres), "energy.yml", SAMPLES, FURNACE_DEPTH)
        bad = _nonfinite(picture)
        if bad is not None:
            return bad
        tolerance = ROUNDING_ULPS * probe.unit_roundoff * SKY
        brighter = int(np.count_nonzero(picture.max(axis=2) > SKY + tolerance))
        darkest = float(picture.min())
        detail = (
            f"{brighter} pixels brighter than L = {SKY} (brightest {picture.max():.6g}); "
            f"darkest {darkest:.3g}"
        )
        if brighter:
            return Outcome(Verdict.WRONG, float(brighter), 0, detail)
        if darkest > SKY - 0.05:
            return Outcome(Verdict.WRONG, None, 0, detail + ": the grey sphere absorbed nothing",
                           "no absorption")  # fmt: skip
        exact = float(picture.max()) <= SKY
        return Outcome(Verdict.EXACT if exact else Verdict.WITHIN, 0.0, 0, detail)

    return Case(
        id="path/energy",
        title=f"energy never created: grey diffuse (0.7), mirror and glass spheres in a uniform "
        f"sky L = {SKY}",
        measure="pixels brighter than L",
        unit="px",
        tolerance=f"0 pixels over L + {ROUNDING_ULPS} unit roundoffs; the grey sphere darker",
        check=_unless_refused(check),
    )


def _box(probe: Probe, factor: float) -> np.ndarray:
    text = scaled_box_text(factor)
    return path_render(probe, text, "spheres-box.yml", BOX_SAMPLES, BOX_DEPTH, BOX_PIXELS)


def box_case(factor: float | None) -> Case:
    """``factor`` None: the unit box is finite and lit; else the box scaled by ``factor``
    against the unit one (RMSE within ``BOX_TOLERANCE``)."""

    def check(probe: Probe) -> Outcome:
        unit = probe.cached("path/box-unit", lambda: _box(probe, 1.0))
        picture = unit if factor is None else _box(probe, factor)
        bad = _nonfinite(picture)
        if bad is not None:
            return bad
        mean = float(picture.mean())
        if mean < BLACK_MEAN:
            return Outcome(Verdict.WRONG, None, 0, f"mean {mean:.3g}: black", "black")
        if factor is None:
            return Outcome(Verdict.EXACT, 0.0, 0, f"finite, mean {mean:.3g}")
        error = image_error(picture, unit)
        detail = (
            f"RMSE {error.rmse:.3g} against the unit-scale picture (largest difference "
            f"{error.max_abs:.3g}, mean {mean:.3g})"
        )
        return graded(error.rmse, BOX_TOLERANCE, detail, exact=error.max_abs == 0)

    if factor is None:
        case_id, title, measure, tolerance = (
            "path/box-unit", "the closed box of radius-1e5 walls (spheres-box), path-traced",
            "finite and not black", f"mean over {BLACK_MEAN}",
        )  # fmt: skip
    else:
        case_id, title, measure, tolerance = (
            f"path/box-{factor:g}", f"the closed box of radius-1e5 walls scaled by {factor:g}",
            "RMSE against the unit-scale box", f"{BOX_TOLERANCE}, finite and not black",
        )  # fmt: skip
    return Case(case_id, title, measure, tolerance, _unless_refused(check))


CASES = [
    furnace_case("path/furnace-diffuse", "a diffuse sphere of albedo 1", WHITE_DIFFUSE),
    furnace_case("path/furnace-glass", "a clear glass sphere (index 1.5)", CLEAR_GLASS),
    energy_case(),
    box_case(None),
    box_case(1e-3),
    box_case(1e3),
]
