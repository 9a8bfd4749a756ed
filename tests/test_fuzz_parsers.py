"""Fuzzing the parsers (issue 19, item 2): scene YAML, OBJ text, PPM text, variant names and
result files, with hypothesis. For any input the only outcomes allowed are a parsed value or
the parser's own clear error (one line, naming the file or the text), never another exception
and never a hang (the suite's hang guards: ``tests/conftest.py``).

The scene inputs are random structures in the scene format's vocabulary (YAML aliases
included: a value repeated in the structure is written once with an anchor), random text,
random nesting depths, and random mutations (lines deleted, moved, re-indented, words
replaced) of the project's own scenes in ``scenes`` and of their OBJ and image files.
Scenes that load are checked against the limits they were loaded under. ``hypothesis.event``
labels each outcome: ``--hypothesis-show-statistics`` shows how many parsed and how many
were clear errors.
"""

from __future__ import annotations

import json
import math
import re
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import event, given
from hypothesis import strategies as st

import scenes
from harness.engine.results import ResultFileError, check_run, load_run
from raytracer.canvas import Canvas, canvas, canvas_to_ppm, pixel_at, write_pixel
from raytracer.colors import color
from raytracer.obj_file import ObjFileError, ObjParser, parse_obj_file
from raytracer.ppm import PPMError, canvas_from_ppm
from scene import SceneError, load_scene_text
from scene.limits import Limits
from scene.loader import AREA_LIGHT_KEYS, CAMERA_KEYS, LIGHT_KEYS
from scene.materials import MATERIAL_KEYS, PATTERNS
from scene.shapes import KEYS, OPERATIONS
from scene.textures import FACES, MAP_KEYS, MAPPINGS, UV_KEYS
from scene.transforms import TRANSFORMS
from variants.registry import VariantError, VariantSpec, load_variant, parse_variant_name

SCENES = scenes.FOLDER
API = load_variant("naive").api
# every scene of the project but the one whose meshes take seconds to load (six-knots.yml)
FAST_SCENES = sorted(p for p in SCENES.glob("*.yml") if "meshes/" not in p.read_text())
RESULT_FILE = Path(__file__).parent / "data" / "bench-schema1.json"


def one_line(error: BaseException, starts: str) -> None:
    """A clear error: one line, starting with what it names (a file, the text)."""
    message = str(error)
    assert "\n" not in message and "Traceback" not in message, message
    assert message.startswith(starts), message


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of scenes (scenes, OBJ models, textures) that mutations may change."""
    folder = tmp_path_factory.mktemp("fuzz") / "scenes"
    shutil.copytree(SCENES, folder, ignore=shutil.ignore_patterns("meshes"))
    return folder


# ----------------------------------------------------------------------------- mutations

NASTY_WORDS = (
    "0", "-1", "1e-200", "1e200", "1e999", ".nan", ".inf", "-.inf", "nan", "''", "x", "[]",
    "{}", "[1, 2]", "true", "null", "~", "65537", "-0", "0x10", "1_000", "*nowhere", "&a",
    "!!binary AA==", "!!python/object:os.system", "<<: *a", "? x", "|", ">", "'", '"', "#",
    "- ", ": ", "\t", "\x00", "é", "😀", "[[[[", "}}}", "&a [*a]", "%YAML 1.1", "---", "...",
    "1" + "0" * 400, "-0x" + "f" * 300, "1." + "0" * 400 + "e5", "1" * 5000,
)  # fmt: skip


@st.composite
def mutated_lines(draw: st.DrawFn, text: str) -> str:
    """``text`` with 1 to 4 mutations: a line deleted, duplicated, moved, re-indented or cut
    short; a word replaced by a nasty one; characters inserted."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, 4))):
        if not lines:
            lines = [draw(st.sampled_from(NASTY_WORDS))]
        at = draw(st.integers(0, len(lines) - 1))
        kind = draw(st.sampled_from(("delete", "duplicate", "move", "indent", "cut", "word",
                                     "insert")))  # fmt: skip
        if kind == "delete":
            del lines[at]
        elif kind == "duplicate":
            lines.insert(at, lines[at])
        elif kind == "move":
            lines.insert(draw(st.integers(0, len(lines) - 1)), lines.pop(at))
        elif kind == "indent":
            shift = draw(st.integers(-4, 4))
            lines[at] = " " * shift + lines[at] if shift > 0 else lines[at][-shift:]
        elif kind == "cut":
            lines[at] = lines[at][: draw(st.integers(0, max(0, len(lines[at]) - 1)))]
        elif kind == "word":
            words = lines[at].split(" ")
            index = draw(st.integers(0, len(words) - 1))
            words[index] = draw(st.sampled_from(NASTY_WORDS) | st.text(max_size=6))
            lines[at] = " ".join(words)
        else:
            column = draw(st.integers(0, len(lines[at])))
            extra = draw(st.text(alphabet="-:[]{},&*!|>'\"#%@` \t\n0123456789.e", max_size=4))
            lines[at] = lines[at][:column] + extra + lines[at][column:]
    return "\n".join(lines) + draw(st.sampled_from(("\n", "", "\r\n")))


