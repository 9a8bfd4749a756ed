"""The path integrator's oracles in ``rtc stability`` (``harness/stability/cases_path.py``):
deliberately wrong tracers are caught, a tracer without a path integrator is listed with its
line, and the scaled closed box is the box file scaled. Renders are 8x6."""

from __future__ import annotations

import dataclasses

import yaml

from harness.stability import cases_path
from harness.stability.model import Outcome, Probe, Verdict
from harness.stability.suite import CASES, run_case
from raytracer.camera import RenderSettings
from raytracer.path import Scattered
from raytracer.tracer import Tracer
from variants.integrators import whitted_only
from variants.registry import tracer_variant

SIZE = (8, 6)


class Brightening(Tracer):
    """Every bounce gains a quarter: light made up."""

    def scatter(self, comps, lobe_u, fresnel_u, u1, u2) -> Scattered:  # type: ignore[no-untyped-def]
        s = super().scatter(comps, lobe_u, fresnel_u, u1, u2)
        return dataclasses.replace(s, weight=s.weight * 1.25)


class Dimming(Tracer):
    """Every bounce loses a tenth: light lost (a dark disc in the furnace)."""

    def scatter(self, comps, lobe_u, fresnel_u, u1, u2) -> Scattered:  # type: ignore[no-untyped-def]
        s = super().scatter(comps, lobe_u, fresnel_u, u1, u2)
        return dataclasses.replace(s, weight=s.weight * 0.9)


class WhittedOnly(Tracer):
    def check_settings(self, settings: RenderSettings) -> None:
        whitted_only("whitted-only", settings)


def outcome(tracer: Tracer, case_id: str) -> Outcome:
    variant = tracer_variant(type(tracer).__name__.lower(), "a test tracer", tracer, base="naive")
    case = next(c for c in CASES if c.id == case_id)
    return run_case(case, Probe(variant, SIZE)).outcome


def test_a_tracer_that_makes_light_fails_the_furnace_and_the_energy_case() -> None:
    furnace = outcome(Brightening(), "path/furnace-diffuse")
    assert furnace.verdict is Verdict.WRONG
    assert furnace.error is not None and furnace.error >= 0.1, furnace.detail  # 0.625 - 0.5
    energy = outcome(Brightening(), "path/energy")
    assert energy.verdict is Verdict.WRONG and energy.error is not None and energy.error >= 1


def test_a_tracer_that_loses_light_fails_both_furnaces() -> None:
    for case_id in ("path/furnace-diffuse", "path/furnace-glass"):
        found = outcome(Dimming(), case_id)
        assert found.verdict is Verdict.WRONG, f"{case_id}: {found.detail}"
        assert found.error is not None and found.error >= 0.04, f"{case_id}: {found.detail}"


def test_the_reference_passes_the_furnace_exactly() -> None:
    for case_id in ("path/furnace-diffuse", "path/furnace-glass"):
        found = outcome(Tracer(), case_id)
        assert found.verdict is Verdict.EXACT and found.error == 0, found.detail


def test_a_tracer_without_a_path_integrator_is_listed_with_its_line() -> None:
    for case in cases_path.CASES:
        found = outcome(WhittedOnly(), case.id)
        assert found.verdict is Verdict.UNSUPPORTED, case.id
        assert "whitted-only has no path integrator" in found.detail
        assert found.note == "no path integrator"


def test_the_scaled_box_scales_the_camera_and_every_shape_not_the_sky() -> None:
    items = yaml.safe_load(cases_path.scaled_box_text(1e3))
    unit = yaml.safe_load(cases_path.BOX_SCENE.read_text(encoding="utf-8"))
    camera = next(i for i in items if i.get("add") == "camera")
    assert camera["from"] == [
        1e3 * v for v in next(i for i in unit if i.get("add") == "camera")["from"]
    ]
    shapes = [i for i in items if i.get("add") == "sphere"]
    assert shapes and all(s["transform"][-2] == ["scale", 1e3, 1e3, 1e3] for s in shapes)
    assert all("transform" not in i for i in items if i.get("add") in ("sky", "render", "camera"))


def test_the_box_renders_at_most_its_pixels_whatever_the_probe() -> None:
    probe = Probe(tracer_variant("reference", "test", Tracer(), base="naive"), (32, 24))
    picture = cases_path.path_render(
        probe, cases_path.scaled_box_text(1.0), "box.yml", 1, 1, cases_path.BOX_PIXELS
    )
    height, width, _ = picture.shape
    assert width * height <= cases_path.BOX_PIXELS and width * 3 == height * 4
