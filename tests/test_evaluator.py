"""The step library's evaluator, comparisons, namespace and step forms, on stand-in types.

The stand-ins are deliberately not the reference's types: the step library is duck-typed so
that a learner's own variant, with its own classes, works too.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from pytest_bdd.exceptions import StepDefinitionNotFoundError

from steps.book import Book
from steps.compare import approx_equal, describe
from steps.errors import (
    EvaluationError,
    NotAllowed,
    NotImplementedByVariant,
    StepError,
    UndefinedStep,
)
from steps.evaluator import Evaluator
from steps.phrases import given_or_when, then

# ----------------------------------------------------------------------------- stand-ins


@dataclass(frozen=True)
class Vec:
    x: float
    y: float
    z: float
    w: float

    def __sub__(self, other: Vec) -> Vec:
        return Vec(self.x - other.x, self.y - other.y, self.z - other.z, self.w - other.w)

    def __mul__(self, k: float) -> Vec:
        return Vec(self.x * k, self.y * k, self.z * k, self.w * k)


@dataclass(frozen=True)
class Col:
    red: float
    green: float
    blue: float


@dataclass(frozen=True)
class Mat:
    rows: tuple[tuple[float, ...], ...]

    @property
    def size(self) -> int:
        return len(self.rows)

    def __getitem__(self, key: tuple[int, int]) -> float:
        return self.rows[key[0]][key[1]]


@dataclass(frozen=True)
class Material:
    color: Col = Col(1, 1, 1)
    ambient: float = 0.1


@dataclass(eq=True)
class Shape:
    material: Material = field(default_factory=Material)
    transform: str = "identity"
    parent: Any = field(default=None, compare=False)


@dataclass(frozen=True)
class Light:
    position: Vec
    intensity: Col


@dataclass(frozen=True)
class Hit:
    t: float
    object: Any


@dataclass
class World:
    objects: list[Any] = field(default_factory=list)
    light: Light | None = None


@dataclass
class Group:
    children: list[Any] = field(default_factory=list)


@dataclass
class Canvas:
    width: int
    height: int
    pixels: dict[tuple[int, int], Col] = field(default_factory=dict)


@dataclass
class Parser:
    groups: dict[str, Group]
    ignored_lines: int


def _determinant(m: Mat) -> float:
    (a, b), (c, d) = m.rows
    return a * d - b * c


def _lighting(*arguments: Any) -> tuple[Any, ...]:
    return arguments  # the test only looks at what arrived


def _write_pixel(c: Canvas, x: int, y: int, color: Col) -> None:
    c.pixels[x, y] = color


def _add_child(g: Group, s: Shape) -> None:
    g.children.append(s)
    s.parent = g


def _recurse(n: float) -> float:
    return _recurse(n + 1)


@dataclass(frozen=True)
class Box:
    """A stand-in for the bonus chapter's bounding box: an immutable value."""

    min: Vec
    max: Vec


def _grow(box: Box, lo: Vec, hi: Vec) -> Box:
    return Box(
        Vec(min(box.min.x, lo.x), min(box.min.y, lo.y), min(box.min.z, lo.z), 1),
        Vec(max(box.max.x, hi.x), max(box.max.y, hi.y), max(box.max.z, hi.z), 1),
    )


API: dict[str, Any] = {
    "tuple": Vec,
    "point": lambda x, y, z: Vec(x, y, z, 1),
    "vector": lambda x, y, z: Vec(x, y, z, 0),
    "color": Col,
    "matrix": lambda rows: Mat(tuple(tuple(row) for row in rows)),
    "identity_matrix": Mat(((1, 0), (0, 1))),
    "determinant": _determinant,
    "EPSILON": 0.0001,
    "sphere": Shape,
    "material": Material,
    "point_light": Light,
    "lighting": _lighting,
    "intersection": Hit,
    "intersections": lambda *xs: sorted(xs, key=lambda i: i.t),
    "world": World,
    "group": Group,
    "add_child": _add_child,
    "canvas": Canvas,
    "write_pixel": _write_pixel,
    "pixel_at": lambda c, x, y: c.pixels.get((x, y), Col(0, 0, 0)),
    "canvas_to_ppm": lambda c: f"P3\n{c.width} {c.height}\n255\n",
    "recurse": _recurse,
    "bounding_box": lambda min, max: Box(min, max),
    "add_point": lambda box, p: _grow(box, p, p),
    "add_box": lambda box, other: _grow(box, other.min, other.max),
}


