"""Wavefront OBJ files (chapter 15): vertices, vertex normals, faces and named groups.

``parse_obj_file`` reads OBJ text into an ``ObjParser`` holding what it found; faces become
triangles (polygons are fanned out from their first corner), or smooth triangles when every
corner names a normal. ``obj_to_group`` gathers the result into one group for a world.

Blank lines and ``#`` comments are skipped; any other line the parser does not know (``vt``,
``s``, ``usemtl``, prose ...) is skipped and counted in ``ignored_lines``. A line the parser
does know but cannot read (``v 1 x 3``, ``v nan 0 0``, ``f 1 2``, a face naming a vertex that
does not exist) is an ``ObjParseError`` naming the line, and so is a NUL byte (a binary file
is not OBJ text). A triangle with no area (its corners on one line, or two of them at one
place) has no surface a ray could hit: it is left out and counted in ``degenerate_triangles``
(``first_degenerate_line`` says where the first one was). ``require_faces=True`` makes text
without a single triangle an ``ObjNoFacesError`` (a scene's model that would draw nothing).

Speed: a model of a million triangles is read in seconds. The loop reads ``v`` and
``f a b c`` lines on a fast path (a face's corners looked up directly); every other form,
and every mistake, goes through the general path, which says what is wrong. The text is
split into lines a megabyte at a time (a list of every line of a million-triangle file
would take about 100 MB more), and Python's cyclic garbage collector is paused while the
shapes are made: a million new triangles would otherwise start about 15 full collections,
a quarter of the time, and find nothing to collect.
"""

from __future__ import annotations

import gc
import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

from raytracer.shapes.group import Group, add_child, group
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import smooth_triangle
from raytracer.shapes.triangle import triangle
from raytracer.tuples import Tuple, point, vector

DEGENERATE_SINE = 1e-12
"""A triangle whose edges from its first corner meet at an angle whose sine is below this has
no area worth the name (``0.1, 0.2, 0.3`` and ``0.3, 0.6, 0.9`` from the origin are on one
line, yet rounding leaves their cross product about 1e-17, not 0)."""


class ObjFileError(ValueError):
    """OBJ text that cannot become a model. source: where the text came from (a file name,
    or "OBJ text")."""

    def __init__(self, source: str, message: str) -> None:
        super().__init__(message)
        self.source = source


class ObjParseError(ObjFileError):
    """A line of OBJ text that the parser recognizes but cannot read.

    source: where the text came from (a file name, or "OBJ text"); line_number: 1-based;
    line: the line as written; expected: what the parser wanted there.
    """

    def __init__(
        self, source: str, line_number: int, line: str, expected: str, *, show_line: bool = True
    ) -> None:
        shown = line.strip()
        if len(shown) > 80:
            shown = shown[:77] + "..."
        quoted = f"{shown!r}: " if show_line else ""  # not the bytes of a binary file
        super().__init__(source, f"{source}, line {line_number}: {quoted}{expected}")
        self.line_number = line_number
        self.line = line
        self.expected = expected


class ObjNoFacesError(ObjFileError):
    """OBJ text without a single triangle (``require_faces=True``): empty, only vertices,
    faces that were all degenerate, or not OBJ at all."""


@dataclass(slots=True, eq=False)
class ObjParser:
    """Chapter 15: what ``parse_obj_file`` found.

    vertices, normals: numbered from 1 as in the file (index 0 holds None);
    default_group: the faces before any ``g`` line; groups: name -> group of the faces after
    ``g name``; ignored_lines: how many lines were not understood; triangles: how many
    triangles the faces became; degenerate_triangles: how many more were left out for having
    no area, ``first_degenerate_line`` the line of the first (0: none); lines: lines read.
    """

    default_group: Group
    vertices: list[Tuple | None] = field(default_factory=lambda: [None])
    normals: list[Tuple | None] = field(default_factory=lambda: [None])
    groups: dict[str, Group] = field(default_factory=dict)
    ignored_lines: int = 0
    triangles: int = 0
    degenerate_triangles: int = 0
    first_degenerate_line: int = 0
    lines: int = 0


def _error(source: str, number: int, line: str, expected: str) -> ObjParseError:
    return ObjParseError(source, number, line, expected)


def _lines(text: str, chunk: int = 1 << 20) -> Iterator[str]:
    """``text.splitlines()`` one at a time: each chunk of about ``chunk`` characters ends
    just after a ``\n``, where every way of splitting lines agrees a line ends."""
    start, end_of_text = 0, len(text)
    while start < end_of_text:
        end = text.find("\n", start + chunk)
        end = end_of_text if end < 0 else end + 1
        yield from text[start:end].splitlines()
        start = end


