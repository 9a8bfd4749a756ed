"""The pieces of the learner's path, in-process: the generated stubs, the placeholder
constants, "to do" versus failed and undefined in the kata, and the ``--next`` report."""

from __future__ import annotations

import importlib.util
import inspect
from pathlib import Path
from types import ModuleType

import pytest

from raytracer.api import BOOK_API, naive_api
from rtc import cmd_variants
from rtc.cli import main
from rtc.scaffold import tracer_source
from steps import plugin
from steps.kata import ScenarioResult, own_names, progress_table, run_kata
from steps.next_scenario import book_order, next_report, next_scenario, scenario_text
from variants.learner import (
    NotImplementedYet,
    is_stub,
    learner_variant,
    module_api,
    not_written_yet,
    stub_names,
)
from variants.registry import Variant


def load_module(path: Path, source: str) -> ModuleType:
    path.write_text(source, encoding="utf-8")
    spec = importlib.util.spec_from_file_location(f"learner_{path.stem}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def fresh(tmp_path: Path) -> ModuleType:
    return load_module(tmp_path / "fresh.py", tracer_source("fresh"))


def test_the_scaffold_defines_every_book_name_as_a_stub_naming_its_chapter(
    fresh: ModuleType,
) -> None:
    api = module_api(fresh)
    assert list(api) == list(BOOK_API)
    assert stub_names(api) == list(BOOK_API)
    reference = naive_api()
    for name, chapter in BOOK_API.items():
        value = api[name]
        if not callable(value) or name in ("EPSILON", "identity_matrix"):
            with pytest.raises(NotImplementedYet) as raised:
                value + 1
        else:
            arguments = [None] * sum(
                1
                for p in inspect.signature(value).parameters.values()
                if p.default is p.empty and p.kind is p.POSITIONAL_OR_KEYWORD
            )
            with pytest.raises(NotImplementedYet) as raised:
                value(*arguments)
            positional = [
                p.name
                for p in inspect.signature(reference[name]).parameters.values()
                if p.kind in (p.POSITIONAL_OR_KEYWORD, p.VAR_POSITIONAL)
            ]
            assert list(inspect.signature(value).parameters) == positional, name
        assert (raised.value.name, raised.value.chapter) == (name, chapter)
        assert f"chapter {chapter}, " in str(raised.value)
    assert "def tuple_(x, y, z, w):" in inspect.getsource(fresh)
    assert str(inspect.signature(fresh.view_transform)) == "(from_, to, up)"
    assert str(inspect.signature(fresh.normal_at)) == "(shape, world_point, hit=None)"


def test_a_written_function_is_not_a_stub() -> None:
    def written(a: float) -> float:
        return a * 2

    def half_way(a: float) -> float:
        if a > 0:
            return a
        raise NotImplementedYet("dot")

    def plain(a: float) -> float:
        raise NotImplementedError

    assert not any(is_stub(f) for f in (written, half_way, plain, len, 0.0001))
    assert is_stub(not_written_yet("EPSILON"))


def test_a_constant_not_written_yet_refuses_every_use() -> None:
    identity = not_written_yet("identity_matrix")
    uses = [
        lambda: identity * 2,
        lambda: 2 * identity,
        lambda: identity[0, 0],
        lambda: identity.size,
        lambda: -identity,
        lambda: 1.0 < identity,  # noqa: SIM300  (float first: the reflected comparison)
        lambda: identity == identity,
        lambda: float(identity),
        lambda: bool(identity),
    ]
    for use in uses:
        with pytest.raises(NotImplementedYet, match=r"identity_matrix is not written yet"):
            use()
    with pytest.raises(AttributeError):
        identity.__deepcopy__  # noqa: B018  (Python's protocols see an ordinary object)
    assert "chapter 3" in repr(identity)


LEARNER_CODE = """

class Tup:
    def __init__(self, x, y, z, w):
        self.x, self.y, self.z, self.w = x, y, z, w


def tuple_(x, y, z, w):
    return Tup(x, y, z, w)


def dot(a, b):
    raise NotImplementedError


del sphere
"""

FEATURE = """\
Feature: A learner's tracer
  @chapter01
  Scenario: A wrong expectation
    Given a ← tuple(1, 2, 3, 1)
    Then a.x = 2

  @chapter01
  Scenario: Tuples work
    Given a ← tuple(1, 2, 3, 1)
    Then a.x = 1

  @chapter01
  Scenario: EPSILON is not written yet
    Given e ← EPSILON / 2

  @chapter01
  Scenario: dot raises a plain NotImplementedError
    Given a ← tuple(1, 2, 3, 1)
    Then dot(a, a) = 15

  @chapter03
  Scenario: The identity matrix is not written yet
    Given a ← tuple(1, 2, 3, 1)
    Then identity_matrix * a = a

  @chapter05
  Scenario: A name the learner deleted
    Given s ← sphere()
"""


@pytest.fixture
def partly_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Variant:
    module = load_module(tmp_path / "partly.py", tracer_source("partly") + LEARNER_CODE)
    variant = learner_variant("partly", module)
    real = plugin.load_variant
    monkeypatch.setattr(plugin, "load_variant", lambda n: variant if n == "partly" else real(n))
    (tmp_path / "learner.feature").write_text(FEATURE, encoding="utf-8")
    return variant


def test_stubs_are_to_do_checks_fail_and_deleted_names_are_undefined(
    tmp_path: Path, partly_written: Variant
) -> None:
    assert sorted(partly_written.overrides) == ["dot", "tuple"]
    assert own_names(partly_written) == ["dot", "tuple"]
    run = run_kata(tmp_path, ["partly"])
    by_title = {r.title: r for r in run.results}
    assert {title: r.status for title, r in by_title.items()} == {
        "A wrong expectation": "failed",
        "Tuples work": "passed",
        "EPSILON is not written yet": "todo",
        "dot raises a plain NotImplementedError": "todo",
        "The identity matrix is not written yet": "todo",
        "A name the learner deleted": "undefined",
    }
    assert by_title["EPSILON is not written yet"].missing == "EPSILON"
    assert by_title["dot raises a plain NotImplementedError"].missing == "dot"
    assert (
        "dot() raises NotImplementedError"
        in by_title["dot raises a plain NotImplementedError"].message
    )
    assert by_title["The identity matrix is not written yet"].missing == "identity_matrix"
    assert "partly.py:" in by_title["dot raises a plain NotImplementedError"].origin

    table = progress_table(run)
    header = table.splitlines()[0].split()
    assert header[-5:] == ["passed", "failed", "to", "do", "undefined"]
    assert any(
        line.split()[-7:] == ["partly", "own", "2/8", "1", "1", "2", "0"]
        for line in table.splitlines()
    ), table
    assert "     to write: dot(), EPSILON\n" in table + "\n"
    assert "     to write: identity_matrix" in table
    next_line = "next for partly: chapter 1, Tuples, Points, and Vectors  (rtc kata --variant"
    assert f"{next_line} partly --next)" in table


def test_next_is_the_first_scenario_not_passing_in_book_order(
    tmp_path: Path, partly_written: Variant
) -> None:
    run = run_kata(tmp_path, ["partly"])
    first = next_scenario(run, "partly")
    assert first is not None and first.title == "A wrong expectation"
    report = next_report(run, "partly")
    assert report.splitlines()[0] == (
        "next for partly: chapter 1, Tuples, Points, and Vectors: 1 passed, 1 failed, 2 to do"
    )
    assert "→    5     Then a.x = 2" in report
    assert "failed: Then a.x = 2\n  expected: 2\n  got:      1" in report


def test_book_order_is_chapter_then_the_books_file_order_then_line() -> None:
    def result(file: str, chapter: int, line: int) -> ScenarioResult:
        return ScenarioResult("v", chapter, "f", file, line, file, "todo")

    results = [
        result("x/intersections.feature", 5, 3),
        result("x/spheres.feature", 5, 40),
        result("x/rays.feature", 5, 90),
        result("x/tuples.feature", 6, 1),
        result("x/tuples.feature", 1, 200),
    ]
    ordered = [(r.file.split("/")[1], r.chapter) for r in sorted(results, key=book_order)]
    assert ordered == [
        ("tuples.feature", 1),
        ("rays.feature", 5),
        ("spheres.feature", 5),
        ("intersections.feature", 5),
        ("tuples.feature", 6),
    ]


def test_the_scenario_text_ends_before_the_next_tag_but_not_inside_a_doc_string(
    tmp_path: Path,
) -> None:
    feature = tmp_path / "obj.feature"
    feature.write_text(
        "Feature: x\n"
        "  Scenario: Reading\n"
        '    Given text ← a file containing:\n      """\n      @not a tag\n'
        '      Scenario: nor a scenario\n      """\n'
        "    Then text is not empty\n\n"
        "  @chapter15\n  Scenario: Next one\n    Given a ← 1\n",
        encoding="utf-8",
    )
    lines = [number for number, _ in scenario_text(str(feature), 2)]
    assert lines == [2, 3, 4, 5, 6, 7, 8]


def test_a_command_that_reaches_a_stub_says_so_in_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    def reaches_a_stub(args: object) -> int:
        raise NotImplementedYet("world")

    monkeypatch.setattr(cmd_variants, "run", reaches_a_stub)
    assert main(["variants"]) == 2
    err = capsys.readouterr().err
    assert err == (
        "rtc variants: the book's world() is not written yet (chapter 7, Making a Scene); "
        "rtc kata --next shows what to write\n"
    )


def test_rtc_variants_describes_a_learners_tracer_by_what_is_written(
    fresh: ModuleType,
) -> None:
    lines = cmd_variants.describe("fresh", learner_variant("fresh", fresh))
    text = "\n".join(lines)
    assert f"0 of {len(BOOK_API)} book names written" in lines[0]
    assert "written: nothing yet" in text
    assert f"stubs to write: {len(BOOK_API)}, the first tuple (ch 1)" in text
    assert "reference" not in text


OWN_CANVAS_CODE = """

class Board:
    def __init__(self, width, height):
        self.width, self.height, self.cells = width, height, {}


class Shade:
    def __init__(self, red, green, blue):
        self.red, self.green, self.blue = red, green, blue


def canvas(width, height):
    return Board(width, height)


def write_pixel(c, x, y, color):
    c.cells[x, y] = color


def pixel_at(c, x, y):
    return c.cells.get((x, y), Shade(0, 0, 0))


def render(c, w, settings=None, progress=None):
    board = canvas(2, 1)
    write_pixel(board, 0, 0, Shade(1.5, 0.5, -1))
    return board
"""


def test_a_learners_own_canvas_from_render_can_be_written_as_png(tmp_path: Path) -> None:
    from PIL import Image

    from groundwork.images import write_image

    module = load_module(tmp_path / "own.py", tracer_source("own") + OWN_CANVAS_CODE)
    variant = learner_variant("own", module)
    board = variant.api["render"](None, None)
    assert type(board).__name__ == "Board" and board.cells[0, 0].red == 1.5
    assert board.to_rgb8() == bytes([255, 128, 0, 0, 0, 0])
    write_image(board, tmp_path / "own.png")
    with Image.open(tmp_path / "own.png") as image:
        assert [image.getpixel((x, 0)) for x in range(2)] == [(255, 128, 0), (0, 0, 0)]
    stubbed = load_module(tmp_path / "stubbed.py", tracer_source("stubbed"))
    assert is_stub(learner_variant("stubbed", stubbed).api["render"])  # a stub stays a stub
