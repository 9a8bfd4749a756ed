"""The path tracer's sections of ``rtc bench`` (issue 34): ``convergence`` (RMSE against a
converged picture as samples grow, fitted on log-log axes) and the path-traced C++ workload in
the ``preset`` section, run for real at a tiny size through naive and cached; ``--integrator``
on ``rtc bench`` and ``rtc profile``. No verdict depends on a time."""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path
from typing import Any

import pytest

from groundwork.sizes import Size
from harness.document.model import Bullets
from harness.document.runinfo import REPORT_DIR
from harness.engine import figures
from harness.engine.bench import run_bench
from harness.engine.child import Renderer
from harness.engine.plan import QUICK, BenchSettings, refusal
from harness.engine.results import load_run
from harness.report.build import build_report
from harness.scenery.presets import SceneRef
from harness.sections import measuring
from harness.sections.convergence import report as convergence_report
from harness.sections.convergence.fit import power_law, time_to
from harness.sections.convergence.measure import is_compiled
from harness.sections.convergence.report import headline
from harness.sections.profile import jobs as profile_jobs
from harness.sections.profile.profiler import Request
from raytracer.camera import PATH, WHITTED, RenderSettings
from raytracer.tracer import Tracer
from rtc import cmd_bench, cmd_profile
from rtc.cli import main
from variants.integrators import whitted_only
from variants.registry import load_variant, tracer_variant

TINY = dataclasses.replace(
    QUICK, convergence_scenes=("cpp-spheres",), convergence_size=Size(4, 3),
    convergence_compiled_size=Size(4, 3), convergence_samples=(1, 2, 4), convergence_truth=32,
    preset_size=Size(4, 3), compare_pixels=12,
)  # fmt: skip


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """One bench run of the preset and convergence sections through naive and cached."""
    results = tmp_path_factory.mktemp("results")
    settings = BenchSettings(
        scene=SceneRef("default-world", None), size=Size(8, 6), samples=1, depth=5, seed=0,
        threads=None, repeat=1, budget=None, variants=["naive", "cached"],
        sections=("preset", "convergence"), mode=TINY, results=results, again=0,
    )  # fmt: skip
    path = run_bench(settings, lambda message: None, measuring(settings.sections))
    return results, load_run(path)["rtc"]


def _entries(rtc: dict[str, Any], part: str | None = None) -> list[dict[str, Any]]:
    return [e for e in rtc["series"] if e["section"] == "convergence" and e.get("part") == part]


def test_each_variant_has_an_rmse_per_sample_count_and_fits(tiny_run) -> None:
    _, rtc = tiny_run
    entries = {e["name"]: e for e in _entries(rtc)}
    assert list(entries) == ["naive", "cached"]
    for entry in entries.values():
        assert entry["status"] == "ok" and entry["scene"] == "cpp-spheres"
        assert [p["samples"] for p in entry["points"]] == [1, 2, 4]
        assert all(p["size"] == [4, 3] and p["error"]["rmse"] > 0 for p in entry["points"])
        assert all(p["image"] is None for p in entry["points"])  # pictures not kept
        assert entry["fit"]["samples"]["points"] == 3 and entry["fit"]["time"]["points"] == 3
        assert math.isfinite(entry["fit"]["samples"]["slope"])
    # the reference and cached trace the same paths (the random numbers are the sample's)
    naive, cached = (entries[n]["points"] for n in ("naive", "cached"))
    assert [p["error"]["rmse"] for p in naive] == [p["error"]["rmse"] for p in cached]


def test_the_converged_picture_is_kept_with_its_own_seed(tiny_run) -> None:
    results, rtc = tiny_run
    (truth,) = _entries(rtc, "truth")
    assert truth["name"] in ("naive", "cached") and truth["samples"] == 32
    assert truth["seed"] != rtc["settings"]["seed"]
    point = truth["points"][0]
    assert point["size"] == [4, 3] and point["samples"] == 32
    assert (results / "runs" / point["image"]).is_file()


def test_the_path_preset_is_measured_in_mrays_beside_the_whitted_one(tiny_run) -> None:
    _, rtc = tiny_run
    rows = [r for r in rtc["rows"] if r["section"] == "preset"]
    assert [(r["name"], r["integrator"]) for r in rows] == [
        ("naive", WHITTED), ("cached", WHITTED), ("naive", PATH), ("cached", PATH),
    ]  # fmt: skip
    path = [r for r in rows if r["integrator"] == PATH]
    assert all(r["scene"] == "cpp-spheres-path" and r["samples"] == 8 for r in path)
    assert path[0]["image"] != rows[0]["image"]  # its own pictures
    assert path[1]["error_vs_naive"]["max_abs"] == 0  # against naive's path-traced picture
    assert path[0]["speedup"]["value"] == pytest.approx(1.0)


def test_the_report_shows_the_convergence_and_the_cited_cpp_figures(tiny_run) -> None:
    results, _ = tiny_run
    readme, _, problems = build_report(results)
    assert problems == []
    text = readme.read_text()
    section = text.split("## Convergence")[1].split("\n## ")[0]
    assert "`cpp-spheres`" in section and "slope vs samples" in section
    assert "| `naive` | 4x3 | 1, 2, 4 |" in section
    assert (results / REPORT_DIR / "convergence.png").is_file() and "convergence.png" in section
    preset = text.split("## The C++ report's workload")[1].split("\n## ")[0]
    assert "Path-traced, as the C++ report ran it" in preset
    assert "| 0.22 |" in preset and "| 44.9 |" in preset and "cited, not measured here" in preset


