"""Texture mapping (the bonus chapter, numbered 19 here): properties of the mappings and UV
patterns, the PPM reader's errors, the scene loader's texture patterns and their errors,
and the variants that must draw a textured scene exactly as ``naive`` does."""

from __future__ import annotations

import math
import pickle
import re
from collections.abc import Mapping
from pathlib import Path
from textwrap import dedent
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from raytracer import (
    Canvas,
    Color,
    CubeMap,
    PPMError,
    TextureMap,
    UVAlignCheck,
    UVImage,
    canvas_from_ppm,
    canvas_to_ppm,
    cube_map,
    cube_uv_back,
    cube_uv_down,
    cube_uv_front,
    cube_uv_left,
    cube_uv_right,
    cube_uv_up,
    cylindrical_map,
    face_from_point,
    inverse,
    pattern_at,
    pattern_at_shape,
    planar_map,
    point,
    rotation_y,
    set_pattern_transform,
    set_transform,
    sphere,
    spherical_map,
    texture_map,
    translation,
    uv_align_check,
    uv_checkers,
    uv_image,
    uv_pattern_at,
    write_pixel,
)
from raytracer.camera import RenderSettings
from raytracer.textures import CUBE_UV
from raytracer.textures.mappings import Face
from raytracer.tuples import Tuple
from scene import SceneError, load_scene
from steps.book import Book
from steps.errors import CheckFailed
from steps.phrases import then
from variants.cached import CACHED_CLASSES
from variants.prealloc.errors import PreallocUnsupported
from variants.prealloc.patterns import pattern_record
from variants.registry import load_variant

SCENES = Path(__file__).resolve().parent.parent / "scenes"
BLACK, WHITE = Color(0, 0, 0), Color(1, 1, 1)
RED, GREEN, BLUE = Color(1, 0, 0), Color(0, 1, 0), Color(0, 0, 1)

coordinate = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
unit = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False)


def in_unit_range(u: float, v: float) -> bool:
    """u and v from 0 to 1; 1 itself is reached at a seam (``-0.0 % 1 == 0.0``, but
    ``-1e-20 % 1 == 1.0`` and ``atan2(-0.0, -1) == -π``)."""
    return 0.0 <= u <= 1.0 and 0.0 <= v <= 1.0


# ------------------------------------------------------------------------ properties


@given(coordinate, coordinate, coordinate)
def test_the_mappings_give_u_and_v_from_0_to_1(x: float, y: float, z: float) -> None:
    p = point(x, y, z)
    for mapping in (spherical_map, planar_map, cylindrical_map):
        u, v = mapping(p)
        assert in_unit_range(u, v), f"{mapping.__name__}({p}) = {(u, v)}"


def test_the_spherical_map_of_the_origin_and_of_tiny_points_is_defined() -> None:
    assert spherical_map(point(0, 0, 0)) == (0.5, 0.5)
    u, v = spherical_map(point(1e-200, 1e-160, 0))  # y*y underflows: y / radius may pass 1
    assert in_unit_range(u, v) and v == pytest.approx(1.0)


@given(st.floats(min_value=0, max_value=2 * math.pi), st.floats(min_value=0.01, max_value=3.13))
def test_the_spherical_map_is_longitude_and_latitude(longitude: float, polar: float) -> None:
    """A point at an angle ``polar`` from +y and ``longitude`` round y from -z towards +x
    maps to u = longitude / 2π and v = 1 - polar / π."""
    p = point(
        math.sin(polar) * math.sin(longitude),
        math.cos(polar),
        -math.sin(polar) * math.cos(longitude),
    )
    u, v = spherical_map(p)
    assert v == pytest.approx(1 - polar / math.pi, abs=1e-9)
    assert min(abs(u - longitude / (2 * math.pi)), 1 - abs(u - longitude / (2 * math.pi))) < 1e-9


