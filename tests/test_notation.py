"""The book's notation rewritten as Python source (steps.notation)."""

from __future__ import annotations

import pytest

from steps.notation import (
    NotationError,
    split_assignment,
    split_comparison,
    target_list,
    target_path,
    to_python,
    tokenize,
)


@pytest.mark.parametrize(
    ("book", "python"),
    [
        ("√2", "sqrt(2)"),
        ("√2/2", "sqrt(2)/2"),
        ("-√3/3", "-sqrt(3)/3"),
        ("vector(√3/3, -√3/3, √3/3)", "vector(sqrt(3)/3, -sqrt(3)/3, sqrt(3)/3)"),
        ("√x", "sqrt(x)"),
        ("√(a + b)", "sqrt(a + b)"),
        ("√v.x * 2", "sqrt(v.x) * 2"),
        ("√f(x)[0]", "sqrt(f(x)[0])"),
        ("√√16", "sqrt(sqrt(16))"),
        ("2√2", "2*sqrt(2)"),
        ("2π", "2*π"),
        ("rotation_x(π / 2)", "rotation_x(π / 2)"),
    ],
)
def test_square_roots_and_pi(book: str, python: str) -> None:
    assert to_python(book) == python


def test_t_colon_object_pairs_become_intersections() -> None:
    assert to_python("intersections(2:A, -√2/2:shape, √2:floor)") == (
        "intersections(intersection(2, A), intersection(-sqrt(2)/2, shape),"
        " intersection(sqrt(2), floor))"
    )


def test_pairs_are_rewritten_in_nested_argument_lists_only() -> None:
    assert to_python("f(g(1:a), 2)") == "f(g(intersection(1, a)), 2)"
    assert to_python("intersections(i1, i2)") == "intersections(i1, i2)"


def test_a_pair_with_two_colons_is_refused() -> None:
    with pytest.raises(NotationError, match="more than one"):
        to_python("intersections(1:2:a)")


def test_python_keywords_used_as_names_are_renamed_everywhere() -> None:
    assert to_python("view_transform(from, to, up)") == "view_transform(from_, to, up)"
    assert to_python("class + import") == "class_ + import_"
    assert target_path("from") == ["from_"]
    assert target_path("from.x") == ["from_", "x"]


def test_operator_keywords_and_constants_keep_their_meaning() -> None:
    assert to_python("a is b") == "a is b"
    assert to_python("not a") == "not a"
    assert to_python("None") == "None"


def test_ordinal_objects_children_and_named_groups() -> None:
    assert to_python("the first object in w") == "nth_object(w, 1)"
    assert to_python("the second object in w") == "nth_object(w, 2)"
    assert to_python("third child of g") == "nth_child(g, 3)"
    assert to_python('"FirstGroup" from parser') == 'group_named(parser, "FirstGroup")'
    assert to_python("normal_at(the first object in w, p)") == "normal_at(nth_object(w, 1), p)"


def test_conditions_compare_with_double_equals_and_drop_approximately() -> None:
    assert to_python("a = b", condition=True) == "a == b"
    assert to_python("a = approximately vector(1, 2, 3)", condition=True) == (
        "a == vector(1, 2, 3)"
    )
    assert to_python("a != b", condition=True) == "a != b"
    assert to_python("a <= b", condition=True) == "a <= b"


def test_split_comparison() -> None:
    assert split_comparison("xs[0].t = 4") == ("xs[0].t", "=", "4")
    assert split_comparison("normalize(v) = approximately vector(1, 0, 0)") == (
        "normalize(v)",
        "=",
        "vector(1, 0, 0)",
    )
    assert split_comparison("comps.over_point.z < -EPSILON/2") == (
        "comps.over_point.z",
        "<",
        "-EPSILON/2",
    )
    assert split_comparison("f(a = b) >= 2") == ("f(a = b)", ">=", "2")
    assert split_comparison("a == b") == ("a", "=", "b")
    assert split_comparison("a is a point") is None
    assert split_comparison("a = b = c") is None


def test_split_assignment_at_the_arrow_outside_strings() -> None:
    assert split_assignment("c ← canvas(10, 20)") == ("c", "canvas(10, 20)")
    assert split_assignment('s ← "a ← b"') == ("s", '"a ← b"')
    assert split_assignment("write_pixel(c, 2, 3, red)") is None


def test_tokens_keep_whitespace_strings_and_numbers() -> None:
    kinds = [token.kind for token in tokenize('f(1.5e-3, "x y") ← √2')]
    assert kinds == [
        "name", "op", "number", "op", "space", "string", "op", "space", "arrow", "space",
        "sqrt", "number",
    ]  # fmt: skip


@pytest.mark.parametrize("text", ["f(1, 2", "f(1, 2))", "a ¤ b", '"open', "√", "√+"])
def test_malformed_notation_is_a_notation_error(text: str) -> None:
    with pytest.raises(NotationError):
        to_python(text)


def test_the_bonus_chapters_keyword_arguments_get_their_commas() -> None:
    assert (
        to_python("bounding_box(min=point(-1, -2, -3) max=point(3, 2, 1))")
        == "bounding_box(min=point(-1, -2, -3), max=point(3, 2, 1))"
    )
    assert to_python("f(a, min=1, max=2)") == "f(a, min=1, max=2)"  # commas already there
    assert to_python("f(g(x=1 y=2) z=3)") == "f(g(x=1, y=2), z=3)"
    # in a condition, = between arguments stays a keyword; at the top it compares
    assert to_python("f(min=1 max=2) = b", condition=True) == "f(min=1, max=2) == b"


def test_empty_as_the_only_argument_means_no_arguments() -> None:
    assert to_python("bounding_box(empty)") == "bounding_box()"
    assert to_python("f(empty, 1)") == "f(empty, 1)"
    assert to_python("empty") == "empty"


def test_tuple_targets() -> None:
    assert target_list("(left, right)") == ["left", "right"]
    assert target_list("a, b.c") == ["a", "b.c"]
    assert target_list("left") is None
    with pytest.raises(NotationError):
        target_list("(left, xs[0])")


def test_targets_must_be_dotted_names() -> None:
    assert target_path("outer.material.ambient") == ["outer", "material", "ambient"]
    with pytest.raises(NotationError):
        target_path("xs[0]")
