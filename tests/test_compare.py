"""Runs compared (``rtc compare``, ``harness.report.compare``), the history across runs and the
opt-in performance gate (``rtc bench --compare-to RUN --fail-slower PCT``)."""

from __future__ import annotations

import json
import random
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from pyperf._utils import is_significant  # the test pyperf compare_to applies

from harness.engine.results import pyperf_document, runs_dir, write_new_file
from harness.report import compare, plots
from harness.report.build import _history_blocks
from harness.report.compare import compare_runs, history, parse_percent, t_test
from rtc.cli import main

# ------------------------------------------------------------------ the t-test


def _normal(mean: float, sd: float, n: int, seed: int) -> list[float]:
    rng = random.Random(seed)
    return [rng.gauss(mean, sd) for _ in range(n)]


def test_clearly_different_walls_are_significant_and_the_sign_says_which_is_slower():
    a = _normal(1.00, 0.01, 5, seed=1)
    b = _normal(1.30, 0.01, 5, seed=2)
    slower = t_test(a, b)
    assert slower.significant and slower.p is not None and slower.p < 1e-6
    assert slower.t is not None and slower.t > 0  # b is the slower
    faster = t_test(b, a)
    assert faster.significant and faster.t is not None and faster.t < 0


def test_walls_from_one_distribution_are_not_significant():
    rng = random.Random(7)
    not_significant = 0
    for _ in range(200):
        a = [rng.gauss(1.0, 0.05) for _ in range(5)]
        b = [rng.gauss(1.0, 0.05) for _ in range(5)]
        not_significant += not t_test(a, b).significant
    # at the 95% level about 5% of same-distribution pairs come out significant
    assert 180 <= not_significant <= 198


def test_the_t_score_and_the_verdict_are_pyperfs_for_equal_sample_sizes():
    for seed in range(20):
        a = _normal(1.0, 0.05, 4, seed=seed)
        b = _normal(1.05, 0.05, 4, seed=100 + seed)
        ours = t_test(a, b)
        significant, t_score = is_significant(a, b)
        assert ours.t == pytest.approx(-t_score)
        # pyperf uses a table of 95% critical values; at 6 degrees of freedom it is exact
        assert ours.significant == significant


def test_the_p_value_is_the_two_tailed_students_t():
    assert compare.two_tailed_p(2.776, 4) == pytest.approx(0.05, abs=1e-4)
    assert compare.two_tailed_p(12.706, 1) == pytest.approx(0.05, abs=1e-4)
    assert compare.two_tailed_p(0.0, 4) == pytest.approx(1.0)


def test_one_render_on_a_side_is_not_tested_and_no_spread_is_certain():
    assert not t_test([1.0], [2.0, 2.1]).tested
    assert t_test([1.0, 1.0], [2.0, 2.0]).significant  # no spread at all: any gap is real
    assert not t_test([1.0, 1.0], [1.0, 1.0]).significant


# ------------------------------------------------------------------ synthetic run files


def _row(
    name: str, walls: list[float], size: tuple[int, int] = (32, 24), section: str = "table",
    scene: str = "reference", samples: int = 1, psnr: float | None = 60.0,
) -> dict[str, Any]:  # fmt: skip
    error = None
    if name != "naive":
        rmse = 0.0 if psnr is None else 10 ** (-psnr / 20)
        error = {"max_abs": rmse, "mean_abs": rmse, "rmse": rmse, "psnr": psnr,
                 "pixels_over_one_step": 0, "pixels": 300, "size": "20x15"}  # fmt: skip
    return {
        "section": section, "name": name, "scene": scene, "status": "ok",
        "size": list(size), "samples": samples, "wall": walls, "cpu": list(walls),
        "cores": 2, "error_vs_naive": error, "speedup": None,
    }  # fmt: skip


def _run(stem: str, rows: list[dict[str, Any]], cpu: str = "Test CPU", commit: str = "a" * 40):
    return {
        "stem": stem, "started": f"2026-01-0{stem[-1]}T10:00:00", "seconds": 1.0,
        "machine": {"hostname": "box", "cpu_model": cpu, "cores_available": 2, "cpu_count": 2,
                    "commit": commit, "dirty": False},
        "settings": {"scene": {"name": "reference"}, "size": [32, 24], "samples": 1,
                     "depth": 5, "seed": 0, "epsilon": None, "mode": {"name": "quick"}},
        "rows": rows, "series": [],
    }  # fmt: skip


