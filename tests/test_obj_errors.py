"""OBJ files that cannot become a model (chapter 15's parser): each mistake is one error line
naming the file and the line; triangles without area are left out and counted; a model
without faces is an error when a scene loads it (``rtc render`` says so in one line)."""

from __future__ import annotations

from pathlib import Path

import pytest

from raytracer.obj_file import (
    ObjNoFacesError,
    ObjParseError,
    _lines,
    is_degenerate,
    obj_to_group,
    parse_obj_file,
)
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.tuples import point
from rtc.cli import main
from scene import SceneError, load_scene
from variants.registry import load_variant

SQUARE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"


def parse_error(text: str) -> ObjParseError:
    with pytest.raises(ObjParseError) as raised:
        parse_obj_file(text, source="model.obj")
    message = str(raised.value)
    assert "\n" not in message  # one line
    return raised.value


# --- faces naming vertices that do not exist ---------------------------------------------


@pytest.mark.parametrize(
    ("face", "expected"),
    [
        ("f 1 2 9", "the face names vertex 9, but 4 vertices are defined so far"),
        ("f 1 2 5", "the face names vertex 5, but 4 vertices are defined so far"),
        ("f 0 1 2", "the face names vertex 0, but vertex numbers start at 1 (or -1 for the last)"),
        ("f -5 1 2", "the face names vertex -5, but 4 vertices are defined so far"),
        ("f 1//1 2//1 3//1", "the face names normal 1, but 0 normals are defined so far"),
        ("f 1 2 3 4 7", "the face names vertex 7, but 4 vertices are defined so far"),
    ],
)
def test_a_face_naming_a_missing_vertex_names_the_file_line_and_count(
    face: str, expected: str
) -> None:
    error = parse_error(SQUARE + "\n" + face + "\n")
    assert str(error) == f"model.obj, line 6: {face!r}: {expected}"
    assert (error.source, error.line_number, error.line) == ("model.obj", 6, face)


def test_a_vertex_named_before_it_is_defined_is_an_error_even_if_defined_later() -> None:
    error = parse_error("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n")
    assert str(error).endswith("the face names vertex 3, but 2 vertices are defined so far")
    assert error.line_number == 3


def test_one_vertex_is_counted_in_the_singular() -> None:
    error = parse_error("v 0 0 0\nf 1 2 3\n")
    assert str(error).endswith("the face names vertex 2, but 1 vertex is defined so far")


# --- numbers that are not finite ------------------------------------------------------------


@pytest.mark.parametrize(
    ("line", "word"),
    [
        ("v nan 0 0", "nan"),
        ("v 0 inf 0", "inf"),
        ("v 0 0 -Infinity", "-Infinity"),
        ("v 1e999 0 0", "1e999"),  # too large for a float: infinity
        ("v 0 0 0 nan", "nan"),  # the optional w too
        ("vn 0 NaN 1", "NaN"),
    ],
)
def test_a_coordinate_that_is_not_finite_names_the_word(line: str, word: str) -> None:
    error = parse_error(f"v 1 1 1\n{line}\n")
    keyword = line.split()[0]
    assert str(error) == (
        f"model.obj, line 2: {line!r}: expected {keyword} x y z, with finite numbers, not {word!r}"
    )


def test_a_very_long_line_is_shortened_in_the_message() -> None:
    line = "v 1 2 x" + "3" * 200
    message = str(parse_error(line + "\n"))
    assert len(message) < 200 and "..." in message
    assert message.startswith("model.obj, line 1: 'v 1 2 x333")
    assert message.endswith("expected v x y z, with numbers only")


# --- binary files -------------------------------------------------------------------------


def test_a_nul_byte_means_a_binary_file_and_names_its_line() -> None:
    error = parse_error("# a comment\nsolid\x00\x01\x02 binary\n")
    assert error.line_number == 2
    assert str(error).endswith("a NUL byte: this is a binary file, not OBJ text")


# --- triangles without area -------------------------------------------------------------------


def test_is_degenerate_for_repeated_corners_and_corners_on_a_line() -> None:
    a, b, c = point(0, 0, 0), point(1, 0, 0), point(0, 1, 0)
    assert not is_degenerate(a, b, c)
    assert is_degenerate(a, a, c) and is_degenerate(a, b, b) and is_degenerate(c, b, c)
    assert is_degenerate(point(0, 0, 0), point(1, 1, 1), point(3, 3, 3))
    # on one line, but rounding leaves a cross product of about 1e-17, not 0
    assert is_degenerate(point(0, 0, 0), point(0.1, 0.2, 0.3), point(0.3, 0.6, 0.9))
    # a thin sliver (an angle of a millionth of a radian) still has an area
    assert not is_degenerate(point(0, 0, 0), point(1, 0, 0), point(1, 1e-6, 0))
    # the test is relative: the same triangle a billion times smaller has no less shape
    assert not is_degenerate(point(0, 0, 0), point(1e-9, 0, 0), point(0, 1e-9, 0))


def test_degenerate_triangles_are_left_out_and_counted_with_the_first_line() -> None:
    text = (
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 0 0 0\n"
        "f 1 2 3\n"  # line 6: a triangle
        "f 1 2 4\n"  # line 7: on the x axis
        "f 1 5 3\n"  # line 8: vertices 1 and 5 are at one place
        "f 2 2 3\n"  # line 9: a vertex twice
        "f 3 2 1\n"  # line 10: a triangle
    )
    parser = parse_obj_file(text)
    assert parser.triangles == 2
    assert len(parser.default_group.children) == 2
    assert parser.degenerate_triangles == 3
    assert parser.first_degenerate_line == 7


