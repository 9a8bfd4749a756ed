"""The shapes the scene format has beyond the book: ``- add: torus`` (chapter 20 here) and
``- add: fir_branch`` (the christmas scene's branch, ``scene.fir_branch``): what the loader
makes of them, and one error line for each mistake."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_scenefile import error, load, only

from raytracer.shapes.triangle import Triangle
from scene.fir_branch import LENGTH, NEEDLES, PER_SEGMENT, RADIUS, SEGMENTS, needle_corners
from variants.registry import load_variant


@pytest.fixture(scope="module")
def api() -> Mapping[str, Any]:
    return load_variant("naive").api


def test_a_torus_with_its_radii_and_one_with_the_defaults(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: torus\n  major-radius: 2\n  minor-radius: 0.5\n"
                 "- add: torus\n")  # fmt: skip
    given, default = scene.world.objects
    assert type(given) is type(api["torus"]())
    assert (given.major_radius, given.minor_radius) == (2, 0.5)
    assert (default.major_radius, default.minor_radius) == (1, 0.25)


@pytest.mark.parametrize(
    ("key", "value"), [("major-radius", 0), ("minor-radius", -0.1), ("minor-radius", 0)]
)
def test_a_torus_radius_must_be_positive(tmp_path: Path, api: Any, key: str, value: float) -> None:
    message = error(tmp_path, api, f"- add: torus\n  {key}: {value}\n")
    assert message.startswith(f"{tmp_path / 'scene.yml'}:12: the torus at line 11: {key} must")
    assert "greater than 0" in message and "\n" not in message


def _needles(branch: Any) -> list[Any]:
    """The branch's needle triangles, segment by segment."""
    needles = branch.children[1]
    return [t for segment in needles.children for t in segment.children]


def test_a_fir_branch_is_a_stem_and_480_needles_in_20_segments(tmp_path: Path, api: Any) -> None:
    branch = only(load(tmp_path, api, "- add: fir_branch\n"))
    stem, needles = branch.children
    assert type(stem) is type(api["cylinder"]())
    assert (stem.minimum, stem.maximum, stem.closed) == (0, LENGTH, True)
    assert stem.transform == api["scaling"](RADIUS, 1, RADIUS)
    assert stem.material.color == api["color"](0.5, 0.35, 0.26)
    assert (stem.material.ambient, stem.material.diffuse, stem.material.specular) == (
        0.2, 0.6, 0,
    )  # fmt: skip
    assert len(needles.children) == SEGMENTS
    assert all(len(segment.children) == PER_SEGMENT for segment in needles.children)
    triangles = _needles(branch)
    assert len(triangles) == NEEDLES
    assert {type(t) for t in triangles} == {Triangle}
    assert {t.material.color for t in triangles} == {api["color"](0.26, 0.36, 0.16)}
    assert {t.material.specular for t in triangles} == {0.1}


def test_the_needles_are_where_the_scene_header_puts_them() -> None:
    """Each needle: a base 0.025 wide at its segment's height (plus up to one segment), a tip
    up to one segment lower and 0.25 to 0.5 from the stem; the segments' turns cover 2.1 pi
    of angle, 24 needles each."""
    corners = needle_corners(seed=5)
    seg_size = LENGTH / (SEGMENTS - 1)
    for n, (p1, p2, p3) in enumerate(corners):
        segment = n // PER_SEGMENT
        assert p1[1] == p2[1]
        assert seg_size * segment <= p1[1] <= seg_size * (segment + 1)
        assert p1[1] - seg_size <= p3[1] <= p1[1]
        assert math.dist(p1, p2) == pytest.approx(RADIUS)
        assert 10 * RADIUS <= math.hypot(p3[0], p3[2]) <= 20 * RADIUS
        assert math.hypot(p1[0], p1[2]) == pytest.approx(RADIUS / math.sqrt(2))
    angles = np.arctan2(corners[:, 2, 0], corners[:, 2, 2])  # of each tip, about the stem
    turns = np.unwrap(angles[:PER_SEGMENT])
    assert 0 <= turns[0] <= 2.1 * math.pi / PER_SEGMENT + 1e-12
    assert np.all(np.diff(turns) > -2.1 * math.pi / PER_SEGMENT)


def test_a_seed_draws_the_same_branch_and_each_line_its_own(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: fir_branch\n- add: fir_branch\n"
                 "- add: fir_branch\n  seed: 99\n- add: fir_branch\n  seed: 99\n")  # fmt: skip
    first, second, seeded, again = (_needles(b) for b in scene.world.objects)
    assert first[0].p1 != second[0].p1  # the default seed: the line it is added at
    assert [t.p3 for t in seeded] == [t.p3 for t in again]
    assert seeded[0].p1 not in (first[0].p1, second[0].p1)
    reloaded = load(tmp_path, api, "- add: fir_branch\n")
    assert [t.p3 for t in _needles(only(reloaded))] == [t.p3 for t in first]


def test_a_fir_branchs_material_is_its_needles(tmp_path: Path, api: Any) -> None:
    branch = only(load(tmp_path, api, "- add: fir_branch\n  material:\n    color: [1, 0, 0]\n"
                       "  shadow: false\n"))  # fmt: skip
    stem = branch.children[0]
    assert stem.material.color == api["color"](0.5, 0.35, 0.26)
    assert {t.material.color for t in _needles(branch)} == {api["color"](1, 0, 0)}
    assert not stem.casts_shadow and not any(t.casts_shadow for t in _needles(branch))


def test_a_defined_fir_branch_added_twice_differs_unless_seeded(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- define: bough\n  value:\n    add: fir_branch\n"
                 "- add: bough\n- add: bough\n- add: bough\n  seed: 3\n- add: bough\n"
                 "  seed: 3\n")  # fmt: skip
    a, b, c, d = (_needles(x) for x in scene.world.objects)
    assert a[0].p1 != b[0].p1 and [t.p1 for t in c] == [t.p1 for t in d]


def test_a_fir_branch_counts_483_shapes(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: fir_branch\n")
    assert scene.objects[0].count == 1 + 1 + 1 + NEEDLES  # branch, stem, needles' group


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("seed: -1", "seed must be a whole number from 0 to"),
        ("seed: 1.5", "seed must be a whole number from 0 to"),
        ("file: x.obj", "unknown key 'file' in a fir_branch"),
    ],
)
def test_a_fir_branch_mistake_is_one_line(
    tmp_path: Path, api: Any, text: str, expected: str
) -> None:
    message = error(tmp_path, api, f"- add: fir_branch\n  {text}\n")
    assert message.startswith(f"{tmp_path / 'scene.yml'}:12: ")
    assert expected in message and "\n" not in message
