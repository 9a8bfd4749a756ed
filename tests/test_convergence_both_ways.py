"""The convergence section on a scene with an area light (chapter 18's light, chapter 21's
path tracer): every variant is measured twice, with explicit light sampling and without,
both against the one converged picture rendered with it. A scene of four by three pixels
and one light cell keeps it to a few CPU seconds through naive. No verdict depends on a time.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import pytest

from groundwork.sizes import Size
from harness.engine.bench import run_bench
from harness.engine.plan import QUICK, BenchSettings
from harness.engine.results import load_run
from harness.report.build import build_report
from harness.scenery.presets import SceneRef
from harness.sections import measuring
from harness.sections.convergence import measure as convergence

LAMP = """\
- add: camera
  width: 4
  height: 3
  field-of-view: 0.8
  from: [0, 1.5, -5]
  to: [0, 0.5, 0]
  up: [0, 1, 0]
- add: area_light
  corner: [-1, 3, -1]
  uvec: [2, 0, 0]
  usteps: 1
  vvec: [0, 0, 2]
  vsteps: 1
  intensity: [1, 1, 1]
- add: plane
- add: sphere
  transform:
    - [translate, 0, 1, 0]
"""

LAMP_MODE = dataclasses.replace(
    QUICK, convergence_scenes=("lamp",), convergence_size=Size(4, 3),
    convergence_compiled_size=Size(4, 3), convergence_samples=(1, 2), convergence_truth=16,
)  # fmt: skip


@pytest.fixture(scope="module")
def lamp_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """One bench run of the convergence section through naive on the lamp scene."""
    scenes = tmp_path_factory.mktemp("scenes")
    (scenes / "lamp.yml").write_text(LAMP, encoding="utf-8")
    results = tmp_path_factory.mktemp("results")
    settings = BenchSettings(
        scene=SceneRef("default-world", None), size=Size(4, 3), samples=1, depth=5, seed=0,
        threads=None, repeat=1, budget=None, variants=["naive"], sections=("convergence",),
        mode=LAMP_MODE, results=results, again=0,
    )  # fmt: skip
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(convergence, "SCENES", scenes)
        path = run_bench(settings, lambda message: None, measuring(settings.sections))
    return results, load_run(path)["rtc"]


def _entries(rtc: dict[str, Any], part: str | None = None) -> list[dict[str, Any]]:
    return [e for e in rtc["series"] if e["section"] == "convergence" and e.get("part") == part]


def test_the_lamp_scene_has_an_area_light(tmp_path: Path) -> None:
    (tmp_path / "lamp.yml").write_text(LAMP, encoding="utf-8")
    assert convergence.has_area_light(SceneRef("lamp", tmp_path / "lamp.yml"))
    assert not convergence.has_area_light(SceneRef("default-world", None))


def test_a_variant_is_measured_with_light_sampling_and_without(lamp_run) -> None:
    _, rtc = lamp_run
    entries = _entries(rtc)
    assert [convergence.label(e) for e in entries] == ["naive", "naive (light sampling off)"]
    for entry in entries:
        assert entry["status"] == "ok" and entry["scene"] == "lamp"
        assert [p["samples"] for p in entry["points"]] == [1, 2]
        assert all(p["error"]["rmse"] > 0 for p in entry["points"])
    sampled, crossed = ([p["error"]["rmse"] for p in e["points"]] for e in entries)
    assert sampled != crossed  # the setting reached the render: other paths, other noise


def test_both_ways_are_measured_against_one_converged_picture_with_light_sampling(
    lamp_run,
) -> None:
    _, rtc = lamp_run
    (truth,) = _entries(rtc, "truth")
    assert truth["name"] == "naive" and truth.get("light_sampling") is None
    assert truth["points"][0]["size"] == [4, 3] and truth["points"][0]["samples"] == 16


def test_the_report_shows_both_rows(lamp_run) -> None:
    results, _ = lamp_run
    readme, _, problems = build_report(results)
    assert problems == []
    section = readme.read_text().split("## Convergence")[1].split("\n## ")[0]
    assert "| `naive` | 4x3 | 1, 2 |" in section
    assert "| `naive (light sampling off)` | 4x3 | 1, 2 |" in section