def evaluate(source: str, **variables: Any) -> Any:
    return Evaluator(API, variables, "stand-in").evaluate(source)


@pytest.fixture
def book() -> Book:
    return Book(API, "stand-in", Path(__file__))


# ----------------------------------------------------------------------------- evaluator


def test_arithmetic_constants_and_calls() -> None:
    assert evaluate("sqrt(2)/2") == pytest.approx(math.sqrt(2) / 2)
    assert evaluate("π / 2") == pytest.approx(math.pi / 2)
    assert evaluate("-infinity") == -math.inf
    assert evaluate("(true, false, nothing)") == (True, False, None)
    assert evaluate("point(1, 2, 3) - vector(1, 1, 1)") == Vec(0, 1, 2, 1)
    assert evaluate("+EPSILON") == 0.0001
    assert evaluate("identity_matrix[1,1]") == 1


@pytest.mark.parametrize(
    "source",
    [
        "__import__('os')",
        "x.__class__",
        "_private",
        "(lambda: 1)()",
        "[i for i in xs]",
        "{i for i in xs}",
        "(i for i in xs)",
        "xs.append(1)",
        "point(*xs)",
        "point(**xs)",
        "point(_x=1, y=2, z=3)",
        "2 ** 3",
        "7 // 2",
        "xs[0:1]",
        "f'{x}'",
        "1 if x else 2",
        "{'a': 1}",
        "x and xs",
        "not x",
        "x in xs",
        "x is x",
        "b'bytes'",
        "(y := 2)",
    ],
)
def test_the_evaluator_refuses_what_the_notation_does_not_allow(source: str) -> None:
    with pytest.raises(NotAllowed):
        evaluate(source, x=1, xs=[1, 2])


def test_keyword_arguments_and_lists_are_part_of_the_notation() -> None:
    # the bonus chapter: bounding_box(min=p max=q), make_subgroup(g, [s1, s2])
    assert evaluate("point(z=3, x=1, y=2)") == Vec(1, 2, 3, 1)
    assert evaluate("[x, point(0, 0, 0)]", x=1) == [1, Vec(0, 0, 0, 1)]
    assert evaluate("[]") == []


def test_refusals_name_the_step() -> None:
    with pytest.raises(NotAllowed, match=r"^Then x\.__class__ = 1: .*'_'"):
        Evaluator(API, {"x": 1}, "stand-in", "Then x.__class__ = 1").evaluate("x.__class__")


def test_in_call_position_the_api_wins_over_a_variable() -> None:
    assert evaluate("color(0, 0, 0)", color=Col(1, 1, 1)) == Col(0, 0, 0)
    assert evaluate("color", color=Col(1, 1, 1)) == Col(1, 1, 1)


def test_variables_come_before_api_constants_and_book_constants() -> None:
    assert evaluate("EPSILON", EPSILON=5) == 5
    assert evaluate("true", true=0) == 0


def test_unknown_names_list_close_matches() -> None:
    with pytest.raises(EvaluationError, match="unknown name 'shap'; did you mean: shape"):
        evaluate("shap", shape=1)


def test_a_book_function_missing_from_the_variant_is_not_implemented_by_it() -> None:
    with pytest.raises(NotImplementedByVariant, match=r"variant 'stand-in'.*cube") as caught:
        evaluate("cube()")
    assert isinstance(caught.value, StepDefinitionNotFoundError)
    assert caught.value.name == "cube"
    with pytest.raises(NotImplementedByVariant, match="not a book function"):
        evaluate("frobnicate(1)")


def test_calling_a_constant_is_an_error() -> None:
    with pytest.raises(EvaluationError, match="constant"):
        evaluate("EPSILON(1)")


def test_count_is_the_length_of_a_sequence_unless_the_object_has_its_own() -> None:
    assert evaluate("xs.count", xs=[1, 2, 3]) == 3
    assert evaluate("xs.count", xs=(1, 2)) == 2
    counted = namedtuple("counted", "count")(7)
    assert evaluate("c.count", c=counted) == 7


def test_missing_attributes_and_items_are_explained() -> None:
    with pytest.raises(EvaluationError, match="no attribute 'xx'; did you mean: x"):
        evaluate("v.xx", v=Vec(1, 2, 3, 0))
    with pytest.raises(EvaluationError, match="it has 1 items"):
        evaluate("xs[3]", xs=[1])


