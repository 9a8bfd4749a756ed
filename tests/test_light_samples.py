"""The bench's light-samples section (issue 15): scenes rewritten per light sampling, the
section measured end to end at a tiny size, and its report (table, front, plot)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from groundwork.sizes import Size
from harness.document.model import Gallery, Table
from harness.sections.light_samples import measure as light_samples
from harness.sections.light_samples import plot as light_samples_plot
from harness.sections.light_samples import report as light_samples_report
from harness.sections.light_samples.measure import Config, Plan, configured

SCENE = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 1.0
  from: [0, 2, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: area_light
  corner: [-1, 4, -1]
  uvec: [2, 0, 0]
  usteps: 3
  vvec: [0, 0, 2]
  vsteps: 3
  intensity: [1, 1, 1]
- add: plane
- add: sphere
  transform:
    - [translate, 0, 1, 0]
"""


def test_configured_sets_every_area_light_and_keeps_its_edges() -> None:
    text = configured(SCENE, Config(16, True), Path("s.yml"))
    light = next(item for item in yaml.safe_load(text) if item["add"] == "area_light")
    assert (light["usteps"], light["vsteps"], light["jitter"]) == (4, 4, True)
    assert light["uvec"] == [2, 0, 0] and light["corner"] == [-1, 4, -1]


def test_a_scene_without_an_area_light_is_named_in_the_error() -> None:
    with pytest.raises(ValueError, match=r"plain\.yml: the scene has no '- add: area_light'"):
        configured("- add: plane\n", Config(4, False), Path("plain.yml"))


def test_cells_must_make_a_square_grid() -> None:
    assert Config(64, False).steps == 8
    assert Config(1, True).label == "1x1 jittered"
    with pytest.raises(ValueError, match="not a square grid"):
        _ = Config(8, False).steps


def _point(samples: int, wall: float, rmse: float) -> dict[str, Any]:
    error = {"rmse": rmse, "psnr": 30.0, "max_abs": 0.2, "pixels_over_one_step": 1}
    return {"size": [8, 6], "samples": samples, "wall": wall, "cpu": 1.0, "error": error}


def _run() -> dict[str, Any]:
    truth = {"section": "light-samples", "part": "truth", "name": "8x8 jittered", "scene": "s",
             "variant": "v",
             "status": "ok", "points": [{"size": [8, 6], "samples": 256, "wall": 9.0}]}  # fmt: skip
    fast_bad = {"section": "light-samples", "name": "1x1 centred", "status": "ok", "jitter": False,
                "points": [_point(1, 0.1, 0.05), _point(4, 0.6, 0.049)]}  # fmt: skip
    slow_good = {"section": "light-samples", "name": "4x4 jittered", "status": "ok", "jitter": True,
                 "points": [_point(1, 0.5, 0.02), _point(4, 2.0, 0.008)]}  # fmt: skip
    machine = {"cpu_model": "cpu", "cores_available": 2, "python": "3.11"}
    return {"series": [truth, fast_bad, slow_good], "machine": machine}


def test_the_front_keeps_only_points_nothing_beats_in_time_and_error() -> None:
    assert light_samples_report.front(_run()) == {
        ("1x1 centred", 1), ("4x4 jittered", 1), ("4x4 jittered", 4)
    }  # fmt: skip


def test_the_report_section_has_a_row_per_point_and_says_what_is_cheapest() -> None:
    blocks = light_samples_report.blocks(_run(), None, "context")
    table = next(b for b in blocks if isinstance(b, Table))
    assert [row[0] for row in table.rows] == ["1x1 centred"] * 2 + ["4x4 jittered"] * 2
    assert [row[-1] for row in table.rows] == ["yes", "", "yes", "yes"]
    text = str(blocks)
    assert "within RMSE 0.01 of the truth: 4x4 jittered at 4 spp" in text


def test_the_plot_is_written(tmp_path: Path) -> None:
    path = light_samples_plot.plot(_run(), tmp_path / "plot.png")
    assert path is not None and path.stat().st_size > 1000


def test_the_section_measures_a_tiny_soft_shadow_scene(tmp_path: Path) -> None:
    scene = tmp_path / "soft.yml"
    scene.write_text(SCENE)
    plan = Plan(
        variant="prealloc", size=Size(8, 6), scene=scene,
        configs=(Config(1, False), Config(4, True)), samples=(1, 2), repeat=2,
        truth=Config(4, True), truth_samples=8, pictures=(scene,),
    )  # fmt: skip
    saved: list[str] = []

    def save(_: Any, name: str) -> str:
        saved.append(name)
        return f"run/{name}"

    entries = light_samples.run(plan, tmp_path / "jobs", lambda _: None, save)
    assert {e["section"] for e in entries} == {"light-samples"}
    assert [e.get("part") for e in entries] == ["truth", None, None, "picture"]
    assert all(e["status"] == "ok" for e in entries), entries
    centred, jittered = entries[1], entries[2]
    for entry in (centred, jittered):
        assert [p["samples"] for p in entry["points"]] == [1, 2]
        assert all(p["wall"] > 0 and p["error"]["rmse"] >= 0 for p in entry["points"])
        assert all(len(p["walls"]) == 2 for p in entry["points"])  # repeat=2, median kept
    # a single centred cell is a hard shadow: it cannot reach the soft truth
    assert centred["points"][1]["error"]["rmse"] > 0
    assert "light-truth.png" in saved and "light-2x2-jittered-1spp.png" in saved
    assert "picture-soft.png" in saved
    gallery = [b for b in light_samples_report.blocks({"series": entries}, None, "") if
               isinstance(b, Gallery)]  # fmt: skip
    assert len(gallery[0].rows) == 3
    assert gallery[1].rows[0][1][0] is not None  # the bonus picture