@contextmanager
def collector_paused() -> Iterator[None]:
    """Pause the cyclic garbage collector (it stays paused if it already was): a million new
    triangles would otherwise start many full collections that find nothing to collect."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _coordinates(
    source: str, number: int, line: str, words: list[str], counts: tuple[int, ...], form: str
) -> list[float]:
    """The numbers after a ``v`` or ``vn`` keyword: ``counts`` of them, finite."""
    if len(words) - 1 not in counts:
        raise _error(source, number, line, f"expected {form}, got {len(words) - 1} numbers")
    try:
        values = [float(word) for word in words[1:]]
    except ValueError:
        raise _error(source, number, line, f"expected {form}, with numbers only") from None
    for word, value in zip(words[1:], values, strict=True):
        if not math.isfinite(value):
            raise _error(
                source, number, line, f"expected {form}, with finite numbers, not {word!r}"
            )
    return values


def _plural(count: int, what: str) -> str:
    if count == 1:
        return f"1 {what}"
    return f"{count} {'vertices' if what == 'vertex' else what + 's'}"


def _index(source: str, number: int, line: str, word: str, items: list[Tuple | None],
           what: str) -> Tuple:  # fmt: skip
    """The item a face corner names: 1-based, or negative counting back from the last."""
    try:
        index = int(word)
    except ValueError:
        raise _error(source, number, line, f"expected a {what} number, not {word!r}") from None
    defined = len(items) - 1
    position = index if index > 0 else defined + 1 + index
    if index == 0:
        raise _error(
            source, number, line,
            f"the face names {what} 0, but {what} numbers start at 1 (or -1 for the last)",
        )  # fmt: skip
    if not 1 <= position <= defined:
        raise _error(
            source, number, line,
            f"the face names {what} {index}, but {_plural(defined, what)} "
            f"{'is' if defined == 1 else 'are'} defined so far",
        )  # fmt: skip
    found = items[position]
    assert found is not None  # index 0 is the only None
    return found


def _is_integer(word: str) -> bool:
    try:
        int(word)
    except ValueError:
        return False
    return True


def _corners(
    source: str, number: int, line: str, words: list[str], parser: ObjParser
) -> list[tuple[Tuple, Tuple | None]]:
    """A face's corners, each ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn`` (the texture index is
    checked and ignored): (vertex, normal or None)."""
    if len(words) < 4:
        raise _error(
            source, number, line, f"expected a face with at least 3 corners, got {len(words) - 1}"
        )
    corners: list[tuple[Tuple, Tuple | None]] = []
    for word in words[1:]:
        parts = word.split("/")
        if len(parts) > 3 or (len(parts) > 1 and parts[1] and not _is_integer(parts[1])):
            raise _error(
                source, number, line, f"expected a corner v, v/vt, v//vn or v/vt/vn, not {word!r}"
            )
        vertex = _index(source, number, line, parts[0], parser.vertices, "vertex")
        normal = None
        if len(parts) == 3 and parts[2]:
            normal = _index(source, number, line, parts[2], parser.normals, "normal")
        corners.append((vertex, normal))
    with_normals = [normal is not None for _, normal in corners]
    if any(with_normals) and not all(with_normals):
        raise _error(
            source, number, line, "expected a normal for every corner of the face or for none"
        )
    return corners


def is_degenerate(p1: Tuple, p2: Tuple, p3: Tuple) -> bool:
    """Whether the triangle ``p1 p2 p3`` has no area: two corners at one place, or all three
    on one line (to ``DEGENERATE_SINE``). Such a triangle has no normal and no ray hits it."""
    ax, ay, az = p2.x - p1.x, p2.y - p1.y, p2.z - p1.z
    bx, by, bz = p3.x - p1.x, p3.y - p1.y, p3.z - p1.z
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    area = cx * cx + cy * cy + cz * cz  # |e1 x e2|^2 = |e1|^2 |e2|^2 sin^2
    scale = (ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz)
    return area <= scale * (DEGENERATE_SINE * DEGENERATE_SINE)


def parse_obj_file(
    text: str,
    *,
    make_triangle: Callable[[Tuple, Tuple, Tuple], Shape] = triangle,
    make_smooth_triangle: Callable[
        [Tuple, Tuple, Tuple, Tuple, Tuple, Tuple], Shape
    ] = smooth_triangle,
    make_group: Callable[[], Group] = group,
    source: str = "OBJ text",
    require_faces: bool = False,
) -> ObjParser:
    """Chapter 15: read OBJ text.

    make_triangle, make_smooth_triangle, make_group: build the shapes (a variant passes its
    own); source: names the text in error messages (e.g. the file's path); require_faces:
    text that makes no triangle at all is an ``ObjNoFacesError`` (the book's parser accepts
    it: a file of gibberish is a parser with nothing in it).
    """
    parser = ObjParser(default_group=make_group())
    with collector_paused():
        _read(text, parser, source, make_triangle, make_smooth_triangle, make_group)
    if require_faces and parser.triangles == 0:
        raise ObjNoFacesError(source, _no_faces(source, parser))
    return parser


def _read(
    text: str,
    parser: ObjParser,
    source: str,
    make_triangle: Callable[[Tuple, Tuple, Tuple], Shape],
    make_smooth_triangle: Callable[[Tuple, Tuple, Tuple, Tuple, Tuple, Tuple], Shape],
    make_group: Callable[[], Group],
) -> None:
    """``parse_obj_file``'s loop: every line of ``text`` into ``parser``."""
    current = parser.default_group
    vertices, normals = parser.vertices, parser.normals
    isfinite = math.isfinite
    binary = "\x00" in text  # then every line is checked for one
    number = 0
    for number, line in enumerate(_lines(text), start=1):
        if binary and "\x00" in line:
            raise ObjParseError(
                source, number, line, "a NUL byte: this is a binary file, not OBJ text",
                show_line=False,
            )  # fmt: skip
        words = line.split()
        if not words:
            continue
        keyword = words[0]
        if keyword == "v":
            if len(words) == 4:  # the fast path: v x y z
                try:
                    x, y, z = float(words[1]), float(words[2]), float(words[3])
                except ValueError:
                    x = y = z = math.nan  # the general path says which word
                if isfinite(x) and isfinite(y) and isfinite(z):
                    vertices.append(point(x, y, z))
                    continue
            # an optional fourth number (w) is read and not used
            x, y, z, *_ = _coordinates(source, number, line, words, (3, 4), "v x y z")
            vertices.append(point(x, y, z))
        elif keyword == "f":
            defined = len(vertices)
            if len(words) == 4 and "/" not in line:  # the fast path: f a b c
                try:
                    a, b, c = int(words[1]), int(words[2]), int(words[3])
                except ValueError:
                    a = b = c = 0  # the general path says which word
                if 0 < a < defined and 0 < b < defined and 0 < c < defined:
                    p1, p2, p3 = vertices[a], vertices[b], vertices[c]
                    assert p1 is not None and p2 is not None and p3 is not None
                    if is_degenerate(p1, p2, p3):
                        _skip(parser, number)
                    else:
                        add_child(current, make_triangle(p1, p2, p3))
                        parser.triangles += 1
                    continue
            corners = _corners(source, number, line, words, parser)
            _fan(parser, current, number, corners, make_triangle, make_smooth_triangle)
        elif keyword == "vn":
            x, y, z = _coordinates(source, number, line, words, (3,), "vn x y z")
            normals.append(vector(x, y, z))
        elif keyword == "g":
            name = " ".join(words[1:])
            if not name:
                current = parser.default_group
            else:
                if name not in parser.groups:
                    parser.groups[name] = make_group()
                current = parser.groups[name]
        elif keyword.startswith("#"):
            continue
        else:
            parser.ignored_lines += 1
    parser.lines = number


def _skip(parser: ObjParser, number: int) -> None:
    """Count a triangle left out for having no area."""
    parser.degenerate_triangles += 1
    if not parser.first_degenerate_line:
        parser.first_degenerate_line = number


def _no_faces(source: str, parser: ObjParser) -> str:
    if parser.lines == 0:
        found = "the file is empty"
    else:
        found = (
            f"{_plural(parser.lines, 'line')}, {_plural(len(parser.vertices) - 1, 'vertex')}, "
            f"{parser.ignored_lines} not understood"
        )
        if parser.degenerate_triangles:
            found += (
                f", {parser.degenerate_triangles} degenerate triangles left out (the first at "
                f"line {parser.first_degenerate_line})"
            )
    return f"{source}: no faces ({found}); expected at least one 'f' line making a triangle"


def _fan(
    parser: ObjParser,
    current: Group,
    number: int,
    corners: list[tuple[Tuple, Tuple | None]],
    make_triangle: Callable[[Tuple, Tuple, Tuple], Shape],
    make_smooth_triangle: Callable[[Tuple, Tuple, Tuple, Tuple, Tuple, Tuple], Shape],
) -> None:
    """Chapter 15: a polygon as triangles sharing its first corner (a fan), added to
    ``current``; triangles with no area are left out and counted."""
    for index in range(1, len(corners) - 1):
        (p1, n1), (p2, n2), (p3, n3) = corners[0], corners[index], corners[index + 1]
        if is_degenerate(p1, p2, p3):
            _skip(parser, number)
            continue
        if n1 is not None and n2 is not None and n3 is not None:
            add_child(current, make_smooth_triangle(p1, p2, p3, n1, n2, n3))
        else:
            add_child(current, make_triangle(p1, p2, p3))
        parser.triangles += 1


def obj_to_group(parser: ObjParser, *, make_group: Callable[[], Group] = group) -> Group:
    """Chapter 15: one group holding the parsed faces: the default group (when it has any)
    and every named group, which become its children."""
    result = make_group()
    if parser.default_group.children:
        add_child(result, parser.default_group)
    for named in parser.groups.values():
        add_child(result, named)
    return result
