"""``rtc bench --sections scene-size`` (``harness.sections.scene_size.measure``): the plan, the skip
rule, the fitted slopes, one tiny run in fresh processes, and its report section and plot."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from groundwork.sizes import Size
from harness.document.model import Picture, Table, to_markdown
from harness.sections import DEFAULTS as DEFAULT_SECTIONS
from harness.sections import NAMES as SECTIONS
from harness.sections import QUICK_DEFAULTS
from harness.sections.scene_size import plot as scene_size_plot
from harness.sections.scene_size import report as scene_size_report
from harness.sections.scene_size.measure import (
    COMMAND_SECTION,
    PARSE_SECTION,
    SECTION,
    Plan,
    mesh_names,
    predicted_render,
    run,
    scene_text,
    slope,
)
from rtc.cli import UserError, build_parser
from rtc.cmd_bench import settings_from

# --- the plan ------------------------------------------------------------------------------


def test_mesh_names_read_sizes_names_and_all_smallest_first() -> None:
    assert mesh_names("10k,1k") == ("ring-1k.obj", "ring-10k.obj")
    assert mesh_names("1M, ring-100k.obj,1m") == ("ring-100k.obj", "ring-1m.obj")
    assert mesh_names("all") == ("ring-1k.obj", "ring-10k.obj", "ring-100k.obj", "ring-1m.obj")
    assert mesh_names("knot-23k.obj,1k") == ("ring-1k.obj", "knot-23k.obj")


@pytest.mark.parametrize("text", ["3k", "teapot.obj", "", " , "])
def test_an_unknown_or_missing_mesh_is_refused_with_the_choices(text: str) -> None:
    with pytest.raises(ValueError, match=r"1k, 10k, 100k, 1m|no mesh chosen"):
        mesh_names(text)


def test_the_scene_names_its_mesh_beside_it_at_the_size_asked() -> None:
    text = scene_text("ring-10k.obj", Size(160, 120))
    assert "file: ring-10k.obj" in text and "width: 160" in text and "height: 120" in text


def test_a_render_is_predicted_linearly_from_the_largest_point_measured() -> None:
    assert predicted_render([], 1000) is None
    points = [
        {"triangles": 1000, "render": [0.1], "render_median": 0.1},
        {"triangles": 10_000, "render": [0.4, 0.5, 0.6], "render_median": 0.5},
        {"triangles": 100_000, "skipped": "over the budget"},
    ]
    assert predicted_render(points, 100_000) == pytest.approx(5.0)


def test_slope_is_the_exponent_of_a_power_law() -> None:
    assert slope([(x, 3 * x**0.5) for x in (1e3, 1e4, 1e5, 1e6)]) == pytest.approx(0.5)
    assert slope([(x, 0.01) for x in (1e3, 1e6)]) == pytest.approx(0.0)
    assert slope([(1e3, 1.0), (1e4, 10.0)]) == pytest.approx(1.0)
    assert slope([(1e3, 1.0)]) is None
    assert slope([(1e3, 1.0), (1e3, 2.0)]) is None


# --- the command line --------------------------------------------------------------------------


def bench_args(*extra: str) -> Any:
    return build_parser(["bench"]).parse_args(["bench", *extra])


def test_the_default_bench_leaves_the_scene_size_section_out() -> None:
    assert "scene-size" in SECTIONS and "scene-size" not in DEFAULT_SECTIONS
    assert settings_from(bench_args()).sections == QUICK_DEFAULTS == ("ladder",)  # quick
    settings = settings_from(bench_args("--variants", "naive"))
    assert settings.sections == ("table", "ladder")  # variants named: their table rows too
    assert settings_from(bench_args("--variants", "naive", "--full")).sections == DEFAULT_SECTIONS
    assert settings.mesh_variants == ("numba", "numba[bvh=off]")
    assert settings.meshes == ("ring-1k.obj", "ring-10k.obj", "ring-100k.obj", "ring-1m.obj")


def test_the_scene_size_options_reach_the_settings() -> None:
    settings = settings_from(
        bench_args("--variants", "naive", "--sections", "scene-size", "--meshes", "1k,10k",
                   "--mesh-variants", "cached,numba[threads=1]")
    )  # fmt: skip
    assert settings.sections == ("scene-size",)
    assert settings.meshes == ("ring-1k.obj", "ring-10k.obj")
    assert settings.mesh_variants == ("cached", "numba[threads=1]")
    assert list(settings.as_dict()["meshes"]) == ["ring-1k.obj", "ring-10k.obj"]


@pytest.mark.parametrize(
    ("flag", "value", "message"),
    [
        ("--meshes", "2k", "--meshes: unknown mesh '2k'"),
        ("--mesh-variants", "numba[", "--mesh-variants: "),
        ("--mesh-variants", ",", "--mesh-variants: name at least one variant"),
    ],
)
def test_bad_scene_size_options_are_one_user_error(flag: str, value: str, message: str) -> None:
    with pytest.raises(UserError, match=message.replace("[", r"\[")):
        settings_from(bench_args("--variants", "naive", flag, value))


# --- a tiny run, in fresh processes ---------------------------------------------------------------


def test_a_tiny_run_measures_each_phase_and_records_what_could_not_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # relative folders, as rtc bench gives them (results/runs/...)
    plan = Plan(
        variants=("cached", "numba[nosuchoption=1]"),
        meshes=("ring-1k.obj",),
        size=Size(4, 3),
        repeat=2,
        folder=Path("meshes"),
    )
    logged: list[str] = []
    saved: dict[str, Any] = {}

    def save(image: Any, name: str) -> str:
        saved[name] = image
        return f"run/{name}"

    parse, cached, unavailable, anchored, commands = run(plan, Path("jobs"), logged.append, save)
    assert (tmp_path / "meshes" / "ring-1k.obj").is_file()
    assert parse["section"] == PARSE_SECTION
    (parsed,) = parse["points"]
    assert parsed["parsed_triangles"] == 1000 and parsed["degenerate"] == 0
    assert len(parsed["parse"]) == 2 and parsed["tracemalloc"]["current"] > 1000 * 100
    assert parsed["arrays_triangles"] == 1000 and len(parsed["arrays"]) == 2  # read_mesh
    # whole commands: ours, and POV-Ray's when it is installed (else the entry says why)
    assert commands["section"] == COMMAND_SECTION and commands["status"] == "ok"
    (command,) = commands["points"]
    assert command["ours"]["wall"] > 0 and command["ours"]["peak"] > 1 << 20
    assert len(command["ours"]["walls"]) == 2
    if commands["povray"] is None:
        assert "povray" not in command and "POV-Ray" in commands["povray_missing"]
    else:
        assert command["povray"]["wall"] > 0 and command["povray"]["peak"] > 1 << 20
    assert (tmp_path / "jobs" / "commands" / "ring-1k.yml").is_file()
    # Embree's primary rays on the same mesh and camera when embreex is installed (the gate
    # installs it: tests/test_embree_anchor.py), else the entry says why
    assert anchored["section"] == "scene-size-embree"
    if anchored["status"] == "ok":
        (rays,) = anchored["points"]
        assert rays["mesh"] == "ring-1k.obj" and rays["rays"] == 12 and len(rays["seconds"]) == 2
    else:
        assert anchored["points"] == [] and "embreex" in anchored["error"]
    assert cached["section"] == SECTION and cached["status"] == "ok"
    (point,) = cached["points"]
    assert point["primitives"] == 1001  # the floor and the ring's triangles
    assert point["load"] > 0 and point["prepare"] >= 0 and len(point["render"]) == 2
    assert point["image"] == "run/scene-size-cached-ring-1k.png"
    assert saved["scene-size-cached-ring-1k.png"].shape == (3, 4, 3)
    assert unavailable["status"] == "unavailable" and "nosuchoption" in unavailable["error"]
    assert any("not run" in line for line in logged)


# --- the report ----------------------------------------------------------------------------


def synthetic_run() -> dict[str, Any]:
    """A run file's ``rtc`` part with this section: numba grows as triangles^0.1, the flat
    loop linearly until the budget stops it."""

    def point(triangles: int, render: float, **extra: Any) -> dict[str, Any]:
        return {
            "mesh": f"ring-{triangles}.obj", "triangles": triangles, "load": triangles * 6e-6,
            "load_rss": triangles * 700, "prepare": triangles * 1e-5, "render": [render] * 3,
            "render_median": render, "cpu": [1.9, 1.8, 1.9], **extra,
        }  # fmt: skip

    bvh = {"structure": "sah", "seconds": 0.01, "depth": 12}
    return {
        "settings": {
            "size": [160, 120],
            "samples": 1,
            "depth": 5,
            "threads": None,
            "repeat": 3,
            "budget": 60.0,
        },
        "machine": {"cpu_model": "a CPU", "cores_available": 2, "python": "3.11"},
        "series": [
            {
                "section": PARSE_SECTION,
                "name": "parse_obj_file",
                "status": "ok",
                "points": [
                    {
                        "mesh": "ring-1k.obj",
                        "triangles": 1000,
                        "bytes": 28000,
                        "parse": [0.006],
                        "parse_median": 0.006,
                        "rss_growth": 850_000,
                        "tracemalloc": {"current": 674_000, "peak": 790_000},
                    },
                ],
            },
            {
                "section": SECTION,
                "name": "numba",
                "status": "ok",
                "points": [
                    point(n, 0.004 * (n / 1000) ** 0.1, hierarchy=bvh) for n in (1000, 10**4, 10**5)
                ],
            },
            {
                "section": SECTION,
                "name": "numba[bvh=off]",
                "status": "ok",
                "points": [
                    point(
                        1000,
                        0.2,
                        difference={"against": "numba", "max_abs": 0.0, "pixels_over_one_step": 0},
                    ),
                    point(10**4, 2.0),
                    {"mesh": "ring-100k.obj", "triangles": 10**5, "skipped": "over the budget"},
                ],
            },
            {
                "section": SECTION,
                "name": "numba[bvh=sah2]",
                "status": "unavailable",
                "error": "no option",
                "points": [],
            },
            {
                "section": COMMAND_SECTION,
                "name": "numba",
                "status": "ok",
                "threads": 2,
                "povray": "POV-Ray 3.7.0",
                "points": [
                    {
                        "mesh": "ring-1k.obj",
                        "triangles": 1000,
                        "ours": {"wall": 0.5, "cpu": 0.6, "peak": 50 << 20, "walls": [0.5]},
                        "povray": {
                            "wall": 1.0,
                            "cpu": 1.1,
                            "peak": 25 << 20,
                            "parse": 0.1,
                            "trace": 0.2,
                            "walls": [1.0],
                        },
                    },
                ],
            },
        ],
    }


def test_the_slopes_tell_a_hierarchy_from_a_flat_loop() -> None:
    numba, flat, _ = scene_size_report.entries(synthetic_run())
    assert scene_size_report.slopes(numba)["render"] == pytest.approx(0.1)
    assert scene_size_report.slopes(flat)["render"] == pytest.approx(1.0)
    assert scene_size_report.slopes(numba)["load"] == pytest.approx(1.0)


def test_the_report_section_has_the_table_the_slopes_and_the_parse_figures() -> None:
    blocks = scene_size_report.blocks(synthetic_run(), "report/t.png", "Measured on a VM.")
    text = to_markdown(blocks)
    assert "## Cost against scene size" in text and "Measured on a VM." in text
    assert any(isinstance(b, Picture) and b.path == "report/t.png" for b in blocks)
    tables = [b for b in blocks if isinstance(b, Table)]
    assert "### Whole commands beside POV-Ray" in text
    (command,) = tables[0].rows
    assert command[-2:] == ["0.50x", "2.00x"]  # time and memory, ours over POV-Ray's
    assert "POV-Ray 3.7.0 on the same scene" in text
    slopes = {row[0]: row[2] for row in tables[2].rows}
    assert slopes == {"`numba`": "0.10", "`numba[bvh=off]`": "1.00"}
    assert "skipped: over the budget" in text and "identical to `numba`" in text
    assert "not run: no option" in text
    assert "10.0 ms (sah, depth 12)" in text
    assert "674 B/tri" in text and "6.00" in text  # tracemalloc per triangle, µs per triangle
    lines = scene_size_report.console_lines(synthetic_run())
    assert any("slopes: render 0.10" in line for line in lines)


def test_a_run_without_the_section_adds_nothing() -> None:
    empty = {"settings": {}, "series": [{"section": "sizes", "name": "x", "points": []}]}
    assert scene_size_report.blocks(empty, None, "") == []
    assert not scene_size_report.has_section(empty)


def test_the_plot_is_a_png_with_one_line_per_variant(tmp_path: Path) -> None:
    path = scene_size_plot.plot(synthetic_run(), tmp_path / "t.png")
    assert path == tmp_path / "t.png"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.png"]  # written atomically, nothing left
    assert scene_size_plot.plot({"series": []}, tmp_path / "none.png") is None
    assert not (tmp_path / "none.png").exists()
    assert math.isfinite(path.stat().st_size)


def test_rtc_bench_records_the_section_and_rtc_report_draws_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from harness.engine.results import list_runs, load_run
    from rtc.cli import main

    results = tmp_path / "results"
    status = main(
        ["bench", "--sections", "scene-size", "--meshes", "1k", "--mesh-variants", "cached",
         "--size", "4x3", "--repeat", "1", "--variants", "naive", "--results-dir", str(results)]
    )  # fmt: skip
    out, _ = capsys.readouterr()
    assert status == 0 and "cached" in out and "slopes: render -" in out
    (path,) = list_runs(results)
    document = load_run(path)
    import pyperf

    names = pyperf.BenchmarkSuite.load(str(path)).get_benchmark_names()
    assert names == ["scene-size cached ring-1k.obj"]
    series = document["rtc"]["series"]
    assert [e["section"] for e in series] == [
        PARSE_SECTION, SECTION, "scene-size-embree", COMMAND_SECTION,
    ]  # fmt: skip
    assert main(["report", "--results-dir", str(results)]) == 0
    readme = (results / "README.md").read_text()
    assert "## Cost against scene size" in readme and "| `cached` | ring-1k.obj |" in readme
    assert "### Whole commands beside POV-Ray" in readme
    assert (results / "report" / "time-vs-triangles.png").is_file()


def test_the_pov_scene_opens_with_comments_povray_can_parse(tmp_path):
    """What POV-Ray reads before ``#version``: comment lines only (checked without POV-Ray,
    which CI does not have; its parser stops at anything else)."""
    from harness.sections.scene_size.measure import pov_scene

    mesh = tmp_path / "tri.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    text = pov_scene(mesh, Size(8, 6), tmp_path / "tri.pov").read_text()
    head = text.split("#version 3.7;")[0].splitlines()
    assert head and all(line.startswith("//") for line in head)
    assert "vertex_vectors { 3," in text and "face_indices { 1," in text
