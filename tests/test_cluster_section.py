"""``rtc bench --sections cluster`` (``harness.sections.cluster.measure``,
``harness.sections.cluster.report``) and ``--sweep-on`` (``harness.engine.cluster_jobs``): the
section measures every configuration, the pictures agree, the report judges the issue's target from
the figures; jobs run on a local cluster come back as they would from this machine."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from groundwork.sizes import Size
from harness.document.model import Para, Table
from harness.engine.bench import series_task
from harness.engine.cluster_jobs import cluster_jobs, cluster_options
from harness.scenery.presets import resolve_scene
from harness.sections.cluster import measure as cluster
from harness.sections.cluster import report as cluster_report
from rtc.cli import main

pytest.importorskip("distributed")  # a declared dependency: always there in CI


@pytest.mark.parametrize(
    ("per_sample", "least", "chosen"), [(0.5, 1, 12), (10.0, 1, 1), (0.5, 20, 20), (0.0, 1, 4096)]
)
def test_the_samples_make_a_render_of_the_target_length(
    per_sample: float, least: int, chosen: int
) -> None:
    assert cluster._chosen_samples(per_sample, 6.0, least) == chosen


@pytest.mark.slow
def test_the_section_measures_every_configuration_and_the_pictures_agree(tmp_path: Path) -> None:
    plan = cluster.Plan(
        scene=resolve_scene("reference"),
        size=Size(24, 18),
        repeat=1,
        target=0.05,
        configs=("numba[threads=1]", "dask[workers=1,tile=8]:numba[threads=1]"),
    )
    logged: list[str] = []
    [entry] = cluster.run(plan, tmp_path / "jobs", logged.append)
    assert entry["status"] == "ok" and len(logged) == 2
    first, dask = entry["points"]
    assert "error" not in first and "error" not in dask, entry
    assert first["samples"] == dask["samples"] == entry["samples"] >= 1
    assert dask["tiles"] == 9 and dask["session"] > 0 and dask["startup"] >= dask["session"]
    assert dask["difference"]["max_abs"] == 0  # a cluster never changes a pixel
    assert all(p["rays_per_second"] > 0 and len(p["cpu"]) == 1 for p in (first, dask))


def _point(variant: str, seconds: float, **extra: Any) -> dict[str, Any]:
    return {
        "variant": variant, "render": [seconds], "render_median": seconds, "cpu": [1.0],
        "startup": 0.1, "rays_per_second": 1000 / seconds, **extra,
    }  # fmt: skip


def _run(points: list[dict[str, Any]]) -> dict[str, Any]:
    entry = {"section": "cluster", "name": "cluster", "status": "ok", "scene": "reference",
             "size": [64, 48], "samples": 10, "points": points}  # fmt: skip
    return {"series": [entry], "machine": {"cores_available": 2}, "settings": {"repeat": 3}}


@pytest.mark.parametrize(("two", "met"), [(5.5, True), (6.5, False)])
def test_the_report_judges_two_workers_against_one(two: float, met: bool) -> None:
    run = _run(
        [
            _point("numba[threads=1]", 9.0),
            _point("numba[threads=2]", 5.0),
            _point("dask[workers=1]:numba[threads=1]", 10.0, tiles=100, tile=32, session=0.8),
            _point("dask[workers=2]:numba[threads=1]", two, tiles=100, tile=32, session=0.9),
        ]
    )
    entry = cluster_report.entries(run)[0]
    assert cluster_report.per_tile(entry) == pytest.approx(0.01)
    assert cluster_report.speedups(entry)["workers"] == pytest.approx(10.0 / two)
    text = cluster_report.verdict(entry)
    assert ("meets" in text) is met and ("misses" in text) is not met
    blocks = cluster_report.blocks(run, None, "machine line")
    assert any(isinstance(b, Table) for b in blocks)
    assert any(isinstance(b, Para) and "10.0 ms per 32x32 tile" in b.text for b in blocks)
    assert cluster_report.console_lines(run)[-1].endswith(text)


def test_a_failed_configuration_is_a_row_and_no_verdict() -> None:
    run = _run([_point("numba[threads=1]", 9.0), {"variant": "dask[workers=2]:numba[threads=1]",
                                                  "error": "boom"}])  # fmt: skip
    entry = cluster_report.entries(run)[0]
    assert "could not be judged" in cluster_report.verdict(entry)
    assert any("failed: boom" in line for line in cluster_report.console_lines(run))


@pytest.mark.parametrize(
    ("text", "words"),
    [("numba", "not a cluster"), ("dask:numba", "not a cluster"),
     ("dask[scheduler=nowhere]", "not an address"), ("dask[", "bad variant name")],
)  # fmt: skip
def test_a_bad_cluster_spelling_is_a_value_error(text: str, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        cluster_options(text)


def test_jobs_on_a_local_cluster_come_back_with_their_pictures(tmp_path: Path) -> None:
    scene = resolve_scene("reference")
    task = series_task([(Size(8, 6), 1), (Size(8, 6), 2)], None)
    jobs = [
        (tmp_path / f"{n:03d}", {"variant": name, "scene": scene.as_dict(), "depth": 5,
                                 "seed": 0, "epsilon": None, "threads": 1, "tasks": [task]})
        for n, name in enumerate(["numba[threads=1]", "no-such-variant"])
    ]  # fmt: skip
    with cluster_jobs("dask[workers=2]") as run:
        good, bad = run(jobs)
    assert good.ok and not bad.ok and "no-such-variant" in bad.result["error"]
    points = good.result["tasks"][0]["points"]
    assert [p["samples"] for p in points] == [1, 2]
    assert good.image(points[1]["image"]).shape[:2] == (6, 8)


def test_sweep_on_an_unreachable_scheduler_stops_before_measuring(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["bench", "--sweep-on", "dask[scheduler=tcp://127.0.0.1:9]",
                 "--sections", "sweep", "--results-dir", str(tmp_path)])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "--sweep-on" in err and "refused" in err.lower()
    assert not (tmp_path / "runs").exists()


def test_the_plot_draws_every_measured_configuration(tmp_path: Path) -> None:
    from PIL import Image

    from harness.sections.cluster.plot import plot as cluster_plot

    run = _run([_point("numba[threads=1]", 9.0), _point("dask[workers=2]:numba[threads=1]", 5.0)])
    run["machine"].update(cpu_model="a CPU", python="3.11")
    path = cluster_plot(run, tmp_path / "cluster.png")
    assert path is not None and Image.open(path).size[0] > 400
    assert cluster_plot(_run([{"variant": "numba", "error": "boom"}]), tmp_path / "x.png") is None


def test_a_cost_per_tile_below_zero_is_called_noise() -> None:
    run = _run(
        [
            _point("numba[threads=1]", 9.0),
            _point("dask[workers=1]:numba[threads=1]", 8.9, tiles=100, tile=32, session=0.8),
        ]
    )
    text = " ".join(b.text for b in cluster_report.blocks(run, None, "m") if isinstance(b, Para))
    assert "no cost per 32x32 tile that the renders tell apart from their noise" in text


def test_sweep_on_without_the_sweep_section_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["bench", "--sections", "cluster", "--sweep-on", "dask[workers=2]",
                 "--results-dir", str(tmp_path)])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "the sweep is not among --sections" in err and err.count("\n") == 1
    assert not (tmp_path / "runs").exists()