@given(unit, unit)
def test_each_cube_face_maps_its_square_onto_the_unit_square(a: float, b: float) -> None:
    on_faces: dict[Face, Tuple] = {
        "left": point(-1, a, b),
        "right": point(1, a, b),
        "down": point(a, -1, b),
        "up": point(a, 1, b),
        "back": point(a, b, -1),
        "front": point(a, b, 1),
    }
    for face, p in on_faces.items():
        u, v = CUBE_UV[face](p)
        assert in_unit_range(u, v), f"cube_uv_{face}({p}) = {(u, v)}"
        if max(abs(a), abs(b)) < 1:  # not on an edge: the face is the one it is on
            assert face_from_point(p) == face


def test_the_cube_uv_functions_are_the_books_names() -> None:
    assert [CUBE_UV[f] for f in ("front", "back", "left", "right", "up", "down")] == [
        cube_uv_front,
        cube_uv_back,
        cube_uv_left,
        cube_uv_right,
        cube_uv_up,
        cube_uv_down,
    ]


@given(st.integers(1, 40), st.integers(1, 40), st.data())
def test_uv_checkers_alternate_from_square_to_square(width: int, height: int, data: Any) -> None:
    checkers = uv_checkers(width, height, BLACK, WHITE)
    i = data.draw(st.integers(0, width - 1))
    j = data.draw(st.integers(0, height - 1))
    u, v = (i + 0.5) / width, (j + 0.5) / height  # the centre of square (i, j)
    expected = BLACK if (i + j) % 2 == 0 else WHITE
    assert uv_pattern_at(checkers, u, v) == expected
    if i + 1 < width:
        assert uv_pattern_at(checkers, (i + 1.5) / width, v) != expected
    if j + 1 < height:
        assert uv_pattern_at(checkers, u, (j + 1.5) / height) != expected


@pytest.mark.parametrize("size", [0, -2, math.inf, math.nan])
def test_uv_checkers_need_a_positive_size(size: float) -> None:
    with pytest.raises(ValueError, match="uv_checkers: the width must be a positive number"):
        uv_checkers(size, 2, BLACK, WHITE)


def test_uv_image_corners_are_the_images_corners() -> None:
    c = Canvas(3, 2)
    write_pixel(c, 0, 1, RED)  # bottom left
    write_pixel(c, 2, 0, GREEN)  # top right
    image = uv_image(c)
    assert uv_pattern_at(image, 0, 0) == RED
    assert uv_pattern_at(image, 1, 1) == GREEN
    assert uv_pattern_at(image, 0.5, 0.5) == BLACK  # round(1.0), round(0.5) = 0: the top row


def test_a_texture_map_is_a_pattern_with_a_transform_and_the_cached_twins_know_it() -> None:
    pattern = texture_map(uv_checkers(2, 1, BLACK, WHITE), spherical_map)
    s = sphere()
    set_transform(s, translation(0, 0, 5))
    assert pattern_at_shape(pattern, s, point(1, 0, 5)) == BLACK  # u = 0.25
    set_pattern_transform(pattern, rotation_y(math.pi))
    assert pattern_at_shape(pattern, s, point(1, 0, 5)) == WHITE
    assert TextureMap in CACHED_CLASSES and CubeMap in CACHED_CLASSES
    cached = load_variant("cached").api
    twin: Any = cached["texture_map"](uv_checkers(2, 1, BLACK, WHITE), cached["spherical_map"])
    twin.transform = rotation_y(math.pi)
    assert twin.inverse_transform == inverse(rotation_y(math.pi))  # kept when set
    assert pattern_at(twin, point(1, 0, 0)) == pattern_at(pattern, point(1, 0, 0))
    assert type(twin) is CACHED_CLASSES[TextureMap]


def test_texture_patterns_survive_pickling_for_the_pool() -> None:
    pattern = cube_map(*(uv_image(canvas_from_ppm("P3 1 1 255 255 0 0")) for _ in range(6)))
    copy = pickle.loads(pickle.dumps(pattern))
    assert copy == pattern and pattern_at(copy, point(1, 0.3, 0.2)) == RED
    mapped = pickle.loads(pickle.dumps(texture_map(uv_checkers(2, 2, RED, BLUE), planar_map)))
    assert mapped.mapping is planar_map