def _base_rows() -> list[dict[str, Any]]:
    return [
        _row("naive", [2.00, 2.02, 1.98], size=(8, 6)),
        _row("cached", [1.00, 1.01, 0.99]),
        _row("numba", [0.010, 0.0101, 0.0099]),
        _row("prealloc", [0.50, 0.51, 0.49], size=(16, 12)),
        _row("robust", [0.70, 0.71, 0.69]),
        _row("numba", [0.20], section="preset", scene="cpp-spheres", samples=8),
    ]


def _slower_rows() -> list[dict[str, Any]]:
    """The base rows again: cached 1.5x slower, numba 1.1x slower (both clearly), prealloc at
    another size, robust gone, a new variant, numba's picture worse."""
    return [
        _row("naive", [2.01, 1.99, 2.00], size=(8, 6)),
        _row("cached", [1.50, 1.51, 1.49]),
        _row("numba", [0.0110, 0.0111, 0.0109], psnr=40.0),
        _row("prealloc", [0.80, 0.81, 0.79], size=(20, 15)),
        _row("numba[float32]", [0.008, 0.0081, 0.0079]),
        _row("numba", [0.40], section="preset", scene="cpp-spheres", samples=8),
    ]


def _write(results: Path, run: dict[str, Any]) -> Path:
    benchmarks = [
        {"name": f"{r['scene']} {r['name']}" + (" [preset]" if r["section"] == "preset" else ""),
         "values": r["wall"], "metadata": {"variant": r["name"]}}
        for r in run["rows"]
    ]  # fmt: skip
    folder = runs_dir(results)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{run['stem']}.json"
    write_new_file(path, json.dumps(pyperf_document(benchmarks, run)))
    return path


@pytest.fixture
def two_runs(tmp_path: Path) -> tuple[Path, Path]:
    first = _write(tmp_path, _run("bench-1", _base_rows()))
    second = _write(tmp_path, _run("bench-2", _slower_rows()))
    return first, second


# ------------------------------------------------------------------ matching rows


def test_rows_match_by_section_scene_variant_size_and_samples():
    comparison = compare_runs(_run("bench-1", _base_rows()), _run("bench-2", _slower_rows()))
    found = {(c.a.key.section, c.a.key.name): c for c in comparison.changes}
    assert set(found) == {("table", "naive"), ("table", "cached"), ("table", "numba"),
                          ("table", "prealloc"), ("preset", "numba")}  # fmt: skip
    assert found["table", "cached"].verdict == "slower"
    assert found["table", "cached"].ratio == pytest.approx(1.5)
    assert found["table", "numba"].verdict == "slower"
    assert found["table", "naive"].verdict == "not significant"
    # the table's numba and the preset's numba are different measurements
    assert found["preset", "numba"].a.key.scene == "cpp-spheres"
    assert found["preset", "numba"].verdict == "not tested"  # one render each
    # another size: per pixel, and never tested
    prealloc = found["table", "prealloc"]
    assert not prealloc.same_size and not prealloc.test.tested
    assert prealloc.ratio == pytest.approx((0.80 / 300) / (0.50 / 192))
    assert [m.key.name for m in comparison.only_a] == ["robust"]
    assert [m.key.name for m in comparison.only_b] == ["numba[float32]"]


def test_the_printed_table_says_the_test_the_verdicts_and_the_image_error_change():
    comparison = compare_runs(_run("bench-1", _base_rows()), _run("bench-2", _slower_rows()))
    text = "\n".join(compare.table_lines(comparison))
    assert "Student's two-sample t-test" in text and "p < 0.05" in text
    lines = text.splitlines()
    cached = next(line for line in lines if line.startswith("cached "))
    assert "1.50x slower" in cached and "slower" in cached.split("p < 0.001")[1]
    numba = next(line for line in lines if line.startswith("numba ") and "reference" in line)
    assert "60.0 -> 40.0 dB" in numba
    assert "5 compared: 2 slower, 0 faster, 1 not significant, 2 not tested" in text
    assert "Only in A: robust (reference)." in text
    # slower rows come first
    assert lines.index(cached) < next(i for i, ln in enumerate(lines) if ln.startswith("naive "))


