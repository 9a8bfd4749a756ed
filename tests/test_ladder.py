"""The report's "Step by step" (``harness.sections.ladder.report``) from made-up run files: each
step's own factor over the step it builds on and its factor over naive (per pixel, across sizes),
the error it adds, the advice computed from the rows, the POV-Ray anchor present or said to be
absent, and the section opening the report with its plot and the links to the others."""

from __future__ import annotations

from typing import Any

import pytest

from harness.document.model import Table, to_markdown
from harness.report.build import build_report
from harness.sections.ladder import measure as ladder
from harness.sections.ladder import report as ladder_report

IDENTICAL = {"max_abs": 0.0, "mean_abs": 0.0, "rmse": 0.0, "psnr": None,
             "pixels_over_one_step": 0, "pixels": 300}  # fmt: skip


def _step(name: str, over: str | None, seconds: float, size=(160, 120), *, runs_on="Python",
          error: dict | None = None, option: bool = False, **extra: Any) -> dict:  # fmt: skip
    row = {
        "section": "ladder", "name": name, "step": name.replace("[workers=2]", ""),
        "scene": "reference", "status": "ok",
        "size": list(size), "samples": 1, "wall": [seconds] * 3, "cpu": [seconds] * 3,
        "cores": 2, "over": over, "change": f"what {name} changes", "runs_on": runs_on,
        "option": option, "compare_size": [20, 15],
        "allocations": {"count": 3000, "bytes": 1, "method": "counter"},
        "error_vs_over": None if over is None else {
            **(error or IDENTICAL), "size": "x".join(map(str, size)), "against": over},
    }  # fmt: skip
    row.update(extra)
    return row


FLOAT32 = {"max_abs": 0.02, "mean_abs": 1e-4, "rmse": 1e-3, "psnr": 60.0,
           "pixels_over_one_step": 12, "pixels": 307200}  # fmt: skip


def _run(anchor: dict | None = None, stem: str = "bench-20990101T000000000Z-aaaaaa") -> dict:
    # fmt: off
    rows = [
        _step("naive", None, 1.0, (10, 10)),  # 10 ms per pixel
        _step("cached", "naive", 0.3, (10, 10)),  # 3 ms: 3.33x
        _step("prealloc", "cached", 1.0, (100, 100)),  # 100 µs: 30x over cached
        _step("pooled[workers=2]:prealloc", "prealloc", 0.5, (100, 100)),  # 50 µs: 2x
        _step("numba", "pooled[workers=2]:prealloc", 0.3072, (640, 480), runs_on="numba"),  # 1 µs
        _step("wavefront", "prealloc", 3.072, (640, 480), runs_on="NumPy"),  # 10 µs: 10x
        _step("numba[float32]", "numba", 0.2048, (640, 480), runs_on="numba", option=True,
              error=FLOAT32),
        {"section": "ladder", "name": "numba[fastmath]", "scene": "reference",
         "status": "unavailable", "error": "no such option here", "over": "numba"},
    ]
    # fmt: on
    return {
        "stem": stem,
        "started": "2099-01-01T00:00:00",
        "seconds": 60.0,
        "machine": {
            "hostname": "box",
            "cpu_model": "a CPU",
            "cpu_count": 2,
            "cores_available": 2,
            "python": "3.11",
        },
        "settings": {
            "size": [160, 120],
            "samples": 1,
            "depth": 5,
            "seed": 0,
            "repeat": 3,
            "budget": 6.0,
            "threads": None,
            "scene": {"name": "reference"},
            "mode": {"name": "quick"},
        },
        "rows": rows,
        "series": [anchor] if anchor else [],
        "compare_size": [20, 15],
    }  # fmt: skip


POVRAY = {
    "section": "ladder", "part": "anchor", "name": "POV-Ray", "anchor": "povray", "status": "ok",
    "version": "POV-Ray 3.7.0.10", "file": "reference.pov", "scene": "reference",
    "points": [{"size": [640, 480], "samples": 1, "threads": 2, "wall": 0.6144,
                "cpu": 1.0, "trace": 0.3072, "walls": [0.6144]}],
    "difference": {**FLOAT32, "psnr": 30.5, "size": "640x480", "against": "numba"},
    "where": {"pixels_off": 39000, "pixels": 307200, "box": [150, 115, 330, 300]},
}  # fmt: skip


def _cells(table: Table, name: str) -> list[str]:
    return next(row for row in table.rows if row[0] == name)


