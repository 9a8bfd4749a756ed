"""The kata runner and ``rtc kata``: results per scenario, undefined versus failed."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from rtc.cli import main
from steps import plugin
from steps.kata import progress_table, run_kata
from variants.registry import Variant, load_variant

SAMPLE = """\
Feature: A learner's first steps
  @chapter01
  Scenario: Square roots and sums
    Given a ← √16
    Then a + 1 = 5

  @chapter01
  Scenario: A wrong value
    Given a ← 2
    Then a * 2 = 5

  @chapter02
  Scenario: A step nobody wrote
    Given the frobnicator is warm

  @chapter02
  Scenario: A function the variant does not have
    Given x ← frobnicate(1)
"""


@pytest.fixture
def kata_folder(tmp_path: Path) -> Path:
    (tmp_path / "sample.feature").write_text(SAMPLE, encoding="utf-8")
    return tmp_path


def test_a_kata_run_reports_passed_failed_and_undefined_with_file_and_line(
    kata_folder: Path,
) -> None:
    run = run_kata(kata_folder)
    by_title = {result.title: result for result in run.results}
    assert [r.status for r in run.results] == ["passed", "failed", "undefined", "undefined"]
    assert not run.ok

    wrong = by_title["A wrong value"]
    assert (wrong.chapter, wrong.line, wrong.step_line) == (1, 8, 10)
    assert wrong.file == str(kata_folder / "sample.feature")
    assert wrong.variant == "naive" and wrong.feature == "A learner's first steps"
    assert "expected: 5" in wrong.message and "got:      4" in wrong.message

    unknown = by_title["A step nobody wrote"]
    assert (unknown.chapter, unknown.step_line) == (2, 14)
    assert "no step form reads 'the frobnicator is warm'" in unknown.message

    missing = by_title["A function the variant does not have"]
    assert "frobnicate" in missing.message and "'naive'" in missing.message


def test_the_progress_table_shows_each_chapter_and_its_first_failure(kata_folder: Path) -> None:
    table = progress_table(run_kata(kata_folder))
    assert " 1 Tuples, Points, and Vectors" in table
    assert f"first failed: {kata_folder / 'sample.feature'}:10  A wrong value" in table
    assert f"first undefined: {kata_folder / 'sample.feature'}:14" in table


def test_a_chapter_filter_runs_only_that_chapter(kata_folder: Path) -> None:
    run = run_kata(kata_folder, chapters=[1])
    assert {result.chapter for result in run.results} == {1}
    assert len(run.results) == 2


def test_untagged_book_files_get_their_chapter_from_the_file_name(tmp_path: Path) -> None:
    (tmp_path / "spheres.feature").write_text(
        "Feature: Spheres\n  Scenario: Arithmetic\n    Given a ← 1\n    Then a = 1\n",
        encoding="utf-8",
    )
    run = run_kata(tmp_path)
    assert [(r.chapter, r.status) for r in run.results] == [(5, "passed")]
    assert run.ok


def test_rtc_kata_exits_non_zero_and_prints_json(
    kata_folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["kata", str(kata_folder), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["ok"] is False
    assert [row["chapter"] for row in data["summary"]] == [1, 2]
    assert data["summary"][1]["undefined"] == 2
    assert data["results"][1]["step_line"] == 10


def test_rtc_kata_rejects_unknown_variants_and_paths(
    kata_folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["kata", str(kata_folder), "--variant", "no-such-variant"]) == 2
    assert "unknown variant 'no-such-variant'" in capsys.readouterr().err
    assert main(["kata", str(kata_folder / "missing")]) == 2
    assert "no such feature file or folder" in capsys.readouterr().err


def test_a_broken_feature_file_is_a_collection_error(tmp_path: Path) -> None:
    (tmp_path / "broken.feature").write_text(
        "Feature: x\n  Scenario: a\n    Given a ← 1\n  Sceanrio: b\n", encoding="utf-8"
    )
    run = run_kata(tmp_path)
    assert not run.ok and not run.results
    assert "Line number: 4" in run.errors[0] and "broken.feature" in run.errors[0]


def test_every_variant_runs_each_scenario_and_a_missing_name_is_undefined(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    naive = load_variant("naive")
    without_spheres = {name: value for name, value in naive.api.items() if name != "sphere"}
    partial = Variant("partial", "the reference without spheres", without_spheres)
    real_load_variant = plugin.load_variant
    monkeypatch.setattr(
        plugin,
        "load_variant",
        lambda name: partial if name == "partial" else real_load_variant(name),
    )
    (tmp_path / "spheres.feature").write_text(
        "Feature: Spheres\n"
        "  Scenario: A sphere starts untransformed\n"
        "    Given s ← sphere()\n"
        "    Then s.transform = identity_matrix\n",
        encoding="utf-8",
    )
    run = run_kata(tmp_path, ["naive", "partial"])
    outcomes = {(result.test, result.status) for result in run.results}
    assert outcomes == {
        ("test_a_sphere_starts_untransformed[naive]", "passed"),
        ("test_a_sphere_starts_untransformed[partial]", "undefined"),
    }
    undefined = next(result for result in run.results if result.variant == "partial")
    assert "variant 'partial' does not provide the book's sphere()" in undefined.message


def test_duplicate_scenario_titles_are_warned_about(tmp_path: Path) -> None:
    (tmp_path / "twice.feature").write_text(
        "Feature: Twice\n  Scenario: Same\n    Given a ← 1\n  Scenario: Same\n    Given a ← 2\n",
        encoding="utf-8",
    )
    run = run_kata(tmp_path)
    assert len(run.results) == 1
    assert "twice.feature:4: the title 'Same' is also used on line 2" in run.warnings[0]
