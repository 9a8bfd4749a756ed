"""The kata's progress table says, per chapter and variant, whose code the scenarios ran."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from rtc.cli import main
from steps import plugin
from steps.kata import own_names, progress_table, run_kata
from variants.registry import Variant, load_variant

SPHERES = """\
Feature: Spheres
  @chapter05
  Scenario: A sphere's default transformation
    Given s ← sphere()
    Then s.transform = identity_matrix

  @chapter01
  Scenario: Adding two tuples
    Given a ← tuple(3, -2, 5, 1)
    Then a + a = tuple(6, -4, 10, 2)
"""


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "spheres.feature").write_text(SPHERES, encoding="utf-8")
    return tmp_path


def test_the_table_marks_reference_own_and_inherited_chapters(folder: Path) -> None:
    run = run_kata(folder, ["naive", "cached", "pooled[workers=1]"])
    assert run.ok
    lines = progress_table(run).splitlines()

    def row(variant: str, chapter_line: int) -> str:
        return next(line for line in lines[chapter_line:] if f" {variant} " in line)

    chapter_1 = next(i for i, line in enumerate(lines) if line.startswith(" 1 Tuples"))
    chapter_5 = next(i for i, line in enumerate(lines) if line.startswith(" 5 Ray-Sphere"))
    assert " reference " in lines[chapter_1]
    assert " inherited " in row("cached", chapter_1)
    assert " own 1/9 " in row("cached", chapter_5)
    assert " inherited " in row("pooled[workers=1]:naive", chapter_5)
    assert any(line.startswith("code: whose code") for line in lines)


def test_the_json_lists_each_variants_own_names(
    folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["kata", str(folder), "--json", "--variant", "naive", "--variant", "cached"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["own"]["naive"] == []
    assert "sphere" in data["own"]["cached"] and "intersect" not in data["own"]["cached"]
    cached_5 = next(r for r in data["summary"] if r["variant"] == "cached" and r["chapter"] == 5)
    assert (cached_5["code"], cached_5["own"]) == ("own 1/9", ["sphere"])


def test_an_undeclared_override_still_counts_as_the_variants_own(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    naive = load_variant("naive")
    sneaky = Variant(
        "sneaky",
        "replaces tuple without saying so",
        {**naive.api, "tuple": naive.api["tuple"].__call__},
    )
    assert own_names(sneaky) == ["tuple"]
    real = plugin.load_variant
    monkeypatch.setattr(
        plugin, "load_variant", lambda name: sneaky if name == "sneaky" else real(name)
    )
    run = run_kata(folder, ["sneaky"], chapters=[1])
    assert " own 1/8 " in progress_table(run)