# ------------------------------------------------------------------------ prealloc


@given(coordinate, coordinate, coordinate)
def test_prealloc_texture_records_give_the_references_colors_exactly(
    x: float, y: float, z: float
) -> None:
    image = Canvas(4, 3, [Color(i / 12, 1 - i / 12, (i * 5 % 12) / 12) for i in range(12)])
    uv_patterns = [
        uv_checkers(7, 3, RED, BLUE),
        uv_align_check(WHITE, RED, GREEN, BLUE, BLACK),
        uv_image(image),
    ]
    p = point(x, y, z)
    on_cube = point(*(c / max(abs(x), abs(y), abs(z), 1e-300) for c in (x, y, z)))
    for uv in uv_patterns:
        for mapping in (spherical_map, planar_map, cylindrical_map):
            pattern = texture_map(uv, mapping)
            out = [0.0, 0.0, 0.0]
            pattern_record(pattern).pattern_at_into([p.x, p.y, p.z, p.w], out)
            expected = pattern_at(pattern, p)
            assert out == [expected.red, expected.green, expected.blue]
        cube = cube_map(uv, uv_patterns[0], uv, uv_patterns[1], uv, uv_patterns[2])
        out = [0.0, 0.0, 0.0]
        pattern_record(cube).pattern_at_into([on_cube.x, on_cube.y, on_cube.z, 1.0], out)
        expected = pattern_at(cube, on_cube)
        assert out == [expected.red, expected.green, expected.blue]


def test_prealloc_refuses_a_mapping_it_does_not_know() -> None:
    pattern = TextureMap(uv_checkers(2, 2, RED, BLUE), lambda p: (0.5, 0.5))
    with pytest.raises(PreallocUnsupported, match="no implementation for the texture mapping"):
        pattern_record(pattern)


# ------------------------------------------------------------------------ PPM errors


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "PPM line 1: the text is empty"),
        ("P6\n1 1\n255\n", "PPM line 1: the magic number is 'P6', not 'P3'"),
        ("# made by hand\nP32\n1 1\n255\n0 0 0\n", "PPM line 2: the magic number is 'P32'"),
        ("P3\n0 1\n255\n", "PPM line 2: the width is '0'; expected a whole number from 1"),
        ("P3\n2 -1\n255\n", "PPM line 2: the height is '-1'"),
        ("P3\n2 1.5\n255\n", "PPM line 2: the height is '1.5'"),
        ("P3\n1 1\n", "PPM line 2: the text ends before the maximum value"),
        ("P3\n1 1\n0\n0 0 0\n", "PPM line 3: the maximum value is '0'"),
        ("P3\n1 1\n100\n0 0\n101\n", "PPM line 5: the value 101 is above the maximum value 100"),
        ("P3\n1 1\n255\n0 x 0\n", "PPM line 4: 'x' is not a color value"),
        ("P3\n1 1\n255\n0 +5 0\n", "PPM line 4: '+5' is not a color value"),
        ("P3\n2 1\n255\n0 0 0\n0 0\n", "PPM line 5: the text ends after 5 of the 6 values"),
        ("P3\n1 1\n255\n0 0 0\n\n7\n", "PPM line 6: more values than the 1x1 image has (3"),
    ],
)
def test_a_broken_ppm_is_one_error_line_naming_the_line(text: str, message: str) -> None:
    with pytest.raises(PPMError) as raised:
        canvas_from_ppm(text)
    assert str(raised.value).startswith(message), str(raised.value)
    assert "\n" not in str(raised.value)
    assert isinstance(raised.value, ValueError)


def test_ppm_comments_whitespace_and_bytes() -> None:
    text = "P3#magic\n# size\n 2\t1 # two by one\n65535\n65535 0 0 0 0 65535"
    c = canvas_from_ppm(text.encode("ascii"))  # type: ignore[arg-type]
    assert (c.width, c.height) == (2, 1)
    assert c.pixels == [RED, BLUE]


