"""The scene loader's limits, progress bar and checks of impossible values (issue 19, item 3):
nesting depth and shape counts checked while the file is read, with errors naming the limit
and the environment variable that raises it; a progress bar for a slow load; materials,
lights, bounds and transforms that cannot be drawn refused with the file and the line."""

from __future__ import annotations

import io
import math
import sys
from collections.abc import Mapping
from pathlib import Path
from textwrap import dedent
from typing import Any

import pytest

from groundwork import progress as progress_module
from groundwork.progress import LoadProgress
from scene import SceneError, load_scene, load_scene_text
from scene.limits import (
    DEFAULT_MAX_DEPTH,
    DEFAULT_MAX_SHAPES,
    DEPTH_VARIABLE,
    SHAPES_VARIABLE,
    Limits,
    limits_from_environment,
)
from scene.reader import compose
from variants.registry import load_variant

HEADER = """\
- add: camera
  width: 8
  height: 4
  field-of-view: 1
  from: [0, 1, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
"""  # 10 lines: a test's own items start at line 11


@pytest.fixture(scope="module")
def api() -> Mapping[str, Any]:
    return load_variant("cached").api


@pytest.fixture(autouse=True)
def _default_limits(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(DEPTH_VARIABLE, raising=False)
    monkeypatch.delenv(SHAPES_VARIABLE, raising=False)


def load(api: Mapping[str, Any], body: str, tmp_path: Path | None = None, **options: Any) -> Any:
    path = (tmp_path or Path("/nowhere")) / "scene.yml"
    return load_scene_text(HEADER + dedent(body), api, path=path, **options)


def error(api: Mapping[str, Any], body: str, tmp_path: Path | None = None, **options: Any) -> str:
    with pytest.raises(SceneError) as raised:
        load(api, body, tmp_path, **options)
    message = str(raised.value)
    assert "\n" not in message
    return message


def nested_groups(count: int) -> str:
    """``count`` groups inside each other around a sphere, in block style."""
    lines, indent = [], ""
    for _ in range(count):
        lines += [f"{indent}- add: group", f"{indent}  children:"]
        indent += "    "
    return "\n".join([*lines, f"{indent}- add: sphere"]) + "\n"


def depth_of(shape: Any) -> int:
    children = getattr(shape, "children", None) or ()
    return max((1 + depth_of(child) for child in children), default=0)


# --- nesting depth ---------------------------------------------------------------------------


def test_groups_nested_to_the_limit_load(api: Mapping[str, Any]) -> None:
    scene = load(api, nested_groups(DEFAULT_MAX_DEPTH))
    assert depth_of(scene.world.objects[0]) == DEFAULT_MAX_DEPTH


def test_one_group_more_is_refused_naming_the_limit_and_the_variable(api: Any) -> None:
    message = error(api, nested_groups(DEFAULT_MAX_DEPTH + 1))
    assert "nested more than 100 deep" in message
    assert f"set the environment variable {DEPTH_VARIABLE} (now 100, at most 1000)" in message


def test_300_nested_groups_stop_in_the_yaml_reader_before_it_recurses(api: Any) -> None:
    limit = sys.getrecursionlimit()
    message = error(api, nested_groups(300))
    assert message.startswith("/nowhere/scene.yml:221: the scene nests too deep here: more than "
                              "210 levels of YAML")  # fmt: skip
    assert sys.getrecursionlimit() == limit  # the default limit is not touched


def test_the_variable_raises_the_depth_limit(api: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(DEPTH_VARIABLE, "300")
    before = sys.getrecursionlimit()
    try:
        scene = load(api, nested_groups(300))
        assert depth_of(scene.world.objects[0]) == 300
        assert sys.getrecursionlimit() >= 12 * 300
    finally:
        sys.setrecursionlimit(before)


def test_nesting_made_by_defined_shapes_counts_too(api: Any) -> None:
    body = "- define: g0\n  value: {add: group, children: [{add: sphere}]}\n"
    for i in range(1, 12):
        body += f"- define: g{i}\n  value: {{add: group, children: [{{add: g{i - 1}}}]}}\n"
    message = error(api, body, limits=Limits(max_depth=10))
    assert "the 'g9' group at line " in message
    assert "nests groups and CSGs 11 deep (defined shapes added by name included), more than " \
        "the limit, 10" in message  # fmt: skip


def test_a_chain_of_yaml_merge_keys_is_refused_not_a_recursion_error(api: Any) -> None:
    body = "- define: m0\n  value: &m0 {ambient: 0.1}\n"
    for i in range(1, 400):
        body += f"- define: m{i}\n  value: &m{i} {{<<: *m{i - 1}, diffuse: 0.5}}\n"
    message = error(api, body)
    assert "the alias *m" in message and "nests the scene too deep here" in message


def test_bad_values_of_the_variables_are_one_clear_error(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    for variable, value in ((DEPTH_VARIABLE, "deep"), (DEPTH_VARIABLE, "1001"),
                            (SHAPES_VARIABLE, "0"), (SHAPES_VARIABLE, "-5")):  # fmt: skip
        monkeypatch.setenv(variable, value)
        with pytest.raises(SceneError) as raised:
            limits_from_environment(Path("scene.yml"))
        assert str(raised.value).startswith(
            f"scene.yml: the environment variable {variable}={value!r} must be a whole number"
        )
        monkeypatch.delenv(variable)
    monkeypatch.setenv(SHAPES_VARIABLE, "2_000_000")
    assert limits_from_environment(Path("x")) == Limits(DEFAULT_MAX_DEPTH, 2_000_000)


# --- shape counts -----------------------------------------------------------------------------


def test_the_shape_limit_counts_every_shape(api: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(SHAPES_VARIABLE, "6")  # the camera and the light count in the YAML
    assert len(load(api, "- add: sphere\n" * 4).world.objects) == 4
    message = error(api, "- add: sphere\n" * 5)
    assert message == (
        "/nowhere/scene.yml:15: the scene describes more than 6 shapes here, counting each copy "
        f"a YAML alias makes; to allow more, set the environment variable {SHAPES_VARIABLE} "
        f"(now 6), e.g. {SHAPES_VARIABLE}=12"
    )


def test_yaml_aliases_are_counted_without_being_expanded() -> None:
    text = "- &a {add: sphere}\n- &b [*a, *a, *a]\n- &c [*b, *b, *b]\n- [*c, *c]\n"
    root, shapes = compose(text, Path("x.yml"))
    assert root is not None and shapes == 1 + 3 + 9 + 18
    with pytest.raises(SceneError, match=r"^x\.yml:4: .* \(the alias \*c here copies 9 shapes\)"):
        compose(text, Path("x.yml"), Limits(max_shapes=25))


def test_copies_of_a_defined_shape_are_counted_before_they_are_built(api: Any) -> None:
    body = "- define: ten\n  value: {add: group, children: [" + ", ".join(["{add: sphere}"] * 10)
    body += "]}\n- define: hundred\n  value: {add: group, children: ["
    body += ", ".join(["{add: ten}"] * 10) + "]}\n- add: hundred\n- add: hundred\n"
    assert len(load(api, body, limits=Limits(max_shapes=300)).world.objects) == 2
    message = error(api, body, limits=Limits(max_shapes=150))
    assert message.startswith(
        "/nowhere/scene.yml:16: the 'hundred' group at line 16 would bring the scene to 222 "
        "shapes (every copy of a defined shape and every triangle of an OBJ model counted), more "
        "than the limit, 150"
    )


def test_obj_triangles_count_and_a_known_model_is_not_parsed_again(
    api: Any, tmp_path: Path
) -> None:
    (tmp_path / "square.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    body = "- define: square\n  value: {add: obj, file: square.obj}\n" + "- add: square\n" * 3
    scene = load(api, body, tmp_path, limits=Limits(max_shapes=9))  # 3 x (group + 2)
    assert len(scene.world.objects) == 3
    message = error(api, body, tmp_path, limits=Limits(max_shapes=8))
    assert message.startswith(
        f"{tmp_path / 'scene.yml'}:15: the 2 triangles of the 'square' obj at line 15 would "
        "bring the scene to 9 shapes"
    )


# --- the progress bar ---------------------------------------------------------------------------


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_the_bar_appears_only_once_the_load_is_slow() -> None:
    stream, clock = io.StringIO(), Clock()
    bar = LoadProgress("loading x.yml", enabled=True, stream=stream, clock=clock)
    bar.phase("reading YAML", 1000, "char")
    bar.update(500)
    assert stream.getvalue() == "" and not bar.shown
    clock.now = 1.5
    bar.update(800)
    assert "loading x.yml: reading YAML" in stream.getvalue() and "800/1.00k" in stream.getvalue()
    bar.phase("building shapes", 10, "shape")
    bar.advance(3)
    assert "loading x.yml: building shapes" in stream.getvalue()
    bar.close()
    assert bar.bar is None and bar.shown


def test_no_bar_when_disabled_however_slow() -> None:
    stream, clock = io.StringIO(), Clock()
    bar = LoadProgress("x", enabled=False, stream=stream, clock=clock)
    bar.phase("reading YAML", 10)
    clock.now = 100.0
    bar.update(5)
    bar.close()
    assert stream.getvalue() == "" and not bar.shown


def test_a_slow_load_shows_its_phases_on_stderr(
    api: Any, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(progress_module, "DELAY", 0.0)  # every load is "slow"
    scene = load_scene_text(HEADER + "- add: group\n  children:\n" + "    - add: sphere\n" * 3000,
                            api, path="big.yml", progress=True)  # fmt: skip
    scene.book_world(divide=True, progress=True)
    out, err = capsys.readouterr()
    assert out == ""
    for phase in ("reading YAML", "reading shapes"):
        assert f"loading big.yml: {phase}" in err
    for phase in ("building shapes", "dividing groups"):
        assert f"building big.yml: {phase}" in err


def test_a_fast_load_shows_nothing(api: Any, capsys: pytest.CaptureFixture[str]) -> None:
    load(api, "- add: sphere\n", progress=True)
    assert capsys.readouterr() == ("", "")


# --- impossible values ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ("- add: cylinder\n  min: 1\n  max: 1\n  closed: true\n", None),  # a disc
        ("- add: cone\n  min: 5\n", None),  # up to the default max, infinity
        ("- add: cylinder\n  max: 0.5\n  min: 0.6\n",
         "13: the cylinder at line 11: min (0.6) is above max (0.5)"),
        ("- add: cone\n  min: 3\n  max: -.inf\n",
         "12: the cone at line 11: min cannot be infinity, nor max -infinity"),
    ],
)  # fmt: skip
def test_cylinder_and_cone_bounds(api: Any, body: str, expected: str | None) -> None:
    if expected is None:
        load(api, body)
    else:
        assert error(api, body).startswith(f"/nowhere/scene.yml:{expected}")


@pytest.mark.parametrize(
    ("key", "good", "bad", "expected"),
    [
        ("ambient", "0", "-0.01", "must be 0 or more"),
        ("diffuse", "2", "-1", "must be 0 or more"),
        ("specular", "0", "-1e-9", "must be 0 or more"),
        ("shininess", "0.5", "0", "must be above 0"),
        ("reflective", "1", "1.01", "must be from 0 to 1"),
        ("transparency", "0", "-0.5", "must be from 0 to 1"),
        ("refractive-index", "0.5", "-1.5", "must be above 0"),
    ],
)
def test_material_ranges(api: Any, key: str, good: str, bad: str, expected: str) -> None:
    load(api, f"- add: sphere\n  material:\n    {key}: {good}\n")
    message = error(api, f"- add: sphere\n  material:\n    {key}: {bad}\n")
    assert message == (
        f"/nowhere/scene.yml:13: the sphere at line 11: material: {key} {expected}, got "
        f"{float(bad) if '.' in bad or 'e' in bad else int(bad)}"
    )


def test_negative_colors_are_refused_everywhere(api: Any) -> None:
    body = """\
        - add: plane
          material:
            pattern:
              type: checkers
              colors: [[1, 1, 1], [0, -0.1, 0]]
        """
    assert error(api, body) == (
        "/nowhere/scene.yml:15: the checkers pattern's color: green is -0.1; a color's "
        "components are 0 or more (a negative amount of light does not exist)"
    )
    light = HEADER.replace("intensity: [1, 1, 1]", "intensity: [0, 0, 0]")  # a light off: fine
    load_scene_text(light, api, path="dark.yml")


@pytest.mark.parametrize(
    ("scale", "expected"),
    [
        ("1e-200", "is not invertible in floating point: it is too small (its determinant, "
                   "about 1e-600, is not 0 but below the smallest float, about 1e-308); keep the "
                   "product of its scales between about 1e-300 and 1e300"),
        ("1e200", "is not invertible in floating point: it is too large (its determinant, "
                  "about 1e600, is not 0 but above the largest float, about 1e308)"),
        ("0", "is not invertible: its determinant is 0 (a scale by 0, or a shear that flattens "
              "space onto a plane); expected an invertible transform"),
    ],
)  # fmt: skip
def test_a_transform_says_what_is_wrong_with_it(api: Any, scale: str, expected: str) -> None:
    body = f"- add: sphere\n  transform:\n    - [scale, {scale}, {scale}, {scale}]\n"
    message = error(api, body)
    assert message.startswith("/nowhere/scene.yml:12: the transform of the sphere at line 11 ")
    assert expected in message


def test_small_but_invertible_scales_load(api: Any) -> None:
    body = "- add: sphere\n  transform:\n    - [scale, 1e-100, 1e-100, 1e-100]\n"
    assert load(api, body).world.objects[0].transform[0, 0] == 1e-100


def test_a_transform_flattened_almost_onto_a_plane_is_not_merely_small(api: Any) -> None:
    body = "- add: cube\n  transform:\n    - [scale, 1, 1e-30, 1]\n    - [rotate-z, 0.7]\n" \
        "    - [scale, 1, 1e-290, 1]\n"  # fmt: skip
    assert (
        "is not invertible in floating point: it flattens space almost onto a plane (its "
        "determinant is about 1e-30 of what its rows' lengths allow)"
    ) in error(api, body)
    moved = "- add: cube\n  transform:\n    - [scale, 1e-200, 1e-200, 1e-200]\n" \
        "    - [translate, 5, 5, 5]\n"  # fmt: skip
    assert "it is too small (its determinant, about 1e-600" in error(api, moved)


# --- files that are not text -----------------------------------------------------------------


def test_a_scene_with_a_nul_byte_or_not_utf8_names_its_line(api: Any, tmp_path: Path) -> None:
    path = tmp_path / "scene.yml"
    path.write_bytes(HEADER.encode() + b"- add: sph\x00ere\n")
    with pytest.raises(SceneError) as raised:
        load_scene(path, api)
    assert str(raised.value) == (
        f"{path}:11: invalid YAML: the character #x0000 is not allowed in YAML text (special "
        "characters are not allowed); is this a binary file?"
    )
    path.write_bytes(HEADER.encode() + b"- add: sph\xe8re\n")
    with pytest.raises(SceneError) as raised:
        load_scene(path, api)
    assert str(raised.value) == (
        f"{path}:11: the scene file is not UTF-8 text: byte 0xe8 (invalid continuation byte); "
        "save it as UTF-8"
    )


def test_the_default_limits() -> None:
    assert Limits() == Limits(100, 5_000_000) == Limits(DEFAULT_MAX_DEPTH, DEFAULT_MAX_SHAPES)
    assert Limits(7).yaml_levels == 24


def test_a_name_over_several_lines_stays_on_one_line_in_the_error(api: Any) -> None:
    """Found by the fuzzer (a mutated cover.yml): a plain YAML scalar over a blank line keeps
    a line break, which the message names."""
    message = error(api, "- add: sphere\n  material: glass\n\n    bottle\n")
    assert message.startswith(
        "/nowhere/scene.yml:12: the sphere at line 11: material: 'glass\\nbottle' is not defined"
    )


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (("from: [0, 1, -5]", "from: [0, 0, 1e-320]"),
         "6: the camera's 'from' and 'to' are too close together for floating point (a length "
         "of 1e-320); expected a length from about 1e-150 to 1e150"),
        (("from: [0, 1, -5]", "from: [-1e308, 0, 0]"),
         "6: the camera's 'from' and 'to' are too far apart for floating point"),
        (("up: [0, 1, 0]", "up: [0, 1e-200, 0]"), "7: the camera's 'up' is too short"),
        (("up: [0, 1, 0]", "up: [0, 1e-300, 1e-310]"), "7: the camera's 'up' is too short"),
    ],
)  # fmt: skip
def test_camera_points_too_close_or_far_for_floats(
    api: Any, change: tuple[str, str], expected: str
) -> None:
    """Found by fuzzing the camera: 'from' 1e-320 from 'to' was a ZeroDivisionError in the
    book's normalize (the squares underflow), 1e308 apart an all-zero view transform."""
    with pytest.raises(SceneError) as raised:
        load_scene_text(HEADER.replace(*change), api, path="c.yml")
    assert str(raised.value).startswith(f"c.yml:{expected}")


def test_a_whole_number_too_large_for_a_float_is_a_clear_error(api: Any) -> None:
    """Found while fuzzing: a 400-digit integer literal was an OverflowError in float()."""
    huge = "1" + "0" * 400
    message = error(api, f"- add: sphere\n  transform:\n    - [translate, {huge}, 0, 0]\n")
    assert message == (
        "/nowhere/scene.yml:13: the sphere at line 11: transform entry: 'translate' x must be a "
        "finite number, got a whole number of 401 digits (above the largest float, about 1.8e308)"
    )
    assert load(api, f"- add: cylinder\n  max: {huge}\n").world.objects[0].maximum == math.inf
    long_word = error(api, "- add: sphere\n  transform:\n    - [rotate-x, " + "x" * 500 + "]\n")
    assert long_word.endswith("radians must be a number, got '" + "x" * 57 + "...'")


def test_an_alias_nests_exactly_as_deep_as_its_text_would() -> None:
    limits = Limits(max_depth=1)  # 12 levels of YAML
    assert compose("[" * 12 + "]" * 12, Path("x.yml"), limits)[0] is not None
    with pytest.raises(SceneError, match=r"^x\.yml:1: the scene nests too deep here"):
        compose("[" * 13 + "]" * 13, Path("x.yml"), limits)
    eleven = "&a " + "[" * 11 + "1" + "]" * 11
    assert compose(f"- {eleven}\n- *a\n", Path("x.yml"), limits)[0] is not None  # 1 + 11
    with pytest.raises(SceneError, match=r"^x\.yml:2: the alias \*a nests the scene too deep"):
        compose(f"- {eleven}\n- [*a]\n", Path("x.yml"), limits)  # 2 + 11