def _shapes_and_depth(shape: Any) -> tuple[int, int]:
    """The shapes in ``shape`` (itself included) and how deep groups and CSGs nest in it."""
    inside = list(getattr(shape, "children", None) or ())
    inside += [s for s in (getattr(shape, "left", None), getattr(shape, "right", None)) if s]
    counts = [_shapes_and_depth(s) for s in inside]
    return 1 + sum(c for c, _ in counts), max((d + 1 for _, d in counts), default=0)


def load_or_clear_error(text: str, path: Path, limits: Limits | None = None,
                        divide: bool = False) -> Any:  # fmt: skip
    """The loaded scene (checked against ``limits``), or None after a clear ``SceneError``."""
    try:
        scene = load_scene_text(text, API, path=path, limits=limits, progress=False)
        world = scene.book_world(divide=divide)
    except SceneError as error:
        one_line(error, str(path))
        event("clear error")
        return None
    event("parsed")
    if limits is not None and not divide:
        totals = [_shapes_and_depth(shape) for shape in world.objects]
        assert sum(count for count, _ in totals) <= limits.max_shapes
        assert max((depth for _, depth in totals), default=0) <= limits.max_depth
    return scene


@given(data=st.data(), index=st.integers(0, len(FAST_SCENES) - 1))
def test_mutated_project_scenes_load_or_fail_clearly(
    data: st.DataObject, index: int, workdir: Path
) -> None:
    path = workdir / FAST_SCENES[index].name
    text = data.draw(mutated_lines(path.read_text(encoding="utf-8")))
    load_or_clear_error(text, path, divide=data.draw(st.booleans()))


OBJ_MODELS = ("gem.obj", "icosphere.obj")


@given(data=st.data(), model=st.sampled_from(OBJ_MODELS))
def test_mutated_obj_models_in_a_scene_load_or_fail_clearly(
    data: st.DataObject, model: str, workdir: Path
) -> None:
    mutated = data.draw(mutated_lines((SCENES / model).read_text(encoding="utf-8")))
    (workdir / "fuzz-model.obj").write_bytes(mutated.encode("utf-8", "surrogatepass"))
    scene = (SCENES / "mesh.yml").read_text(encoding="utf-8").replace(model, "fuzz-model.obj")
    load_or_clear_error(scene, workdir / "mesh.yml")


IMAGES = {"label.ppm": "textures/label.ppm", "planet.png": "textures/planet.png"}


@given(data=st.data(), image=st.sampled_from(sorted(IMAGES)))
def test_damaged_texture_images_load_or_fail_clearly(
    data: st.DataObject, image: str, workdir: Path
) -> None:
    original = bytearray((SCENES / IMAGES[image]).read_bytes())
    for _ in range(data.draw(st.integers(1, 6))):
        kind = data.draw(st.sampled_from(("flip", "cut", "insert")))
        at = data.draw(st.integers(0, len(original) - 1))
        if kind == "flip":
            original[at] = data.draw(st.integers(0, 255))
        elif kind == "cut":
            del original[at:]
            if not original:
                break
        else:
            original[at:at] = data.draw(st.binary(min_size=1, max_size=8))
    suffix = Path(image).suffix
    (workdir / "textures" / f"fuzz{suffix}").write_bytes(bytes(original))
    scene = (SCENES / "textures.yml").read_text(encoding="utf-8")
    load_or_clear_error(scene.replace(image, f"fuzz{suffix}"), workdir / "textures.yml")


# --------------------------------------------------------------- random scene structures

ADDABLE = ("camera", "light", "area_light", *KEYS, "a", "b")
ALL_KEYS = sorted(
    {*CAMERA_KEYS, *LIGHT_KEYS, *AREA_LIGHT_KEYS, *(k for ks in KEYS.values() for k in ks),
     *MATERIAL_KEYS, *MAP_KEYS, *(k for ks in UV_KEYS.values() for k in ks), "define", "value",
     "extend", "main", "ul", "ur", "bl", "br"}
)  # fmt: skip
WORDS = (*ADDABLE, *PATTERNS, "map", *MAPPINGS, *UV_KEYS, *FACES, *TRANSFORMS, *OPERATIONS,
         "label.ppm", "textures/planet.png", "gem.obj", "missing.obj")  # fmt: skip