def test_lighting_without_an_object_gets_a_default_sphere() -> None:
    light = Light(Vec(0, 0, -10, 1), Col(1, 1, 1))
    old_form = evaluate("lighting(m, light, p, e, n)", m="m", light=light, p="p", e="e", n="n")
    assert old_form[0] == "m" and isinstance(old_form[1], Shape) and old_form[2] is light
    with_shadow = evaluate("lighting(m, light, p, e, n, true)", m=1, light=light, p=2, e=3, n=4)
    assert len(with_shadow) == 7 and with_shadow[-1] is True
    new_form = evaluate(
        "lighting(m, s, light, p, e, n, false)", m=1, s="s", light=light, p=2, e=3, n=4
    )
    assert new_form == (1, "s", light, 2, 3, 4, False)


def test_comparisons_are_approximate() -> None:
    assert evaluate("a == b", a=1.00001, b=1) is True
    assert evaluate("a != b", a=1.001, b=1) is True
    assert evaluate("a <= b", a=1.00001, b=1) is True
    assert evaluate("1 < 2 < 3") is True


# ----------------------------------------------------------------------------- compare


def test_approximate_equality_of_numbers_tuples_colours_and_matrices() -> None:
    assert approx_equal(0.1 + 0.2, 0.3)
    assert not approx_equal(1.0, 1.0002)
    assert approx_equal(math.inf, math.inf) and not approx_equal(math.inf, 1e300)
    assert approx_equal(Vec(1, 2, 3, 1), Vec(1.00001, 2, 3, 1))
    assert not approx_equal(Vec(1, 2, 3, 1), Vec(1, 2, 3, 0))
    assert approx_equal(Col(0.9, 0.2, 0.04), Col(0.90001, 0.2, 0.04))
    assert approx_equal(Mat(((1, 2), (3, 4))), Mat(((1, 2), (3, 4.00001))))
    assert not approx_equal(Mat(((1, 2), (3, 4))), Mat(((1, 2), (3, 5))))
    assert approx_equal([1, Vec(0, 0, 0, 0)], (1.00001, Vec(0, 0, 0, 0)))
    assert not approx_equal([1, 2], [1])


def test_an_intersection_equals_a_number_when_its_t_does() -> None:
    assert approx_equal(Hit(4.0, "s"), 4)
    assert approx_equal(4, Hit(4.00001, "s"))
    assert not approx_equal(Hit(4.0, "s"), 5)


def test_identity_and_plain_equality_are_the_fallback() -> None:
    unequal_to_itself = float("nan")
    assert approx_equal(unequal_to_itself, unequal_to_itself)
    assert approx_equal("union", "union") and not approx_equal("union", "difference")
    assert approx_equal(Shape(), Shape())


def test_descriptions_read_like_the_book() -> None:
    assert describe(Vec(1, 2, 3, 1)) == "point(1, 2, 3)"
    assert describe(Vec(1, 2, 3, 0)) == "vector(1, 2, 3)"
    assert describe(Vec(1, 2, 3, 2)) == "tuple(1, 2, 3, 2)"
    assert describe(Col(0.5, 0, 1)) == "color(0.5, 0, 1)"
    assert describe(Mat(((1, 2), (3, 4)))) == "2x2 matrix | 1 | 2 | | 3 | 4 |"
    assert describe(None) == "nothing"
    assert describe(True) == "true"
    assert describe(-math.inf) == "-infinity"
    assert describe([Hit(1, "s")]) == "[intersection(1, 's')]"


# ----------------------------------------------------------------------------- assignment


def test_dotted_assignment_changes_a_mutable_owner_in_place(book: Book) -> None:
    given_or_when(book, "s ← sphere()")
    shape = book.variables["s"]
    given_or_when(book, 's.transform ← "scaled"')
    assert book.variables["s"] is shape and shape.transform == "scaled"


def test_dotted_assignment_on_a_frozen_value_rebinds_the_name(book: Book) -> None:
    given_or_when(book, "m ← material()")
    given_or_when(book, "m.ambient ← 1")
    assert book.variables["m"] == Material(ambient=1)


def test_a_frozen_value_inside_a_mutable_owner_is_replaced_in_the_owner(book: Book) -> None:
    given_or_when(book, "w ← world()")
    given_or_when(book, "outer ← sphere()")
    given_or_when(book, "outer is added to w")
    given_or_when(book, "shape ← the first object in w")
    given_or_when(book, "shape.material.ambient ← 1")
    assert book.variables["outer"].material.ambient == 1
    assert book.variables["w"].objects[0].material.ambient == 1


def test_namedtuples_are_replaced_too(book: Book) -> None:
    book.variables["p"] = namedtuple("pair", "a b")(1, 2)
    given_or_when(book, "p.b ← 3")
    assert book.variables["p"] == (1, 3)