def test_ppm_reads_back_what_canvas_to_ppm_writes() -> None:
    c = Canvas(5, 4, [Color(i / 19, (19 - i) / 19, 0.5) for i in range(20)])
    back = canvas_from_ppm(canvas_to_ppm(c))
    for a, b in zip(c.pixels, back.pixels, strict=True):
        for x, y in ((a.red, b.red), (a.green, b.green), (a.blue, b.blue)):
            assert abs(x - y) <= 0.5 / 255 + 1e-12


# ------------------------------------------------------------------------ the steps


def test_should_fail_passes_on_a_value_error_and_fails_without_one() -> None:
    book = Book(load_variant("naive").api)
    book.variables["ppm"] = "P3\n1 1\n255\n0 0 0\n"
    with pytest.raises(CheckFailed, match="expected: a ValueError"):
        then(book, "canvas_from_ppm(ppm) should fail")
    book.variables["ppm"] = "P32\n1 1\n255\n0 0 0\n"
    then(book, "canvas_from_ppm(ppm) should fail")


def test_a_bare_word_compares_with_a_string_and_a_variable_still_wins() -> None:
    book = Book(load_variant("naive").api)
    then(book, "face_from_point(point(-2, 0, 0)) = left")
    with pytest.raises(CheckFailed):
        then(book, "face_from_point(point(-2, 0, 0)) = right")
    book.variables["left"] = "right"
    with pytest.raises(CheckFailed):
        then(book, "face_from_point(point(-2, 0, 0)) = left")


# ------------------------------------------------------------------------ the scene loader