NUMBERS = st.sampled_from(
    (
        0,
        1,
        -1,
        2,
        0.5,
        3,
        16,
        1e-200,
        1e200,
        1e308,
        5e-324,
        65536,
        math.nan,
        math.inf,
        -math.inf,
        10**400,
        -(2**1100),
    )
) | st.floats(-10, 10, allow_nan=False)
SCALARS = NUMBERS | st.sampled_from(WORDS) | st.booleans() | st.none() | st.text(max_size=4)


def _repeated(value: Any, times: int) -> list[Any]:
    return [value] * times  # one object many times: YAML writes an anchor and aliases


VALUES = st.recursive(
    SCALARS,
    lambda inner: st.lists(inner, max_size=4)
    | st.lists(NUMBERS, min_size=3, max_size=3)  # a point, a color
    | st.tuples(st.sampled_from(sorted(TRANSFORMS)), NUMBERS, NUMBERS, NUMBERS).map(list)
    | st.dictionaries(st.sampled_from(ALL_KEYS), inner, max_size=5)
    | st.fixed_dictionaries({"add": st.sampled_from(ADDABLE)},
                            optional={k: inner for k in ("children", "left", "right", "transform",
                                                         "material", "min", "max")})
    | st.builds(_repeated, inner, st.integers(2, 12)),
    max_leaves=40,
)  # fmt: skip
ITEMS = (
    st.fixed_dictionaries(
        {"add": st.sampled_from(ADDABLE)},
        optional={k: VALUES for k in ALL_KEYS if k not in ("add", "define")},
    )
    | st.fixed_dictionaries(
        {"define": st.sampled_from(("a", "b", "sphere", "c"))},
        optional={"value": VALUES, "extend": st.sampled_from(("a", "b", "x"))},
    )
    | VALUES
)
HEADER = [
    {"add": "camera", "width": 4, "height": 2, "field-of-view": 1, "from": [0, 1, -5],
     "to": [0, 0, 0], "up": [0, 1, 0]},
    {"add": "light", "at": [-5, 5, -5], "intensity": [1, 1, 1]},
]  # fmt: skip
LIMITS = st.builds(Limits, st.integers(1, 30), st.integers(1, 3000))


@given(
    items=st.lists(ITEMS, max_size=6),
    header=st.booleans(),
    limits=LIMITS,
    flow=st.booleans(),
)
def test_random_scene_structures_load_or_fail_clearly(
    items: list[Any], header: bool, limits: Limits, flow: bool, workdir: Path
) -> None:
    document = (HEADER if header else []) + items
    text = yaml.safe_dump(document, default_flow_style=flow, allow_unicode=True)
    load_or_clear_error(text, workdir / "random.yml", limits)


@given(text=st.text(alphabet="-:[]{},&*!|>'\"#%@`? \t\n\r0123456789.eaddsphergoupcmil\x00\x85",
                    max_size=300))  # fmt: skip
def test_random_text_loads_or_fails_clearly(text: str, workdir: Path) -> None:
    load_or_clear_error(text, workdir / "text.yml")


@given(
    depth=st.integers(0, 3000),
    style=st.sampled_from(("flow-list", "flow-map", "block", "groups")),
    limits=st.none() | LIMITS,
)
def test_any_nesting_depth_loads_or_fails_clearly(
    depth: int, style: str, limits: Limits | None, workdir: Path
) -> None:
    if style == "flow-list":
        body = "- " + "[" * depth + "]" * depth + "\n"
    elif style == "flow-map":
        body = "- " + "{a: " * depth + "1" + "}" * depth + "\n"
    elif style == "block":
        body = "".join("  " * i + "- \n" for i in range(depth)) + "  " * depth + "- 1\n"
    else:
        body = "- " + "{add: group, children: [" * depth + "{add: sphere}" + "]}" * depth + "\n"
    text = yaml.safe_dump(HEADER) + body
    load_or_clear_error(text, workdir / "deep.yml", limits)


def mostly(usual: st.SearchStrategy[Any], rare: st.SearchStrategy[Any]) -> st.SearchStrategy[Any]:
    """``usual`` seven times in eight, else ``rare`` (so that many inputs get far)."""
    return st.integers(0, 7).flatmap(lambda i: rare if i == 0 else usual)


# mostly ordinary numbers (so that many cameras load and their views are checked), with the
# extreme ones mixed in
COORDINATE = mostly(st.floats(-1e3, 1e3), NUMBERS)
TRIPLES = st.lists(COORDINATE, min_size=3, max_size=3)
SIDE = mostly(st.integers(1, 64), NUMBERS)