def test_keyword_names_are_assigned_and_read_consistently(book: Book) -> None:
    given_or_when(book, "from ← point(0, 0, 8)")
    then(book, "from = point(0, 0, 8)")
    assert "from_" in book.variables


def test_a_tuple_target_takes_the_items_one_by_one(book: Book) -> None:
    given_or_when(book, "(a, b) ← (point(1, 2, 3), 4)")
    given_or_when(book, "c, d ← [5, 6]")
    assert book.variables["a"] == Vec(1, 2, 3, 1)
    assert [book.variables[name] for name in "bcd"] == [4, 5, 6]
    with pytest.raises(EvaluationError, match="2 names to assign, but the value has 3 items"):
        given_or_when(book, "(a, b) ← (1, 2, 3)")
    with pytest.raises(EvaluationError, match="the value is int, not a tuple or a list"):
        given_or_when(book, "(a, b) ← 1")


def test_a_point_or_a_box_is_added_to_a_box(book: Book) -> None:
    # the bonus chapter's "p is added to box": an immutable box is rebound to the new one
    given_or_when(book, "box ← bounding_box(min=point(0, 0, 0) max=point(1, 1, 1))")
    given_or_when(book, "p ← point(-1, 3, 0.5)")
    given_or_when(book, "p is added to box")
    then(book, "box.min = point(-1, 0, 0)")
    then(book, "box.max = point(1, 3, 1)")
    given_or_when(book, "box2 ← bounding_box(min=point(0, 0, -4) max=point(2, 0, 0))")
    given_or_when(book, "box2 is added to box")
    assert book.variables["box"] == Box(Vec(-1, 0, -4, 1), Vec(2, 3, 1, 1))


def test_assigning_to_an_unknown_root_is_explained(book: Book) -> None:
    with pytest.raises(EvaluationError, match="'nope' has no value yet"):
        given_or_when(book, "nope.x ← 1")


# ----------------------------------------------------------------------------- Given / When


def test_tables_assign_dotted_keys_and_turn_tuples_into_colours(book: Book) -> None:
    given_or_when(
        book,
        "s ← sphere() with:",
        [["material.color", "(0.8, 1.0, 0.6)"], ["material.ambient", "√2/2"]],
    )
    assert book.variables["s"].material == Material(Col(0.8, 1.0, 0.6), math.sqrt(2) / 2)
    given_or_when(book, "s has:", [["transform", '"moved"']])
    assert book.variables["s"].transform == "moved"


def test_matrices_from_tables(book: Book) -> None:
    given_or_when(book, "the following 2x2 matrix A:", [["1", "-√4"], ["3", "4"]])
    given_or_when(book, "the following matrix B:", [["1", "2"], ["3", "4"]])
    then(book, "A is the following 2x2 matrix:", [["1", "-2"], ["3", "4"]])
    then(book, "A != B")
    then(book, "B is invertible")
    then(book, "B[1,0] = 3")
    with pytest.raises(EvaluationError, match="not"):
        given_or_when(book, "the following 3x3 matrix C:", [["1", "2"], ["3", "4"]])


def test_files_are_read_beside_the_feature_or_in_files(book: Book, tmp_path: Path) -> None:
    (tmp_path / "files").mkdir()
    (tmp_path / "files" / "one.obj").write_text("v 1 2 3\n")
    book.feature_file = tmp_path / "x.feature"
    given_or_when(book, 'text ← the file "one.obj"')
    assert book.variables["text"] == "v 1 2 3\n"
    with pytest.raises(EvaluationError, match=r"looked in .*missing\.obj"):
        given_or_when(book, 'text ← the file "missing.obj"')
    given_or_when(book, "doc ← a file containing:", None, "line one\nline two")
    then(book, "lines 2-2 of doc are", None, "line two")


def test_calls_for_their_effect_and_every_pixel(book: Book) -> None:
    given_or_when(book, "c ← canvas(2, 2)")
    given_or_when(book, "write_pixel(c, 1, 1, color(1, 0, 0))")
    then(book, "pixel_at(c, 1, 1) = color(1, 0, 0)")
    given_or_when(book, "every pixel of c is set to color(0, 0, 1)")
    then(book, "every pixel of c is color(0, 0, 1)")
    given_or_when(book, "ppm ← canvas_to_ppm(c)")
    then(book, "ppm ends with a newline character")
    then(book, "lines 1-2 of ppm are", None, "P3\n2 2")