def test_each_step_has_its_own_factor_and_its_factor_over_naive_per_pixel():
    run = _run()
    found = ladder_report.rows(run)
    by_name = {r["name"]: r for r in found}
    assert ladder_report.own_factor(by_name["cached"], found) == pytest.approx(10 / 3)
    assert ladder_report.own_factor(by_name["prealloc"], found) == pytest.approx(30)
    assert ladder_report.cumulative(by_name["numba"], found) == pytest.approx(10_000)
    assert ladder_report.own_factor(by_name["wavefront"], found) == pytest.approx(10)
    assert ladder_report.own_factor(by_name["naive"], found) is None
    table = ladder_report.table(run)
    assert _cells(table, "`numba`")[3] == "50x (`pooled:prealloc`)"
    assert _cells(table, "`numba`")[4] == "10,000x"
    assert _cells(table, "`numba`")[2] == "1\u00a0µs\u00a0(640x480)\u00a0**busy**"
    assert _cells(table, "`numba[float32]`")[5] == "PSNR 60.0 dB, 12 px off (640x480)"
    assert _cells(table, "`cached`")[5] == "identical (10x10)"
    assert _cells(table, "`pooled:prealloc`")  # the step's own spelling, not the canonical
    assert all("fastmath" not in row[0] for row in table.rows)  # unavailable: in the notes


def test_a_step_is_exact_only_when_no_step_before_it_added_error():
    run = _run()
    run["rows"][2]["error_vs_over"] = {**FLOAT32, "size": "20x15", "against": "cached"}
    found = ladder_report.rows(run)
    by_name = {r["name"]: r for r in found}
    assert ladder_report.exact(by_name["cached"], found)
    assert not ladder_report.exact(by_name["numba"], found)  # prealloc, below it, differs


def test_the_advice_is_computed_from_the_rows():
    text = ladder_report.advice(_run())
    assert text.startswith("**Advice from this run: use `numba` for the book's scenes (10,000x")
    assert "without a compiler, `wavefront` (1,000x, NumPy only)" in text
    assert "to learn from, `prealloc`: one change, 30x over `cached` in plain Python" in text
    assert "the options run at `numba[float32]` 1.5x `numba`'s speed, with the error shown" in text
    assert text.endswith(".**")
    slow = _run()
    slow["rows"][4]["wall"] = [30.72] * 3  # numba now slower than wavefront
    assert "use `wavefront`" in ladder_report.advice(slow)


def test_povray_stands_beside_the_steps_when_the_run_had_it():
    table = ladder_report.table(_run(POVRAY))
    (row,) = [r for r in table.rows if r[0].startswith("POV-Ray")]
    assert row[0] == "POV-Ray 3.7, 2 threads"
    assert row[2].startswith("2\u00a0µs")  # 0.6144 s over 640x480, whole process
    assert "(640x480;\u00a0trace\u00a01\u00a0µs)" in row[2]
    assert row[4] == "5,000x"  # naive's 10 ms per pixel over 2 µs
    assert row[5] == "PSNR 30.5 dB vs `numba` (640x480)"
    text = to_markdown(ladder_report.blocks(_run(POVRAY), None))
    assert "x 150-330, y 115-300" in text
    assert "†" in row[2] and "POV-Ray (its start-up, parsing and writing: 50% of" in text
    assert "No C++ anchor" not in text


def test_without_povray_the_rows_are_absent_and_a_note_says_why():
    missing = {
        "section": "ladder",
        "part": "anchor",
        "name": "POV-Ray",
        "anchor": "povray",
        "status": "unavailable",
        "error": "POV-Ray is not installed",
        "points": [],
    }
    table = ladder_report.table(_run(missing))
    assert not [r for r in table.rows if r[0].startswith("POV-Ray")]
    text = to_markdown(ladder_report.blocks(_run(missing), None))
    assert "**No C++ anchor in this run:** POV-Ray is not installed." in text


def test_the_go_write_up_is_cited_with_its_machine_not_measured():
    text = to_markdown(ladder_report.go_blocks())
    assert "Cited, not measured here" in text and "4-core/8-thread" in text
    assert "| naive, single-threaded | 3 min 15 s | - | 1x |" in text
    assert "| cached inverse | 4.5 s | 20x | 43.3x |" in text


def test_the_steps_are_in_the_seeds_order_each_over_one_before_it():
    names = [step.variant for step in ladder.STEPS]
    assert names[:4] == ["naive", "cached", "prealloc", "pooled:prealloc"]
    for index, step in enumerate(ladder.STEPS[1:], start=1):
        assert step.over in names[:index]
    assert all(step.large for step in ladder.STEPS if step.runs_on in ("numba", "NumPy"))