HEADER = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 0.8
  from: [0, 1, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: sphere
  material:
    pattern:
"""  # 13 lines: the pattern's keys start at line 14, indented by 6


@pytest.fixture(scope="module")
def api() -> Mapping[str, Any]:
    return load_variant("naive").api


def scene_with(tmp_path: Path, pattern: str) -> Path:
    path = tmp_path / "scene.yml"
    body = "".join("      " + line + "\n" for line in dedent(pattern).strip("\n").splitlines())
    path.write_text(HEADER + body, encoding="utf-8")
    return path


def loaded_pattern(tmp_path: Path, api: Mapping[str, Any], pattern: str) -> Any:
    scene = load_scene(scene_with(tmp_path, pattern), api)
    return scene.world.objects[0].material.pattern


def scene_error(tmp_path: Path, api: Mapping[str, Any], pattern: str) -> str:
    with pytest.raises(SceneError) as raised:
        load_scene(scene_with(tmp_path, pattern), api)
    message = str(raised.value)
    assert "\n" not in message
    return message


def write_png(path: Path, width: int, height: int, rgb: tuple[int, int, int]) -> None:
    from PIL import Image

    Image.new("RGB", (width, height), rgb).save(path)


def test_the_loader_reads_each_mapping_and_uv_pattern(
    tmp_path: Path, api: Mapping[str, Any]
) -> None:
    spherical = loaded_pattern(
        tmp_path,
        api,
        """
        type: map
        mapping: spherical
        uv_pattern: {type: checkers, width: 4, height: 2, colors: [[1, 0, 0], [0, 0, 1]]}
        transform: [[rotate-y, 1]]
        """,
    )
    assert spherical == TextureMap(uv_checkers(4, 2, RED, BLUE), spherical_map,
                                   transform=rotation_y(1))  # fmt: skip
    (tmp_path / "img.ppm").write_text("P3 1 1 255 0 255 0\n")
    write_png(tmp_path / "img.png", 2, 1, (0, 0, 255))
    for mapping, function in (("planar", planar_map), ("cylindrical", cylindrical_map)):
        for name, color in (("img.ppm", GREEN), ("img.png", BLUE)):
            pattern = loaded_pattern(
                tmp_path,
                api,
                f"""
                type: map
                mapping: {mapping}
                uv_pattern: {{type: image, file: {name}}}
                """,
            )
            assert isinstance(pattern, TextureMap) and pattern.mapping is function
            assert isinstance(pattern.uv_pattern, UVImage)
            assert uv_pattern_at(pattern.uv_pattern, 0.3, 0.6) == color


def test_the_loader_reads_a_cube_map_and_decodes_one_image_once(
    tmp_path: Path, api: Mapping[str, Any]
) -> None:
    write_png(tmp_path / "face.png", 4, 4, (255, 0, 0))
    pattern = loaded_pattern(
        tmp_path,
        api,
        """
        type: map
        mapping: cube
        uv_pattern: {type: image, file: face.png}
        up:
          type: align_check
          colors: {main: [1, 1, 1], ul: [1, 0, 0], ur: [0, 1, 0], bl: [0, 0, 1], br: [0, 0, 0]}
        front: {type: image, file: ./face.png}
        """,
    )
    assert isinstance(pattern, CubeMap)
    assert pattern.up == UVAlignCheck(WHITE, RED, GREEN, BLUE, BLACK)
    canvases = [
        getattr(pattern, face).canvas for face in ("left", "front", "right", "back", "down")
    ]
    assert all(c is canvases[0] for c in canvases)  # decoded once, shared
    assert pattern_at(pattern, point(0, 0, 1)) == RED


@pytest.mark.parametrize(
    ("pattern", "message"),
    [
        ("type: map\nmapping: sphere\nuv_pattern: {type: checkers}",
         r"scene\.yml:15: unknown mapping 'sphere'; known: spherical, planar, cylindrical, cube"),
        ("type: map\nuv_pattern: {type: checkers}",
         r"scene\.yml:14: the map pattern has no 'mapping'"),
        ("type: map\nmapping: planar",
         r"scene\.yml:14: the planar map pattern has no 'uv_pattern'"),
        ("type: map\nmapping: planar\nuv_pattern: {type: dots}",
         r"scene\.yml:16: unknown UV pattern type 'dots'; known: checkers, align_check, image"),
        ("type: map\nmapping: planar\nuv_pattern:\n"
         "  {type: checkers, width: 0, height: 2, colors: [[1, 1, 1], [0, 0, 0]]}",
         r"scene\.yml:17: the planar map's uv_pattern: the checkers' width \(squares along u\) "
         r"must be a whole number from 1 to 100000, got 0"),
        ("type: map\nmapping: planar\nuv_pattern:\n"
         "  type: checkers\n  width: 2\n  height: -3\n  colors: [[1, 1, 1], [0, 0, 0]]",
         r"scene\.yml:19: .*the checkers' height \(squares along v\) must be a whole number "
         r"from 1 to 100000, got -3"),
        ("type: map\nmapping: planar\nuv_pattern:\n  type: checkers\n  width: 2\n  height: 2\n"
         "  colors: [[1, 1, 1]]",
         r"scene\.yml:20: .*checkers take 2 colors"),
        ("type: map\nmapping: planar\nuv_pattern:\n  type: align_check\n"
         "  colors: {main: [1, 1, 1], ul: [1, 0, 0]}",
         r"scene\.yml:18: .*the align check's colors have no ur, bl, br"),
        ("type: map\nmapping: spherical\nleft: {type: image, file: a.png}",
         r"scene\.yml:16: 'left' is a face of 'mapping: cube'; a spherical map takes one "
         r"uv_pattern"),
        ("type: map\nmapping: cube\nleft: {type: image, file: a.png}",
         r"scene\.yml:14: the cube map pattern has no UV pattern for front, right, back, up, "
         r"down"),
        ("type: map\nmapping: planar\nuv_pattern: {type: image, file: missing.png}",
         r"scene\.yml:16: image file not found: .*missing\.png \('missing\.png' is read "
         r"relative to the scene file's folder\)"),
        ("type: map\nmapping: planar\nuv_pattern: {type: checkers, size: 2}",
         r"scene\.yml:16: unknown key 'size' in the planar map's uv_pattern \(checkers\)"),
        ("type: map\nmapping: planar\nmapping2: cube",
         r"scene\.yml:16: unknown key 'mapping2' in a map pattern"),
        ("type: map\nmapping: planar\nuv_pattern: {type: checkers, width: 2, height: 2, "
         "colors: [[1, 1, 1], [0, 0, 0]]}\ntransform: [[scale, 0, 1, 1]]",
         r"scene\.yml:17: the transform of the map pattern at line 14 is not invertible"),
        ("type: dots\ncolors: [[1, 1, 1], [0, 0, 0]]",
         r"scene\.yml:14: unknown pattern type 'dots'; known: stripes, gradient, rings, "
         r"checkers, map"),
    ],
)  # fmt: skip
def test_a_texture_mistake_is_one_line_naming_the_scene_file_and_line(
    tmp_path: Path, api: Mapping[str, Any], pattern: str, message: str
) -> None:
    found = scene_error(tmp_path, api, pattern)
    assert re.search(message, found), found


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("bad.png", b"not a png at all",
         r"the image file .*bad\.png is not a PNG or PPM image: it starts with neither"),
        ("cut.png", None, r"the image file .*cut\.png is broken: "),
        ("bad.ppm", b"P3\n1 1\n255\n0 300 0\n",
         r"the image file .*bad\.ppm is not a plain PPM image: PPM line 4: the value 300 is "
         r"above the maximum value 255"),
        ("bad.ppm", b"P7\n", r"bad\.ppm is not a plain PPM image: PPM line 1: the magic"),
        ("folder.png", "folder", r"cannot read image file .*folder\.png: it is a folder"),
    ],
)  # fmt: skip
def test_a_broken_image_is_one_line_naming_the_scene_line_and_the_image(
    tmp_path: Path, api: Mapping[str, Any], name: str, content: bytes | str | None, message: str
) -> None:
    target = tmp_path / name
    if content is None:  # a PNG cut short: the header is fine, the pixels are missing
        write_png(target, 32, 32, (10, 20, 30))
        target.write_bytes(target.read_bytes()[:60])
    elif content == "folder":
        target.mkdir()
    else:
        assert isinstance(content, bytes)
        target.write_bytes(content)
    found = scene_error(
        tmp_path, api, f"type: map\nmapping: planar\nuv_pattern: {{type: image, file: {name}}}"
    )
    assert found.startswith(f"{tmp_path / 'scene.yml'}:16: "), found
    assert re.search(message, found), found


# ------------------------------------------------------------------------ the variants


def _pixels(name: str, path: Path, size: tuple[int, int]) -> list[tuple[float, float, float]]:
    variant = load_variant(name)
    scene = load_scene(path, variant.api, variant=variant.name).resized(*size)
    image = variant.api["render"](scene.camera, scene.world, RenderSettings())
    pixel_at = variant.api["pixel_at"]
    return [
        (float(c.red), float(c.green), float(c.blue))
        for c in (pixel_at(image, x, y) for y in range(image.height) for x in range(image.width))
    ]


@pytest.fixture(scope="module")
def naive_textures() -> list[tuple[float, float, float]]:
    pixels = _pixels("naive", SCENES / "textures.yml", (16, 12))
    assert len({tuple(round(v, 3) for v in p) for p in pixels}) > 40  # not a blank picture
    return pixels


@pytest.mark.parametrize("name", ["cached", "prealloc", "robust", "pooled[workers=2]:prealloc"])
def test_the_variants_draw_the_textured_scene_as_naive_does(
    name: str, naive_textures: list[tuple[float, float, float]]
) -> None:
    got = _pixels(name, SCENES / "textures.yml", (16, 12))
    tolerance = load_variant(name).tolerance
    worst = max(
        abs(a - b)
        for p, q in zip(got, naive_textures, strict=True)
        for a, b in zip(p, q, strict=True)
    )
    if tolerance == 0:
        assert got == naive_textures, f"{name} differs from naive by up to {worst:.3g}"
    else:
        assert worst <= tolerance, f"{name} differs from naive by up to {worst:.3g}"