def test_the_time_to_the_target_rmse_is_read_off_the_fit() -> None:
    law = power_law([1, 4, 16], [0.08, 0.04, 0.02])  # RMSE = 0.08 t^-1/2
    assert law is not None and law.slope == pytest.approx(-0.5)
    found = time_to(law, 0.01)
    assert found is not None and found["seconds"] == pytest.approx(64)
    assert found["extrapolated"] is True  # beyond the 16 s measured
    assert time_to(power_law([1, 4, 16], [0.08, 0.04, 0.02]), 0.03)["extrapolated"] is False
    assert time_to(power_law([1, 2], [0.1, 0.1])) is None  # flat: never reaches it
    assert power_law([2, 2], [0.1, 0.2]) is None  # one x: no line
    far = time_to(power_law([1, 2], [0.5, 0.49]))  # barely falling: ages away
    assert far is not None and far["seconds"] is None and far["beyond"] == 1e9
    assert headline({"status": "ok", "fit": {"time_to": far}}) == "over 1e+09 s (extrapolated)"
    entry = {"status": "ok", "fit": {"time_to": found}}
    assert headline(entry) == f"{figures.seconds_text(64.0)} (extrapolated)"


def test_a_variant_without_a_path_integrator_says_why() -> None:
    class WhittedOnly(Tracer):
        def check_settings(self, settings: RenderSettings) -> None:
            whitted_only("whitted-only", settings)

    variant = tracer_variant("whitted-only", "test", WhittedOnly(), base="naive")
    assert refusal(variant, WHITTED) is None
    why = refusal(variant, PATH)
    assert why is not None and why.startswith("whitted-only has no path integrator")
    assert refusal(tracer_variant("ref", "test", Tracer(), base="naive"), PATH) is None


@pytest.mark.parametrize("command", ["bench", "profile"])
@pytest.mark.parametrize(
    ("flag", "word"), [("--integrator", "photon"), ("--light-sampling", "maybe")]
)
def test_a_bad_integrator_or_light_sampling_word_is_a_one_line_error(
    command: str, flag: str, word: str, capsys, tmp_path
) -> None:
    args = [command, flag, word]
    args += (
        ["--results-dir", str(tmp_path)] if command == "bench" else ["x.yml", "--variant", "naive"]
    )
    with pytest.raises(SystemExit) as stopped:
        main(args)
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and flag in err and word in err


def test_bench_light_sampling_off_reaches_every_jobs_render_settings(tmp_path) -> None:
    parser = argparse.ArgumentParser()
    cmd_bench.add_arguments(parser)
    base = ["--integrator", "path", "--variants", "naive", "--results-dir", str(tmp_path)]
    assert cmd_bench.settings_from(parser.parse_args(base)).light_sampling is True
    settings = cmd_bench.settings_from(parser.parse_args([*base, "--light-sampling", "off"]))
    assert settings.light_sampling is False
    job = {"variant": "naive", "scene": settings.scene.as_dict(), "depth": 5, "seed": 0,
           "integrator": PATH, "light_sampling": settings.light_sampling}  # fmt: skip
    assert Renderer(job).settings(1).light_sampling is False


def test_profile_light_sampling_off_reaches_the_profiled_render(tmp_path) -> None:
    parser = argparse.ArgumentParser()
    cmd_profile.add_arguments(parser)
    args = parser.parse_args(["x.yml", "--variant", "naive", "--light-sampling", "off"])
    assert cmd_profile._light_sampling(args) is False
    assert cmd_profile._light_sampling(parser.parse_args(["x.yml", "--variant", "naive"]))
    request = Request(variant="naive", scene=tmp_path / "x.yml", size=Size(4, 3),
                      folder=tmp_path, stem="p", integrator=PATH, light_sampling=False)  # fmt: skip
    settings = profile_jobs._settings({**request.job("stages"), "samples": 2})
    assert settings.integrator == PATH and settings.light_sampling is False


def test_bench_integrator_path_lists_a_refusing_variant_as_unavailable(tmp_path) -> None:
    parser = argparse.ArgumentParser()
    cmd_bench.add_arguments(parser)
    args = ["--integrator", "path", "--variants", "naive,cached,numba", "--results-dir"]
    settings = cmd_bench.settings_from(parser.parse_args([*args, str(tmp_path)]))
    assert settings.integrator == PATH
    numba = load_variant("numba")
    why = refusal(numba, PATH)
    if why is None:  # numba path-traces: measured like the others
        assert settings.variants == ["naive", "cached", "numba"]
    else:
        assert settings.variants == ["naive", "cached"]
        assert settings.unavailable == {"numba": why}


def test_the_report_lists_a_refusing_variant_with_its_line(tiny_run) -> None:
    _, rtc = tiny_run
    why = "numba has no path integrator yet (its render loop is the book's Whitted tracer)"
    refused = {"section": "convergence", "part": "refused", "name": "numba",
               "scene": "cpp-spheres", "status": "refused", "error": why}  # fmt: skip
    run = {**rtc, "series": [*rtc["series"], refused]}
    found = [b for b in convergence_report.blocks(run, None, "context") if isinstance(b, Bullets)]
    assert found and found[-1].items == [f"`numba`: {why}"]


def test_compiled_variants_render_the_larger_size() -> None:
    assert is_compiled("numba") and is_compiled("wavefront")
    assert not is_compiled("cached") and not is_compiled("pooled")
