"""OBJ models read into arrays (``scene.obj_mesh``): the compiled scanner and Python's reading
of its slow lines give what the book's ``parse_obj_file`` and ``obj_to_group`` give, number
for number, in the same order, with the same errors on the same lines, whatever the text."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from budget import examples
from hypothesis import example, given, settings
from hypothesis import strategies as st

from raytracer.obj_file import ObjFileError
from scene import obj_mesh
from scene.obj_mesh import Mesh, book_mesh, read_mesh

SCAN_FILE = Path(obj_mesh.__file__).with_name("obj_scan.py")


def _same(a: Mesh, b: Mesh) -> None:
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.triangles, b.triangles)
    assert (a.corner_normals is None) == (b.corner_normals is None)
    if a.corner_normals is not None and b.corner_normals is not None:
        assert np.array_equal(a.corner_normals, b.corner_normals)
        assert np.array_equal(a.normals, b.normals)
    assert a.groups == b.groups
    assert (a.lines, a.ignored_lines) == (b.lines, b.ignored_lines)
    assert (a.degenerate, a.first_degenerate_line) == (b.degenerate, b.first_degenerate_line)


def _outcome(read: object, data: bytes) -> Mesh | str:
    try:
        return read(data, "model.obj")  # type: ignore[operator]
    except ObjFileError as error:
        return f"{type(error).__name__}: {error}"


def _agree(data: bytes) -> None:
    fast, book = _outcome(read_mesh, data), _outcome(book_mesh, data)
    if isinstance(book, str) or isinstance(fast, str):
        assert fast == book
    else:
        _same(fast, book)


def test_the_layout_the_reader_uses_is_the_scanners() -> None:
    """``obj_mesh._Layout`` repeats the scanner's constants (the scanner imports numba and is
    imported only to build it): they must agree."""
    tree = ast.parse(SCAN_FILE.read_text(encoding="utf-8"))
    constants = {
        node.targets[0].id: ast.literal_eval(node.value)
        for node in tree.body
        if isinstance(node, ast.Assign)
        and isinstance(node.targets[0], ast.Name)
        and node.targets[0].id.isupper()
        and isinstance(node.value, ast.Constant)
    }
    layout = {k: v for k, v in vars(obj_mesh._Layout).items() if k.isupper()}
    assert layout and all(constants[name] == value for name, value in layout.items())


SQUARE = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"


@pytest.mark.parametrize(
    "text",
    [
        SQUARE + b"f 1 2 3\nf 2 4 3\n",
        SQUARE + b"g a\nf 1 2 3\ng b\nf 2 4 3\ng a\nf 1 2 4\ng\nf -1 -2 -3\n",  # groups again
        SQUARE + b"vn 0 0 1\nf 1//1 2//1 3//1 4//1\nf 1/7/1 2/8/1 3/9/1\nf 1/2 2/3 3/4\n",
        SQUARE + b"f 1 2 3 4\nf 1 1 2\nf 1 2 4\n",  # a fan, a degenerate triangle
        b"\xef\xbb\xbf" + SQUARE + b"f 1 2 3\n",  # a byte-order mark
        SQUARE.replace(b"\n", b"\r\n") + b"f 1 2 3\r\n",
        SQUARE + b"v 0.10000000000000000555 1e-30 2.5e+300\nf 1 2 5\n",  # past the fast path
        SQUARE + b"v 1_0 +2 -.5\nvt 0 1\ns off\n# comment\n\n  f 1 2 5  \n",
        SQUARE + b"g mod\xc3\xa8le\nf 1 2 3\nusemtl b\xc3\xa9ton\nf 1 2 4\n",
        SQUARE + b"f 1 2 3\n\xc2\xa0v 1 1 1\nf 1 2 5\n",  # a space only Python sees
        SQUARE + b"f 1\xc2\xa02 3 4\n",
        SQUARE + b"f 1 2 9\n",
        SQUARE + b"v 1 2 nan\n",
        SQUARE + b"f 1//1 2//1 3//1\n",
        SQUARE + b"f 1/x 2 3\n",
        SQUARE + b"vn 0 0 1\nf 1//1 2 3\n",
        SQUARE + b"f 1 2\n",
        SQUARE + b"f 1 2 3\x00\n",  # a binary file
        SQUARE + b"f 1 2 3\rf 2 4 3\n",  # an old Macintosh line break
        b"",
        b"# nothing\n",
        SQUARE,
    ],
)
def test_the_arrays_are_the_book_parsers_for_every_kind_of_line(text: bytes) -> None:
    _agree(text)


NUMBERS = st.sampled_from(
    ["0", "1", "-1", "2.5", "-0", "1e3", "1E-3", ".5", "5.", "+3", "0.1234567890123456789",
     "1e400", "nan", "x", "1_0", "1.2.3", "--1", "1e", "0x10", "12345678901234567"]
)  # fmt: skip
INDICES = st.sampled_from(["1", "2", "3", "-1", "-2", "0", "9", "+1", "a", "1.5", ""])


@st.composite
def obj_lines(draw: st.DrawFn) -> bytes:
    """A line of OBJ text: mostly well formed, sometimes not."""
    kind = draw(st.sampled_from(["v", "vn", "f", "g", "vt", "#", "", "junk"]))
    if kind in ("v", "vn", "vt"):
        words = draw(st.lists(NUMBERS, min_size=2, max_size=5))
    elif kind == "f":
        form = draw(st.sampled_from(["{v}", "{v}//{n}", "{v}/{t}/{n}", "{v}/{t}", "{v}/", "/{v}"]))
        corners = draw(st.integers(2, 5))
        words = [
            form.format(v=draw(INDICES), t=draw(INDICES), n=draw(INDICES)) for _ in range(corners)
        ]
    elif kind == "g":
        words = draw(st.lists(st.sampled_from(["a", "b", "c d", "\u00e9"]), max_size=2))
    else:
        words = draw(st.lists(st.sampled_from(["x", "1", "y z"]), max_size=3))
    space = draw(st.sampled_from([" ", "  ", "\t", " \x1f "]))
    lead = draw(st.sampled_from(["", "", " ", "\u00a0"]))
    return (lead + space.join([kind, *words]) + draw(st.sampled_from(["\n", "\r\n"]))).encode()


@settings(max_examples=examples(300), deadline=None)
@given(head=st.integers(0, 6), lines=st.lists(obj_lines(), max_size=25))
@example(head=4, lines=[b"f 1 2 3 4\n", b"g\n", b"f -1 -2 -3\n"])
def test_any_obj_text_reads_as_the_book_parser_reads_it(head: int, lines: list[bytes]) -> None:
    _agree(SQUARE + b"v 2 0 1\nv 0 3 1\nvn 0 0 1\nvn 0 1 0\n"[: head * 8] + b"".join(lines))


def test_the_project_models_read_as_the_book_parser_reads_them() -> None:
    folder = Path(obj_mesh.__file__).parents[1] / "scenes"
    for model in sorted(folder.glob("*.obj")):
        data = model.read_bytes()
        _same(read_mesh(data, str(model)), book_mesh(data, str(model)))


def test_a_large_model_with_one_bad_face_at_its_end_is_one_error_naming_that_line() -> None:
    """200,000 ordinary triangles (read by the compiled scanner), then one face naming a
    vertex that does not exist: the error names the file and that last line."""
    side = 318  # a grid of side^2 vertices, 2 (side - 1)^2 triangles
    x, z = np.meshgrid(np.arange(side, dtype=float), np.arange(side, dtype=float))
    vertices = "".join(f"v {a:g} 0 {b:g}\n" for a, b in zip(x.ravel(), z.ravel(), strict=True))
    k = (np.arange(side - 1)[:, None] * side + np.arange(side - 1)[None, :]).ravel() + 1
    quads = np.stack([k, k + 1, k + side, k + 1, k + side + 1, k + side], axis=1)
    faces = "".join(f"f {a} {b} {c}\nf {d} {e} {f}\n" for a, b, c, d, e, f in quads.tolist())
    bad = f"f 1 2 {side * side + 7}\n"
    data = (vertices + faces + bad).encode()
    lines = data.count(b"\n")
    assert 2 * (side - 1) ** 2 > 200_000
    with pytest.raises(ObjFileError) as raised:
        read_mesh(data, "large.obj")
    message = str(raised.value)
    assert message.startswith(f"large.obj, line {lines}: 'f 1 2 {side * side + 7}': ")
    assert f"but {side * side:,} vertices are defined so far".replace(",", "") in message
    assert len(read_mesh(data[: -len(bad)], "large.obj").triangles) == 2 * (side - 1) ** 2
