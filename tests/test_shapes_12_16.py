"""Chapters 12 to 16 beyond the book's scenarios: bad input gets a clear error, and corner
cases (a degenerate triangle, the tip of a cone, nested groups) do not crash the tracer."""

from __future__ import annotations

import math
import re

import pytest

from raytracer import (
    CSG,
    Camera,
    Group,
    ObjParseError,
    Sphere,
    Triangle,
    add_child,
    color,
    color_at,
    cone,
    csg,
    cube,
    cylinder,
    default_world,
    group,
    intersect,
    intersection,
    intersection_allowed,
    local_normal_at,
    normal_at,
    obj_to_group,
    parse_obj_file,
    pixel_at,
    point,
    ray,
    render,
    smooth_triangle,
    sphere,
    translation,
    triangle,
    vector,
    view_transform,
)

# --- OBJ files -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "line_number", "expected"),
    [
        ("v 1 2 3\nv 1 x 3\n", 2, r"line 2: 'v 1 x 3': expected v x y z, with numbers only"),
        ("v 1 2\n", 1, r"line 1: 'v 1 2': expected v x y z, got 2 numbers"),
        ("vn 0 1\n", 1, r"line 1: 'vn 0 1': expected vn x y z, got 2 numbers"),
        ("v 0 0 0\nv 1 0 0\n\nf 1 2\n", 4, r"line 4: 'f 1 2': expected a face with at least 3"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
            4,
            r"line 4: 'f 1 2 4': the face names vertex 4, but 3 vertices are defined",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, r"line 4: 'f 0 1 2': the face names vertex 0"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
            5,
            r"line 5: 'f 1//1 2//1 3//2': the face names normal 2, but 1 normal",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2 3\n",
            5,
            r"line 5: .*a normal for every corner of the face or for none",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n", 4, r"line 4: .*a vertex number, not 'two'"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/a/\n", 4, r"line 4: .*a corner v, v/vt"),
        ("v nan 0 0\n", 1, r"line 1: .*finite numbers"),
    ],
)
def test_a_malformed_obj_line_names_its_number_text_and_what_was_expected(
    text: str, line_number: int, expected: str
) -> None:
    with pytest.raises(ObjParseError, match=expected) as error:
        parse_obj_file(text, source="model.obj")
    assert isinstance(error.value, ValueError)
    assert str(error.value).startswith(f"model.obj, line {line_number}: ")
    assert error.value.line_number == line_number
    assert error.value.line == text.splitlines()[line_number - 1]


def test_an_obj_parse_error_without_a_source_names_the_text() -> None:
    with pytest.raises(ObjParseError, match=r"^OBJ text, line 1: 'v 1 x 3'"):
        parse_obj_file("v 1 x 3")


def test_blank_lines_and_comments_are_skipped_without_being_counted() -> None:
    parser = parse_obj_file("# a comment\n\n   \nvt 0 1\ns off\nv 1 2 3\n")
    assert parser.ignored_lines == 2  # vt and s
    assert parser.vertices == [None, point(1, 2, 3)]