def test_the_comparison_says_which_run_is_faster_in_words():
    base, slower = _run("bench-1", _base_rows()), _run("bench-2", _slower_rows())
    forward = compare.in_words(compare_runs(base, slower))
    assert forward.startswith("A (bench-1) is faster than B (bench-2): ")
    backward = compare.in_words(compare_runs(slower, base))  # latest previous, previous faster
    assert backward.startswith("B (bench-1) is faster than A (bench-2): ")
    assert "0 significantly faster in B, 2 significantly slower in B" in forward
    lines = compare.table_lines(compare_runs(slower, base))
    assert lines[2] == backward
    cached = next(line for line in lines if line.startswith("cached "))
    assert "B 1.50x faster" in cached  # B took 1/1.5 of A's time
    same = compare.in_words(compare_runs(base, base))
    assert same.startswith("Neither run is faster")


def test_runs_on_two_cpus_or_with_other_settings_say_so():
    b = _run("bench-2", _slower_rows(), cpu="Other CPU")
    b["settings"]["depth"] = 3
    notes = compare_runs(_run("bench-1", _base_rows()), b).notes
    assert any("different machines" in n for n in notes)
    assert any("depth: 5 (A) against 3 (B)" in n for n in notes)


def test_the_gate_picks_significant_slow_downs_over_the_threshold_only():
    comparison = compare_runs(_run("bench-1", _base_rows()), _run("bench-2", _slower_rows()))
    assert [c.a.key.name for c in compare.slower_than(comparison, 25)] == ["cached"]
    assert [c.a.key.name for c in compare.slower_than(comparison, 5)] == ["cached", "numba"]
    assert compare.slower_than(comparison, 60) == []


@pytest.mark.parametrize(("text", "value"), [("25%", 25.0), ("25", 25.0), (" 7.5 % ", 7.5)])
def test_a_percentage_reads_with_or_without_its_sign(text, value):
    assert parse_percent(text) == value


@pytest.mark.parametrize("text", ["abc", "-5%", "nan", "%", "inf"])
def test_a_bad_percentage_is_refused(text):
    with pytest.raises(ValueError, match="expected a percentage"):
        parse_percent(text)


# ------------------------------------------------------------------ the commands


def test_rtc_compare_reads_runs_by_stem_path_and_alias(two_runs, capsys):
    first, second = two_runs
    results = str(first.parent.parent)
    assert main(["compare", "bench-1", str(second), "--results-dir", results]) == 0
    by_name = capsys.readouterr().out
    assert main(["compare", "previous", "latest", "--results-dir", results]) == 0
    assert capsys.readouterr().out == by_name
    assert "A = bench-1" in by_name and "B = bench-2" in by_name
    assert "1.50x slower" in by_name


