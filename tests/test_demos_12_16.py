"""The chapter 12-16 demos run, at a few pixels, and draw something; the OBJ text the
chapter 15 demo generates parses into the mesh it describes."""

from __future__ import annotations

import pytest

from raytracer import CSG, Group, SmoothTriangle, Triangle, color, parse_obj_file, pixel_at
from rtc.demos import DEMOS, die, icosahedron_obj


@pytest.mark.parametrize("chapter", [12, 13, 14, 15, 16])
def test_a_demo_draws_a_picture_at_any_size(chapter: int) -> None:
    picture = DEMOS[chapter].draw(6, 4)
    assert picture is not None
    assert (picture.width, picture.height) == (6, 4)
    colors = {pixel_at(picture, x, y) for y in range(4) for x in range(6)}
    assert len(colors) > 1  # not one flat color: something is in view
    assert colors != {color(0, 0, 0)}


def test_the_generated_icosahedron_parses_into_flat_and_smooth_meshes() -> None:
    parser = parse_obj_file(icosahedron_obj())
    assert len(parser.vertices) - 1 == 12 and len(parser.normals) - 1 == 12
    assert parser.ignored_lines == 1  # the "o icosahedron" line
    flat, smooth = parser.groups["Flat"], parser.groups["Smooth"]
    assert [type(t) for t in flat.children] == [Triangle] * 20
    assert [type(t) for t in smooth.children] == [SmoothTriangle] * 20
    assert parser.default_group.children == []


def test_the_die_is_a_rounded_cube_minus_six_pips() -> None:
    shape = die()
    assert shape.operation == "difference"
    assert isinstance(shape.left, CSG) and shape.left.operation == "intersection"
    assert isinstance(shape.right, Group) and len(shape.right.children) == 6