def test_negative_indices_count_back_from_the_last_vertex() -> None:
    parser = parse_obj_file("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    (only,) = parser.default_group.children
    assert only == triangle(point(0, 0, 0), point(1, 0, 0), point(0, 1, 0))


def test_faces_become_children_of_their_group() -> None:
    parser = parse_obj_file("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng Top\nf 1 3 2\n")
    top = parser.groups["Top"]
    assert all(t.parent is parser.default_group for t in parser.default_group.children)
    assert [t.parent for t in top.children] == [top]


def test_obj_to_group_holds_the_default_group_and_the_named_groups() -> None:
    parser = parse_obj_file("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng A\nf 1 3 2\ng B\nf 2 1 3\n")
    g = obj_to_group(parser)
    assert g.children == [parser.default_group, parser.groups["A"], parser.groups["B"]]
    assert all(child.parent is g for child in g.children)
    hits = intersect(g, ray(point(0.2, 0.2, -5), vector(0, 0, 1)))
    assert len(hits) == 3  # the three triangles lie on top of each other


def test_obj_to_group_leaves_out_an_empty_default_group() -> None:
    parser = parse_obj_file("v 0 0 0\nv 1 0 0\nv 0 1 0\ng A\nf 1 2 3\n")
    assert obj_to_group(parser).children == [parser.groups["A"]]


def test_the_parser_builds_shapes_through_the_factories_it_is_given() -> None:
    class MyTriangle(Triangle):
        __slots__ = ()

    class MyGroup(Group):
        __slots__ = ()

    parser = parse_obj_file(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\ng A\n",
        make_triangle=MyTriangle,
        make_group=MyGroup,
    )
    assert type(parser.default_group) is MyGroup and type(parser.groups["A"]) is MyGroup
    assert [type(t) for t in parser.default_group.children] == [MyTriangle, MyTriangle]


# --- CSG -------------------------------------------------------------------------------


@pytest.mark.parametrize("operation", ["onion", "Union", "", "subtract"])
def test_an_unknown_csg_operation_lists_the_three(operation: str) -> None:
    message = f"unknown CSG operation {operation!r}; choose 'union', 'intersection', 'difference'"
    with pytest.raises(ValueError, match=re.escape(f"CSG: {message}")):
        csg(operation, sphere(), cube())
    with pytest.raises(ValueError, match=re.escape(f"intersection_allowed: {message}")):
        intersection_allowed(operation, True, False, False)


def test_a_difference_carves_the_right_shape_out_of_the_left() -> None:
    # a unit cube minus a sphere sticking out of its front face: the ray along the axis
    # enters where the sphere's back surface is, inside the cube
    carved = csg("difference", cube(), Sphere(transform=translation(0, 0, -1)))
    xs = intersect(carved, ray(point(0, 0, -5), vector(0, 0, 1)))
    assert [round(i.t, 6) for i in xs] == [5.0, 6.0]
    assert [type(i.object).__name__ for i in xs] == ["Sphere", "Cube"]


def test_csg_through_groups_matches_children_by_identity() -> None:
    left, right = group(), group()
    s1, s2 = sphere(), sphere()  # equal values, different shapes
    add_child(left, s1)
    add_child(right, s2)
    c = csg("intersection", left, right)
    xs = intersect(c, ray(point(0, 0, -5), vector(0, 0, 1)))
    assert len(xs) == 2 and isinstance(c, CSG)


# --- triangles -------------------------------------------------------------------------


def test_a_degenerate_triangle_has_a_zero_normal_and_is_never_hit() -> None:
    flat = triangle(point(0, 0, 0), point(1, 1, 0), point(2, 2, 0))  # three points on a line
    assert flat.normal == vector(0, 0, 0)
    for origin in (point(1, 1, -5), point(0.5, 0.5, -5), point(0, 0, -5)):
        assert intersect(flat, ray(origin, vector(0, 0, 1))) == []
    same = triangle(point(1, 2, 3), point(1, 2, 3), point(1, 2, 3))  # a single point
    assert same.normal == vector(0, 0, 0)


def test_a_scene_with_degenerate_triangles_renders_as_if_they_were_not_there() -> None:
    plain = default_world()
    with_flat = default_world()
    for corners in [
        (point(-1, 0, -2), point(0, 0, -2), point(1, 0, -2)),  # a line across the view
        (point(0, 0, -2), point(0, 0, -2), point(0, 0, -2)),  # a point in the middle
    ]:
        with_flat.objects.append(triangle(*corners))
    c = Camera(
        11, 11, math.pi / 2, view_transform(point(0, 0, -5), point(0, 0, 0), vector(0, 1, 0))
    )
    expected, actual = render(c, plain), render(c, with_flat)
    for y in range(11):
        for x in range(11):
            assert pixel_at(actual, x, y) == pixel_at(expected, x, y)
    assert pixel_at(actual, 5, 5) != color(0, 0, 0)  # the spheres are in view


def test_a_smooth_triangle_normal_needs_the_hit() -> None:
    t = smooth_triangle(
        point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0),
        vector(0, 1, 0), vector(-1, 0, 0), vector(1, 0, 0),
    )  # fmt: skip
    with pytest.raises(ValueError, match=r"SmoothTriangle.*u and v"):
        local_normal_at(t, point(0, 0.5, 0))
    with pytest.raises(ValueError, match=r"SmoothTriangle.*u and v"):
        local_normal_at(t, point(0, 0.5, 0), intersection(1, t))


# --- groups, cones, cylinders ------------------------------------------------------------


def test_a_group_cannot_contain_itself() -> None:
    outer, inner = group(), group()
    add_child(outer, inner)
    with pytest.raises(ValueError, match=r"add_child\(Group, Group\).*cannot contain itself"):
        add_child(inner, outer)
    with pytest.raises(ValueError, match="cannot contain itself"):
        add_child(outer, outer)
    assert inner.children == [] and outer.children == [inner]


def test_a_group_has_no_normal_of_its_own() -> None:
    with pytest.raises(TypeError, match=r"local_normal_at\(Group\)"):
        local_normal_at(group(), point(0, 0, 0))
    with pytest.raises(TypeError, match=r"local_normal_at\(CSG\)"):
        local_normal_at(csg("union", sphere(), cube()), point(0, 0, 0))


def test_group_equality_compares_children_without_following_parents() -> None:
    a, b = group(), group()
    add_child(a, sphere())
    add_child(b, sphere())
    assert a == b  # the children's parents (a and b) are not compared
    add_child(b, cube())
    assert a != b
    nested_a, nested_b = group(), group()
    add_child(nested_a, a)
    add_child(nested_b, group())
    assert nested_a != nested_b


def test_the_tip_of_a_cone_shades_without_dividing_by_zero() -> None:
    w = default_world()
    w.objects = [cone()]
    straight_down = ray(point(0, 5, 0), vector(0, -1, 0))
    assert normal_at(cone(), point(0, 0, 0)) == vector(0, 0, 0)
    shade = color_at(w, straight_down)
    assert all(math.isfinite(value) for value in (shade.red, shade.green, shade.blue))


def test_a_ray_along_the_axis_of_an_open_cylinder_misses() -> None:
    assert intersect(cylinder(), ray(point(0, -5, 0), vector(0, 1, 0))) == []
    closed = cylinder()
    closed.minimum, closed.maximum, closed.closed = -1, 1, True
    xs = intersect(closed, ray(point(0, -5, 0), vector(0, 1, 0)))
    assert [i.t for i in xs] == [4, 6]


@pytest.mark.parametrize("x", [-1, 1])
def test_a_ray_lying_in_a_cube_face_touches_it_without_nan(x: int) -> None:
    xs = intersect(cube(), ray(point(x, 0, -5), vector(0, 0, 1)))
    assert [i.t for i in xs] == [4, 6]