@given(
    eye=TRIPLES, to=TRIPLES, up=TRIPLES, fov=mostly(st.floats(0.01, 3.1), NUMBERS),
    size=st.tuples(SIDE, SIDE), light=TRIPLES,
    intensity=st.lists(mostly(st.floats(0, 2), NUMBERS), min_size=3, max_size=3),
)  # fmt: skip
def test_any_camera_and_light_numbers_load_or_fail_clearly(
    eye: list[float], to: list[float], up: list[float], fov: float,
    size: tuple[float, float], light: list[float], intensity: list[float], workdir: Path,
) -> None:  # fmt: skip
    document = [
        {"add": "camera", "width": size[0], "height": size[1], "field-of-view": fov,
         "from": eye, "to": to, "up": up},
        {"add": "light", "at": light, "intensity": intensity},
        {"add": "sphere"},
    ]  # fmt: skip
    scene = load_or_clear_error(yaml.safe_dump(document), workdir / "camera.yml")
    if scene is not None:  # a camera that loads has a finite, invertible view
        rows = [[scene.camera.transform[r, c] for c in range(4)] for r in range(4)]
        assert all(math.isfinite(value) for row in rows for value in row)
        assert API["inverse"](scene.camera.transform) is not None


@given(levels=st.integers(1, 12), width=st.integers(2, 12), by_alias=st.booleans())
def test_exponential_copies_are_refused_before_they_are_built(
    levels: int, width: int, by_alias: bool, workdir: Path
) -> None:
    """Groups of ``width`` copies of the level below, ``levels`` deep: refused past the limit
    as soon as the copies are counted (YAML aliases or defined shapes), never built one by
    one."""
    limits = Limits(max_depth=20, max_shapes=5000)
    if by_alias:
        level: Any = {"add": "sphere"}
        for _ in range(levels):
            level = {"add": "group", "children": _repeated(level, width)}
        text = yaml.safe_dump([*HEADER, level])
    else:
        text = yaml.safe_dump(HEADER) + "- define: l0\n  value: {add: sphere}\n"
        for i in range(1, levels + 1):
            children = ", ".join([f"{{add: l{i - 1}}}"] * width)
            text += f"- define: l{i}\n  value: {{add: group, children: [{children}]}}\n"
        text += f"- add: l{levels}\n"
    load_or_clear_error(text, workdir / "copies.yml", limits)


# ------------------------------------------------------------------------------- OBJ text

INDEX = st.integers(-6, 12).map(str) | st.sampled_from(("", "x", "1.5", "99999999999999999999"))
CORNER = st.one_of(
    INDEX,
    st.builds("{}/{}".format, INDEX, INDEX),
    st.builds("{}//{}".format, INDEX, INDEX),
    st.builds("{}/{}/{}".format, INDEX, INDEX, INDEX),
    st.builds("{}/{}/{}/{}".format, INDEX, INDEX, INDEX, INDEX),
)
NUMBER_WORD = NUMBERS.map(str) | st.sampled_from(("x", "1e999", "-0", "1,5", ""))
OBJ_LINES = st.one_of(
    st.lists(NUMBER_WORD, max_size=5).map(lambda words: " ".join(["v", *words])),
    st.lists(NUMBER_WORD, max_size=4).map(lambda words: " ".join(["vn", *words])),
    st.lists(CORNER, max_size=7).map(lambda corners: " ".join(["f", *corners])),
    st.text(max_size=8).map(lambda name: "g " + name),
    st.sampled_from(("# a comment", "", "   ", "vt 0 0", "s off", "usemtl red", "o thing")),
    st.text(max_size=20),
)


def parse_or_clear_error(text: str, require_faces: bool) -> ObjParser | None:
    try:
        parser = parse_obj_file(text, source="fuzz.obj", require_faces=require_faces)
    except ObjFileError as error:
        one_line(error, "fuzz.obj")
        event("clear error")
        return None
    event("parsed")
    groups = [parser.default_group, *parser.groups.values()]
    assert sum(len(group.children) for group in groups) == parser.triangles
    return parser


@given(
    lines=st.lists(OBJ_LINES, max_size=25),
    ending=st.sampled_from(("\n", "\r\n", "\r")),
    require_faces=st.booleans(),
)
def test_obj_text_parses_or_fails_clearly(
    lines: list[str], ending: str, require_faces: bool
) -> None:
    parse_or_clear_error(ending.join(lines), require_faces)