def test_a_polygon_loses_only_its_degenerate_fan_triangles() -> None:
    # a square written with its third corner twice: the fan (1 2 3) (1 3 3) (1 3 4) loses
    # its middle triangle and keeps the two that cover the square
    text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 3 4\n"
    parser = parse_obj_file(text)
    assert parser.triangles == 2 and parser.degenerate_triangles == 1
    assert parser.first_degenerate_line == 5


def test_degenerate_smooth_triangles_are_left_out_too() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 2//1 4//1\n"
    parser = parse_obj_file(text)
    (kept,) = parser.default_group.children
    assert isinstance(kept, SmoothTriangle)
    assert (parser.degenerate_triangles, parser.first_degenerate_line) == (1, 6)


def test_a_parser_without_degenerate_triangles_says_zero() -> None:
    parser = parse_obj_file(SQUARE + "f 1 2 4 3\n")
    assert (parser.triangles, parser.degenerate_triangles, parser.first_degenerate_line) == (
        2,
        0,
        0,
    )


# --- no faces -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "found"),
    [
        ("", "the file is empty"),
        ("v 0 0 0\nv 1 0 0\n", "2 lines, 2 vertices, 0 not understood"),
        ("hello\nworld\n", "2 lines, 0 vertices, 2 not understood"),
        (
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
            "4 lines, 3 vertices, 0 not understood, 1 degenerate triangles left out "
            "(the first at line 4)",
        ),
    ],
)
def test_text_without_a_triangle_is_an_error_when_faces_are_required(text: str, found: str) -> None:
    with pytest.raises(ObjNoFacesError) as raised:
        parse_obj_file(text, source="model.obj", require_faces=True)
    assert str(raised.value) == (
        f"model.obj: no faces ({found}); expected at least one 'f' line making a triangle"
    )
    assert isinstance(raised.value, ValueError)


def test_the_books_parser_accepts_text_without_faces() -> None:
    parser = parse_obj_file("There was a young lady named Bright\nwho traveled much faster\n")
    assert parser.ignored_lines == 2 and parser.triangles == 0
    assert obj_to_group(parser).children == []


# --- line endings ---------------------------------------------------------------------------


@pytest.mark.parametrize("chunk", [1, 2, 3, 7, 1 << 20])
def test_lines_are_read_a_chunk_at_a_time_exactly_as_splitlines_splits(chunk: int) -> None:
    text = "v 1 2 3\r\nv 4 5 6\rf 1 2 3\n\n# end\x0cg x\r\n\r\nlast"
    assert list(_lines(text, chunk)) == text.splitlines()
    assert list(_lines("", chunk)) == []


def test_windows_line_endings_keep_the_line_numbers() -> None:
    error = parse_error("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 4\r\n")
    assert error.line_number == 4 and error.line == "f 1 2 4"


# --- through a scene file and the command line ------------------------------------------------

SCENE = """\
- add: camera
  width: 4
  height: 3
  field-of-view: 1.0
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-4, 4, -4]
  intensity: [1, 1, 1]
- add: obj
  file: model.obj
"""


def scene_with(tmp_path: Path, obj: bytes) -> Path:
    (tmp_path / "model.obj").write_bytes(obj)
    scene = tmp_path / "scene.yml"
    scene.write_text(SCENE, encoding="utf-8")
    return scene


@pytest.mark.parametrize(
    ("obj", "message"),
    [
        (b"", "no faces (the file is empty)"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "line 3: "),
        (b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "1 degenerate triangles left out"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4: 'f 1 2 -4': the face names vertex -4"),
    ],
)
def test_a_broken_model_in_a_scene_is_one_error_naming_both_files(
    tmp_path: Path, obj: bytes, message: str
) -> None:
    scene = scene_with(tmp_path, obj)
    model = (tmp_path / "model.obj").resolve()
    with pytest.raises(SceneError) as raised:
        load_scene(scene, load_variant("naive").api)
    text = str(raised.value)
    assert text.startswith(f"{scene}:11: the OBJ file of the obj at line 11 is broken: {model}")
    assert message in text and "\n" not in text


def test_rtc_render_of_an_empty_model_fails_in_one_line_and_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scene = scene_with(tmp_path, b"# nothing here\n")
    output = tmp_path / "out.png"
    status = main(["render", str(scene), "-o", str(output)])
    _, err = capsys.readouterr()
    assert status == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"rtc render: {scene}:11: the OBJ file of the obj at line 11 is broken")
    assert "no faces (1 line, 0 vertices, 0 not understood)" in err
    assert not output.exists()


def test_the_cached_variant_checks_the_faces_through_its_hooks(tmp_path: Path) -> None:
    scene = scene_with(tmp_path, b"v 0 0 0\n")
    with pytest.raises(SceneError, match="no faces"):
        load_scene(scene, load_variant("cached").api)


def test_degenerate_triangles_in_a_scene_are_skipped_and_counted_in_the_notes(
    tmp_path: Path,
) -> None:
    obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 2 2 3\n"
    scene = load_scene(scene_with(tmp_path, obj), load_variant("naive").api)
    model = scene.world.objects[0]
    assert sum(len(getattr(c, "children", [c])) for c in model.children) == 1
    path = (tmp_path / "model.obj").resolve()
    assert f"{path}: 2 degenerate triangles (zero area) skipped, the first at line 6" in scene.notes