def test_the_report_opens_with_the_ladder_its_advice_plot_and_links(tmp_path):
    import json

    runs = tmp_path / "runs"
    runs.mkdir()
    run = _run(POVRAY)
    (runs / f"{run['stem']}.json").write_text(json.dumps({"rtc": {"schema_version": 2, **run}}))
    readme, page, problems = build_report(tmp_path)
    assert problems == []
    text = readme.read_text(encoding="utf-8")
    top = text.split("\n## ")[1]
    assert top.startswith("Step by step")
    assert (
        top.index("| `naive` |") < top.index("**Advice from this run:") < top.index("![the ladder")
    )
    assert "See also: [" in top and "(#history)" in top
    assert (tmp_path / "report" / "ladder.png").is_file()
    html = page.read_text(encoding="utf-8")
    assert '<h2 id="step-by-step">' in html and '<h2 id="history">' in html


def test_a_step_whose_fixed_costs_dominate_is_marked_with_a_note():
    run = _run()
    run["rows"][3]["probe"] = {"fixed": 0.3, "per_pixel": 2e-5}  # the pool: 0.3 of 0.5 s
    table = ladder_report.table(run)
    assert "†" in _cells(table, "`pooled:prealloc`")[2]
    assert "†" not in _cells(table, "`prealloc`")[2]
    text = to_markdown(ladder_report.blocks(run, None))
    assert "† `pooled:prealloc`: fixed costs" in text


def test_the_steps_that_add_error_show_where():
    run = _run()
    run["rows"][6]["heatmap_over"] = "bench-x/ladder-numba-float32-over-diff.png"
    text = to_markdown(ladder_report.blocks(run, None))
    assert "| `numba[float32]` against `numba` (640x480): PSNR 60.0 dB" in text
    assert "ladder-numba-float32-over-diff.png" in text
    assert text.count("-over-diff.png") == 1  # the exact steps have none


def test_a_partial_run_adds_to_the_report_and_never_replaces_the_fuller_ladder(tmp_path):
    """The README's learner command, ``rtc bench --variants mine,naive``, then ``rtc report``:
    the ladder, the Summary and the README's figures stay the whole run's; the partial run's
    rows follow the ladder, named."""
    import json

    from harness.report import choice, readme_figures

    whole = _run(POVRAY)
    partial = _run(stem="bench-20990102T000000000Z-bbbbbb")
    partial["started"] = "2099-01-02T00:00:00"
    partial["settings"] = {**partial["settings"], "variants_asked": "naive,mine"}
    partial["rows"] = [_step("naive", None, 1.1, (10, 10)), _step("mine", "naive", 0.5, (10, 10))]
    runs = tmp_path / "runs"
    runs.mkdir()
    for run in (whole, partial):
        document = {"rtc": {"schema_version": 2, **run}}
        (runs / f"{run['stem']}.json").write_text(json.dumps(document))
    assert choice.partial(whole) is None and choice.partial(partial) == "--variants naive,mine"
    assert choice.shown("ladder", [whole, partial]) is whole
    assert choice.newer_partial("ladder", [whole, partial]) is partial
    assert choice.shown("ladder", [partial]) is partial  # only partial runs: the newest
    assert readme_figures.block([whole, partial]) == readme_figures.block([whole])
    readme, _, problems = build_report(tmp_path)
    assert problems == []
    ladder_text = readme.read_text(encoding="utf-8").split("\n## ")[1]
    assert "`numba[float32]`" in ladder_text  # the whole run's steps
    assert f"Added by a newer run over part of the variants, `{partial['stem']}`" in ladder_text
    assert "| `mine` |" in ladder_text


def test_the_projects_readme_and_committed_report_change_only_when_published(
    tmp_path, monkeypatch
):
    """``rtc report`` writes your own report, ``results/local/`` by default; the committed
    ``results/`` and the README's figures only with ``--publish``."""
    import json

    from harness.report import readme_figures
    from rtc.cli import main

    monkeypatch.chdir(tmp_path)
    readme = tmp_path / "README.md"
    readme.write_text(f"intro\n{readme_figures.START}\nold\n{readme_figures.END}\n")
    run = _run(POVRAY)
    for folder in (tmp_path / "results" / "runs", tmp_path / "results" / "local" / "runs"):
        folder.mkdir(parents=True)
        (folder / f"{run['stem']}.json").write_text(json.dumps({"rtc": {"schema_version": 2,
                                                                        **run}}))  # fmt: skip
    assert main(["report"]) == 0
    assert (tmp_path / "results" / "local" / "README.md").is_file()
    assert not (tmp_path / "results" / "README.md").exists()
    assert "\nold\n" in readme.read_text()  # untouched
    assert main(["report", "--publish"]) == 0
    assert (tmp_path / "results" / "README.md").is_file()
    assert readme_figures.quoted(readme.read_text()) == readme_figures.block([run])
    assert main(["report", "--publish", "--results-dir", "elsewhere"]) == 2