@given(data=st.data(), model=st.sampled_from(OBJ_MODELS), require_faces=st.booleans())
def test_mutated_obj_models_parse_or_fail_clearly(
    data: st.DataObject, model: str, require_faces: bool
) -> None:
    text = data.draw(mutated_lines((SCENES / model).read_text(encoding="utf-8")))
    parse_or_clear_error(text, require_faces)


# ------------------------------------------------------------------------------- PPM text

PPM_WORDS = st.one_of(
    st.integers(-2, 300).map(str),
    st.sampled_from(
        (
            "P3",
            "P6",
            "p3",
            "P",
            "65535",
            "65536",
            "16385",
            "0",
            "1e3",
            "٣",
            "²",
            "9" * 5000,
            "0" * 30 + "7",
        )
    ),
    st.text(max_size=4),
)
SPACE = st.sampled_from((" ", "\n", "\t", "  ", "\r\n", " # a comment\n", "#", "\x0b"))


@st.composite
def ppm_texts(draw: st.DrawFn) -> str:
    """Either any words after a header, or a well-formed header with about as many values as
    it announces (one fewer or more at times), any of them possibly replaced."""
    if draw(st.booleans()):
        header = draw(st.sampled_from(("", "P3\n", "P3\n2 2\n255\n", "P3 1 1 1 ",
                                       "P3\n# made by hand\n")))  # fmt: skip
        words = draw(st.lists(st.tuples(PPM_WORDS, SPACE), max_size=40))
        return header + "".join(word + space for word, space in words)
    width, height, maximum = draw(st.integers(1, 4)), draw(st.integers(1, 3)), draw(
        st.sampled_from((1, 15, 255, 65535)))  # fmt: skip
    count = width * height * 3 + draw(st.sampled_from((-1, 0, 0, 0, 0, 1)))
    values = draw(st.lists(mostly(st.integers(0, maximum).map(str), PPM_WORDS), min_size=count,
                           max_size=count))  # fmt: skip
    spaces = draw(st.lists(mostly(st.just(" "), SPACE), min_size=len(values) + 4,
                           max_size=len(values) + 4))  # fmt: skip
    tokens = ["P3", str(width), str(height), str(maximum), *values]
    return "".join(token + space for token, space in zip(tokens, spaces, strict=True))


@given(text=ppm_texts())
def test_ppm_text_reads_or_fails_clearly(text: str) -> None:
    try:
        image = canvas_from_ppm(text)
    except PPMError as error:
        one_line(error, "PPM line ")
        event("clear error")
        return
    event("parsed")
    assert isinstance(image, Canvas)


@given(
    width=st.integers(1, 5),
    height=st.integers(1, 4),
    levels=st.lists(st.integers(0, 255), min_size=60, max_size=60),
)
def test_a_written_ppm_reads_back_to_the_same_canvas(
    width: int, height: int, levels: list[int]
) -> None:
    image = canvas(width, height)
    values = iter(levels)
    for y in range(height):
        for x in range(width):
            write_pixel(image, x, y, color(*(next(values) / 255 for _ in range(3))))
    again = canvas_from_ppm(canvas_to_ppm(image))
    for y in range(height):
        for x in range(width):
            a, b = pixel_at(image, x, y), pixel_at(again, x, y)
            assert max(abs(a.red - b.red), abs(a.green - b.green), abs(a.blue - b.blue)) < 1e-9


@given(data=st.data())
def test_mutated_ppm_images_read_or_fail_clearly(data: st.DataObject) -> None:
    small = "P3\n# a 3x2 test image\n3 2\n255\n255 0 0  0 255 0  0 0 255\n1 2 3  4 5 6  7 8 9\n"
    text = data.draw(mutated_lines(small))
    try:
        canvas_from_ppm(text)
    except PPMError as error:
        one_line(error, "PPM line ")
        event("clear error")
    else:
        event("parsed")


# ---------------------------------------------------------------------------- variant names

VARIANT_WORDS = ("naive", "cached", "pooled", "numba", "prealloc", "robust", "wavefront", "all",
                 "nope", "workers", "bvh", "sah", "off", "on", "2", "0", "-1", "999")  # fmt: skip
NAME_PARTS = (
    st.sampled_from(VARIANT_WORDS) | st.sampled_from(list("[]:=, \t")) | st.text(max_size=3)
)


@given(parts=st.lists(NAME_PARTS, max_size=14))
def test_variant_names_parse_or_fail_clearly(parts: list[str]) -> None:
    name = "".join(parts)
    try:
        spec = parse_variant_name(name)
    except VariantError as error:
        one_line(error, "")
        event("clear error")
        return
    event("parsed")
    assert isinstance(spec, VariantSpec)
    assert parse_variant_name(str(spec)) == spec  # the canonical spelling reads back