def test_pyperf_compare_to_still_reads_two_run_files(two_runs):
    first, second = two_runs
    done = subprocess.run(
        [sys.executable, "-m", "pyperf", "compare_to", str(first), str(second)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "reference cached" in done.stdout
    assert "1.50x slower" in done.stdout


def _fake_bench(monkeypatch: pytest.MonkeyPatch, path: Path) -> None:
    """``rtc bench`` without the measuring: its run is the file ``path``."""
    import harness.engine.bench

    monkeypatch.setattr(harness.engine.bench, "run_bench", lambda settings, log, sections: path)


def test_the_gate_exits_1_with_one_line_per_slower_variant(two_runs, monkeypatch, capsys):
    first, second = two_runs
    _fake_bench(monkeypatch, second)
    results = ["--results-dir", str(first.parent.parent), "--variants", "naive"]
    code = main(["bench", *results, "--compare-to", "bench-1", "--fail-slower", "5%"])
    captured = capsys.readouterr()
    assert code == 1
    failures = captured.err.strip().splitlines()
    assert len(failures) == 2
    assert failures[0].startswith("rtc bench: slower: cached (reference, 32x24, 1 spp): 1.50x")
    assert failures[1].startswith("rtc bench: slower: numba (reference, 32x24, 1 spp): 1.10x")
    assert "over the 5% allowed" in failures[0]
    assert "Gate: 2 of 3 tested variants significantly slower by more than 5%." in captured.out

    assert main(["bench", *results, "--compare-to", "bench-1", "--fail-slower", "60"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["bench", *results, "--compare-to", "bench-1"]) == 0  # compared, not gated
    out = capsys.readouterr().out
    assert "Compared with bench-1:" in out and "Gate:" not in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["compare", "nosuch", "latest"], "rtc compare: nosuch: no such run file"),
        (["compare", "broken", "latest"], "rtc compare: "),
        (["compare", "stability.json", "latest"], "rtc compare: stability.json: not a bench run"),
        (["compare", "sizeless", "latest"], "rtc compare: "),
        (["bench", "--compare-to", "nosuch"], "rtc bench: --compare-to nosuch: no such run"),
        (["bench", "--compare-to", "latest", "--fail-slower", "lots"],
         "rtc bench: --fail-slower 'lots': expected a percentage"),
        (["bench", "--fail-slower", "25%"], "rtc bench: --fail-slower: give the run"),
    ],
)  # fmt: skip
def test_bad_input_is_one_line_and_exit_2(two_runs, monkeypatch, capsys, argv, message):
    first, _ = two_runs
    (first.parent / "broken.json").write_text('{"rtc": ', encoding="utf-8")
    stability = {"rtc": {"schema_version": 1, "kind": "stability", "results": []}}
    (first.parent / "stability.json").write_text(json.dumps(stability), encoding="utf-8")
    sizeless = json.loads(first.read_text(encoding="utf-8"))
    del sizeless["rtc"]["rows"][0]["size"]
    (first.parent / "sizeless.json").write_text(json.dumps(sizeless), encoding="utf-8")
    _fake_bench(monkeypatch, first)  # never reached: the options are checked first
    monkeypatch.chdir(first.parent)
    assert main([*argv, "--results-dir", str(first.parent.parent)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert err.startswith(message)
    if "broken" in argv:
        assert "broken.json: cannot read the result file" in err
    if "sizeless" in argv:
        assert "sizeless.json: a row the comparison cannot read (KeyError: 'size')" in err


def test_latest_in_an_empty_folder_says_there_is_no_run(tmp_path, capsys):
    assert main(["compare", "previous", "latest", "--results-dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"rtc compare: previous: {tmp_path / 'runs'} holds 0 run files; " \
        "run `rtc bench` first"  # fmt: skip


# ------------------------------------------------------------------ history


def _history_runs() -> list[dict[str, Any]]:
    return [
        _run("bench-1", _base_rows(), commit="1" * 40),
        _run("bench-2", _base_rows(), commit="2" * 40),  # the same again: nothing moves
        _run("bench-3", _slower_rows(), commit="3" * 40),
    ]


def test_history_tests_each_variant_against_its_previous_run():
    found = {s.name: s for s in history(_history_runs())}
    cached = found["cached"].points
    assert [p.run for p in cached] == [0, 1, 2]
    assert cached[0].change is None
    assert cached[1].change is not None and not cached[1].change.test.significant
    assert cached[2].change is not None and cached[2].change.verdict == "slower"
    assert cached[2].previous == 1
    prealloc = found["prealloc"].points  # another size in the third run: not tested
    assert prealloc[2].change is None
    assert [p.run for p in found["robust"].points] == [0, 1]
    assert "numba[float32]" in found  # first seen in the third run


def test_the_reports_history_shows_the_plot_and_names_the_significant_changes(tmp_path):
    runs = _history_runs()
    plot = plots.history_plot(runs, tmp_path / "history.png")
    assert plot is not None and plot.stat().st_size > 10_000
    from harness.document.model import Bullets, Picture, Table, to_markdown

    blocks = _history_blocks(runs, plot)
    assert any(isinstance(b, Picture) and b.path == "report/history.png" for b in blocks)
    table = next(b for b in blocks if isinstance(b, Table))
    assert table.rows[0][-1] == "2 slower, 0 faster"  # newest first
    assert table.rows[1][-1] == "-"
    bullets = next(b for b in blocks if isinstance(b, Bullets))
    assert bullets.items[0].startswith("`bench-3` (commit 3333333333): `cached` 1.50x slower")
    assert "Student's two-sample t-test" in to_markdown(blocks)


def test_no_table_rows_no_history_plot(tmp_path):
    assert plots.history_plot([_run("bench-1", [])], tmp_path / "history.png") is None