def test_groups_worlds_and_parsers(book: Book) -> None:
    given_or_when(book, "g ← group()")
    given_or_when(book, "s ← sphere()")
    then(book, "g is empty")
    given_or_when(book, "add_child(g, s)")
    then(book, "g is not empty")
    then(book, "g includes s")
    given_or_when(book, "t ← first child of g")
    then(book, "t.parent = g")
    book.variables["parser"] = Parser({"FirstGroup": Group()}, ignored_lines=5)
    given_or_when(book, 'add_child(g, "FirstGroup" from parser)')
    then(book, 'g includes "FirstGroup" from parser')
    then(book, "parser should have ignored 5 lines")
    given_or_when(book, "w ← world()")
    then(book, "w contains no objects")
    then(book, "w has no light source")
    given_or_when(book, "w.light ← point_light(point(0, 0, 0), color(1, 1, 1))")
    given_or_when(book, "s is added to w")
    then(book, "w contains s")
    then(book, "w.light = point_light(point(0, 0, 0), color(1, 1, 1))")


def test_a_missing_group_name_lists_the_groups(book: Book) -> None:
    book.variables["parser"] = Parser({"FirstGroup": Group()}, ignored_lines=0)
    with pytest.raises(EvaluationError, match=r"no such group.*'FirstGroup'"):
        given_or_when(book, 'g ← "Second" from parser')


# ----------------------------------------------------------------------------- Then


def test_then_forms_that_pass(book: Book) -> None:
    given_or_when(book, "p ← point(1, 2, 3)")
    given_or_when(book, "s ← sphere()")
    given_or_when(book, "xs ← intersections(2:s, -1:s)")
    for text in [
        "p is a point",
        "p is not a vector",
        "p.x < p.y",
        "p.z >= 3",
        "p.z <= 3.00001",
        "p.y > 1",
        "xs.count = 2",
        "xs[0] = -1",
        "xs[1].t = 2",
        "p = approximately point(1.00001, 2, 3)",
        "nothing is nothing",
        "true is true",
        "1 > 2 is false",
    ]:
        then(book, text)


def test_a_failed_check_names_the_step_and_both_sides(book: Book) -> None:
    given_or_when(book, "p ← point(1, 2, 3)")
    with pytest.raises(AssertionError) as caught:
        then(book, "p = vector(1, 2, 3)")
    assert str(caught.value) == (
        "p = vector(1, 2, 3)\n  expected: vector(1, 2, 3)\n  got:      point(1, 2, 3)"
    )
    with pytest.raises(AssertionError, match="expected: a vector"):
        then(book, "p is a vector")
    with pytest.raises(AssertionError, match="got:      \\| 1 \\| 0 \\|"):
        then(book, "identity_matrix is the following matrix:", [["1", "1"], ["0", "1"]])


def test_true_means_a_boolean(book: Book) -> None:
    with pytest.raises(AssertionError, match="expected: true"):
        then(book, "1 is true")


def test_termination_failure_is_reported(book: Book) -> None:
    with pytest.raises(AssertionError, match="RecursionError"):
        then(book, "recurse(1) should terminate successfully")


def test_unreadable_steps_are_undefined(book: Book) -> None:
    for step, text in [
        (given_or_when, "the frobnicator is warm"),
        (given_or_when, "x ← a lamp that glows"),
        (given_or_when, "the light (a lamp)"),
        (then, "the frobnicator is warm"),
        (then, "p"),
        (given_or_when, "x ← f(1"),
        (given_or_when, "the following matrix M:"),  # no table
    ]:
        with pytest.raises(UndefinedStep):
            step(book, text)


def test_exceptions_from_the_tracer_are_step_errors_that_keep_the_cause(book: Book) -> None:
    with pytest.raises(StepError, match=r"x ← determinant\(1\): AttributeError") as caught:
        given_or_when(book, "x ← determinant(1)")
    assert isinstance(caught.value.__cause__, AttributeError)


def test_an_outline_parameter_without_a_column_is_pointed_out(book: Book) -> None:
    with pytest.raises(UndefinedStep, match="<n8>: no Examples column of that name"):
        then(book, "comps.n1 = <n8>")


def test_an_assert_inside_the_tracer_is_a_step_error_not_a_failed_check(book: Book) -> None:
    def broken() -> None:
        raise AssertionError("internal invariant")

    book.api = {**API, "broken": broken}
    with pytest.raises(StepError, match="broken\\(\\): AssertionError: internal invariant"):
        given_or_when(book, "broken()")