@given(parts=st.lists(NAME_PARTS, max_size=10))
def test_variant_names_load_or_fail_clearly(parts: list[str]) -> None:
    name = "".join(parts)
    try:
        variant = load_variant(name)
    except VariantError as error:
        one_line(error, "")
        event("clear error")
        return
    event("loaded")
    assert variant.name


@given(depth=st.integers(1, 3000))
def test_deeply_wrapped_variant_names_fail_clearly(depth: int) -> None:
    try:
        parse_variant_name("pooled:" * depth + "naive")
    except VariantError as error:
        one_line(error, "bad variant name")


# ----------------------------------------------------------------------------- result files

JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-2, 10**6) | st.floats() | st.text(max_size=6),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner,
                                                                  max_size=3),
    max_leaves=8,
)  # fmt: skip


def _paths(value: Any, at: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """Every path (keys and indexes) into a JSON value."""
    yield at
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(
        value, list) else ()  # fmt: skip
    for key, inner in items:
        yield from _paths(inner, (*at, key))


def _parent(document: Any, path: tuple[Any, ...]) -> Any:
    """The list or mapping holding the value at ``path``."""
    for key in path[:-1]:
        document = document[key]
    return document


@given(data=st.data())
def test_damaged_result_files_load_or_fail_clearly(data: st.DataObject, workdir: Path) -> None:
    document = json.loads(RESULT_FILE.read_text(encoding="utf-8"))
    for _ in range(data.draw(st.integers(1, 4))):
        paths = [p for p in _paths(document) if p]
        if not paths:
            break
        path = data.draw(st.sampled_from(paths))
        parent, key = _parent(document, path), path[-1]
        if data.draw(st.booleans()):
            parent.pop(key)
        else:
            parent[key] = data.draw(JSON_VALUES)
    target = workdir / "bench-fuzz.json"
    target.write_text(json.dumps(document), encoding="utf-8")
    read_result(target)


@given(raw=st.binary(max_size=200) | JSON_VALUES.map(json.dumps))
def test_any_bytes_as_a_result_file_load_or_fail_clearly(raw: bytes | str, workdir: Path) -> None:
    target = workdir / "bench-raw.json"
    target.write_bytes(raw if isinstance(raw, bytes) else raw.encode("utf-8"))
    read_result(target)


def read_result(path: Path) -> None:
    """``load_run`` and the report's ``check_run``: a run, or one clear ``ResultFileError``."""
    try:
        run = load_run(path)
        check_run(run["rtc"], str(path))
    except ResultFileError as error:
        one_line(error, str(path))
        event("clear error")
    else:
        event("parsed")


# ----------------------------------------------------------------- the report's pages

# pieces of text a run file could hold in a name, a note or a picture's path
TEXT_PIECES = (
    "<", ">", "&", '"', "'", "`", "*", "**", "[", "]", "(", ")", "](", "#", "|", "\\", "!",
    ":", "/", ".", "..", "\n", "\r", " ", "\t", "_", "-", "=", "\u2028", "é", "x", "1",
    "javascript:alert(1)", "<script>", "</td>", "onerror=", "data:", "#anchor", "runs/ok.png",
    "](javascript:alert(1))", "[x](#fine)", "[x](runs/ok.png)", "[x](../up.png)", "\n# h",
)  # fmt: skip
TEXTS = st.lists(st.sampled_from(TEXT_PIECES), max_size=12).map("".join)
PICTURE_PATHS = st.sampled_from(
    ["runs/ok.png", "runs/missing.png", "runs/link.png", "runs/pipe.png", "runs/text.png",
     "runs/../../secret.png", "/etc/passwd", "javascript:alert(1)", "runs/ok.png\n# x",
     "runs/ok .png", "runs", ""]
) | TEXTS  # fmt: skip


@st.composite
def report_blocks(draw: st.DrawFn) -> list[Any]:
    from harness.document.model import Bullets, Gallery, Heading, Para, Picture, Table

    def picture() -> Picture:
        width = draw(st.none() | st.integers(1, 500))
        return Picture(draw(PICTURE_PATHS), draw(TEXTS), width)

    kinds = draw(st.lists(st.integers(0, 5), min_size=1, max_size=6))
    blocks: list[Any] = []
    for kind in kinds:
        if kind == 0:
            blocks.append(Heading(draw(st.integers(1, 3)), draw(TEXTS)))
        elif kind == 1:
            blocks.append(Para(draw(TEXTS)))
        elif kind == 2:
            blocks.append(Bullets(draw(st.lists(TEXTS, max_size=3))))
        elif kind == 3:
            columns = draw(st.integers(1, 3))
            rows = draw(st.lists(st.lists(TEXTS, min_size=columns, max_size=columns),
                                 max_size=3))  # fmt: skip
            blocks.append(Table([draw(TEXTS) for _ in range(columns)], rows, {0}))
        elif kind == 4:
            blocks.append(picture())
        else:
            rows = [(draw(TEXTS), [picture() if draw(st.booleans()) else None])
                    for _ in range(draw(st.integers(0, 2)))]  # fmt: skip
            blocks.append(Gallery(["a", draw(TEXTS)], rows))
    return blocks


@pytest.fixture(scope="module")
def results_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A results folder with one picture of its own, and around it what a run file could
    point at: a secret PNG outside, a link to it, a pipe and a text file named as PNG."""
    import os

    base = tmp_path_factory.mktemp("report")
    (base / "secret.png").write_bytes(b"\x89PNG\r\n\x1a\nSECRET")
    runs = base / "results" / "runs"
    runs.mkdir(parents=True)
    shutil.copy(SCENES / "textures" / "planet.png", runs / "ok.png")
    (runs / "link.png").symlink_to(base / "secret.png")
    os.mkfifo(runs / "pipe.png")
    (runs / "text.png").write_text("not a picture", encoding="utf-8")
    return base / "results"


@given(blocks=report_blocks())
def test_any_text_in_a_report_is_escaped_and_no_file_outside_is_embedded(
    blocks: list[Any], results_folder: Path
) -> None:
    """The report's own tags only, links to its headings or to files of the results
    folder, pictures only embedded from there (never the secret outside, never a pipe's
    wait), and no heading made by a line break in a name."""
    from report_checks import check_html, check_markdown

    from harness.document.model import Heading, to_html, to_markdown

    page = to_html(blocks, results_folder, "title <script>")
    markdown = to_markdown(blocks, results_folder)
    headings = sum(isinstance(b, Heading) for b in blocks)
    check_html(page, results_folder)
    check_markdown(markdown, results_folder, headings)
    assert "SECRET" not in page and "U0VDUkVU" not in page
    assert len(re.findall(r"<h[1-6][ >]", page)) == headings
    event(f"{page.count('data:image/png')} pictures embedded")


# ------------------------------------------------------------------ the kernel cache


@pytest.fixture(scope="module")
def tiny_library(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, bytes, bytes]:
    """The test kernel (``tests/compiled_tiny.py``) built in a private folder of its own, and
    copied to another that this process never loads from (damage written into a loaded
    library would reach the process's own copy): the copy's name (``library_path``), its
    library file, and the bytes of both it and its record."""
    from test_hostile import TINY

    from compiled import library, records

    base = tmp_path_factory.mktemp("kernels")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("RTC_NUMBA_KERNELS", str(base / "built"))
        patch.delenv("CC", raising=False)
        built = TINY.path()
        library.load(TINY)
        library._loaded.pop(str(built), None)
    shutil.copytree(base / "built", base / "copy", ignore=shutil.ignore_patterns("numba-*"))
    path = base / "copy" / built.name
    records._keys[str(path)] = records._keys[str(built)]
    found, why = records.verify(path)
    assert found is not None and found.parent == base / "copy", why
    return path, found, found.read_bytes(), records.record_path(path).read_bytes()


@st.composite
def damaged(draw: st.DrawFn, original: bytes) -> bytes:
    """``original`` cut, overwritten in places, lengthened, or replaced."""
    how = draw(st.sampled_from(["cut", "overwrite", "append", "replace"]))
    if how == "cut":
        return original[: draw(st.integers(0, len(original)))]
    if how == "append":
        return original + draw(st.binary(min_size=1, max_size=64))
    if how == "replace":
        return draw(st.binary(max_size=4096))
    data = bytearray(original)
    for _ in range(draw(st.integers(1, 4))):
        at = draw(st.integers(0, len(data) - 1))
        patch = draw(st.binary(min_size=1, max_size=8))
        data[at : at + len(patch)] = patch
    return bytes(data)[: len(original)]


@given(data=st.data())
def test_a_damaged_library_is_never_taken_for_the_one_built(
    data: st.DataObject, tiny_library: tuple[Path, Path, bytes, bytes]
) -> None:
    """Any damage to the library's bytes is found before it is loaded (its digest), and
    said in one line; only the bytes built pass."""
    from compiled import records

    path, file, original, _record = tiny_library
    bytes_now = data.draw(damaged(original))
    file.write_bytes(bytes_now)
    try:
        found, why = records.verify(path)
    finally:
        file.write_bytes(original)
    if bytes_now == original:
        assert found == file and why == ""
        event("the same bytes")
    else:
        assert found is None and why and "\n" not in why
        assert why.startswith(f"its library {file.name} is not the one built"), why
        event("damage found")


@given(record=st.binary(max_size=300) | JSON_VALUES.map(json.dumps) | st.data())
def test_a_damaged_record_is_never_trusted(
    record: Any, tiny_library: tuple[Path, Path, bytes, bytes]
) -> None:
    """Any record but the one written names no library to load; verifying it never raises.
    (``st.data``: the record with one of its fields changed.)"""
    from compiled import records

    path, file, _original, written = tiny_library
    if isinstance(record, st.DataObject):
        entry = json.loads(written)
        field = record.draw(st.sampled_from(sorted(entry)))
        entry[field] = record.draw(JSON_VALUES)
        record = json.dumps(entry)
    text = record if isinstance(record, bytes) else record.encode("utf-8")
    place = records.record_path(path)
    place.write_bytes(text)
    try:
        found, why = records.verify(path)
    finally:
        place.write_bytes(written)
    if text == written or (found is not None and json.loads(text) == json.loads(written)):
        assert found == file
        event("the same record")
    else:
        assert found is None and why and "\n" not in why, (text, why)
        event("record refused")


# ------------------------------------------------- what fuzzing found, kept as regressions


def test_found_a_ppm_value_of_thousands_of_digits_is_a_ppm_error() -> None:
    """Was a bare ValueError from int() (Python reads at most 4300 digits)."""
    with pytest.raises(PPMError, match=r"^PPM line 1: the value 99999999999999999\.\.\. is "):
        canvas_from_ppm("P3 1 1 255 " + "9" * 5000 + " 0 0")
    with pytest.raises(PPMError, match=r"^PPM line 1: the width is '99999999999999999999'"):
        canvas_from_ppm("P3 " + "9" * 5000 + " 1 255 0 0 0")
    padded = canvas_from_ppm("P3 1 1 255 " + "0" * 5000 + "255 0 0")
    assert pixel_at(padded, 0, 0) == color(1, 0, 0)


def test_found_a_variant_name_wrapping_thousands_deep_is_a_variant_error() -> None:
    """Was a RecursionError in the name's recursive-descent parser."""
    with pytest.raises(VariantError, match=r"more than 32 variants inside each other"):
        parse_variant_name("pooled:" * 2000 + "naive")
    assert parse_variant_name("pooled:" * 31 + "naive").name == "pooled"


@pytest.mark.parametrize(
    "text",
    [
        '{"rtc": {"schema_version": ' + "9" * 5000 + "}}",  # was a ValueError from int()
        '{"rtc": ' + "[" * 100_000 + "]" * 100_000 + "}",  # was a RecursionError in json
    ],
    ids=["thousands-of-digits", "arrays-100000-deep"],
)
def test_found_result_files_json_cannot_read_are_result_file_errors(
    text: str, tmp_path: Path
) -> None:
    path = tmp_path / "bench-found.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ResultFileError) as raised:
        load_run(path)
    one_line(raised.value, f"{path}: cannot read the result file: ")


def test_found_a_key_with_a_line_break_stays_on_one_line(tmp_path: Path) -> None:
    """Found by the long profile: a key "\\n" holding infinity broke the message in two."""
    document = json.loads(RESULT_FILE.read_text(encoding="utf-8"))
    document["rtc"]["machine"]["python_implementation"] = {"\n": math.inf}
    path = tmp_path / "bench-found.json"
    path.write_text(json.dumps(document), encoding="utf-8")
    with pytest.raises(ResultFileError) as raised:
        read_result_strictly(path)
    one_line(raised.value, str(path))
    assert "\\n" in str(raised.value)


def read_result_strictly(path: Path) -> None:
    check_run(load_run(path)["rtc"], str(path))


@pytest.mark.parametrize("section", [[], {}, 3, None])
def test_a_result_row_whose_section_is_not_a_name_loads_or_fails_clearly(
    section: Any, workdir: Path
) -> None:
    """The schema migration reads every row's section: one that is a list (unhashable) once
    raised a TypeError (found by the damaged-file test above)."""
    document = json.loads(RESULT_FILE.read_text(encoding="utf-8"))
    document["rtc"]["rows"][0]["section"] = section
    target = workdir / "bench-section.json"
    target.write_text(json.dumps(document), encoding="utf-8")
    with pytest.raises(ResultFileError) as caught:  # the report cannot use such a row
        check_run(load_run(target)["rtc"], str(target))
    one_line(caught.value, str(target))
    assert "rows[0].section" in str(caught.value)
