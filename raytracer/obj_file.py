"""Wavefront OBJ files (chapter 15): vertices, vertex normals, faces and named groups.

``parse_obj_file`` reads OBJ text into an ``ObjParser`` holding what it found; faces become
triangles (polygons are fanned out from their first corner), or smooth triangles when every
corner names a normal. ``obj_to_group`` gathers the result into one group for a world.

Blank lines and ``#`` comments are skipped; any other line the parser does not know (``vt``,
``s``, ``usemtl``, prose ...) is skipped and counted in ``ignored_lines``. A line the parser
does know but cannot read (``v 1 x 3``, ``f 1 2``, a face naming a vertex that does not
exist) is an ``ObjParseError`` naming the line.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from raytracer.shapes.group import Group, add_child, group
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import smooth_triangle
from raytracer.shapes.triangle import triangle
from raytracer.tuples import Tuple, point, vector


class ObjParseError(ValueError):
    """A line of OBJ text that the parser recognizes but cannot read.

    source: where the text came from (a file name, or "OBJ text"); line_number: 1-based;
    line: the line as written; expected: what the parser wanted there.
    """

    def __init__(self, source: str, line_number: int, line: str, expected: str) -> None:
        super().__init__(f"{source}, line {line_number}: {line.strip()!r}: {expected}")
        self.source = source
        self.line_number = line_number
        self.line = line
        self.expected = expected


@dataclass(slots=True, eq=False)
class ObjParser:
    """Chapter 15: what ``parse_obj_file`` found.

    vertices, normals: numbered from 1 as in the file (index 0 holds None);
    default_group: the faces before any ``g`` line; groups: name -> group of the faces after
    ``g name``; ignored_lines: how many lines were not understood.
    """

    default_group: Group
    vertices: list[Tuple | None] = field(default_factory=lambda: [None])
    normals: list[Tuple | None] = field(default_factory=lambda: [None])
    groups: dict[str, Group] = field(default_factory=dict)
    ignored_lines: int = 0


@dataclass(frozen=True, slots=True)
class _Line:
    """One line being parsed, for error messages."""

    source: str
    number: int
    text: str

    def error(self, expected: str) -> ObjParseError:
        return ObjParseError(self.source, self.number, self.text, expected)


def _numbers(line: _Line, words: list[str], counts: tuple[int, ...], form: str) -> list[float]:
    if len(words) not in counts:
        raise line.error(f"expected {form}, got {len(words)} numbers")
    try:
        values = [float(word) for word in words]
    except ValueError:
        raise line.error(f"expected {form}, with numbers only") from None
    if not all(math.isfinite(value) for value in values):
        raise line.error(f"expected {form}, with finite numbers")
    return values


def _index(line: _Line, word: str, items: list[Tuple | None], what: str) -> Tuple:
    """The item a face corner names: 1-based, or negative counting back from the last."""
    try:
        number = int(word)
    except ValueError:
        raise line.error(f"expected a {what} number, not {word!r}") from None
    defined = len(items) - 1
    position = number if number > 0 else defined + 1 + number
    if number == 0 or not 1 <= position <= defined:
        raise line.error(
            f"the face names {what} {number}, but {defined} {what}s are defined so far"
        )
    found = items[position]
    assert found is not None  # index 0 is the only None
    return found


def _corner(line: _Line, word: str, parser: ObjParser) -> tuple[Tuple, Tuple | None]:
    """A face corner: ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn`` (the texture index is ignored)."""
    parts = word.split("/")
    if len(parts) > 3 or (len(parts) > 1 and parts[1] and not _is_integer(parts[1])):
        raise line.error(f"expected a corner v, v/vt, v//vn or v/vt/vn, not {word!r}")
    vertex = _index(line, parts[0], parser.vertices, "vertex")
    if len(parts) == 3 and parts[2]:
        return vertex, _index(line, parts[2], parser.normals, "normal")
    return vertex, None


def _is_integer(word: str) -> bool:
    try:
        int(word)
    except ValueError:
        return False
    return True


def parse_obj_file(
    text: str,
    *,
    make_triangle: Callable[[Tuple, Tuple, Tuple], Shape] = triangle,
    make_smooth_triangle: Callable[
        [Tuple, Tuple, Tuple, Tuple, Tuple, Tuple], Shape
    ] = smooth_triangle,
    make_group: Callable[[], Group] = group,
    source: str = "OBJ text",
) -> ObjParser:
    """Chapter 15: read OBJ text.

    make_triangle, make_smooth_triangle, make_group: build the shapes (a variant passes its
    own); source: names the text in error messages (e.g. the file's path).
    """
    parser = ObjParser(default_group=make_group())
    current = parser.default_group
    for number, text_line in enumerate(text.splitlines(), start=1):
        line = _Line(source, number, text_line)
        words = text_line.split()
        if not words or words[0].startswith("#"):
            continue
        keyword, arguments = words[0], words[1:]
        if keyword == "v":
            x, y, z, *_ = _numbers(line, arguments, (3, 4), "v x y z")  # an optional w is unused
            parser.vertices.append(point(x, y, z))
        elif keyword == "vn":
            x, y, z = _numbers(line, arguments, (3,), "vn x y z")
            parser.normals.append(vector(x, y, z))
        elif keyword == "f":
            if len(arguments) < 3:
                raise line.error(f"expected a face with at least 3 corners, got {len(arguments)}")
            corners = [_corner(line, word, parser) for word in arguments]
            for shape in _fan(line, corners, make_triangle, make_smooth_triangle):
                add_child(current, shape)
        elif keyword == "g":
            name = " ".join(arguments)
            if not name:
                current = parser.default_group
            else:
                if name not in parser.groups:
                    parser.groups[name] = make_group()
                current = parser.groups[name]
        else:
            parser.ignored_lines += 1
    return parser


def _fan(
    line: _Line,
    corners: list[tuple[Tuple, Tuple | None]],
    make_triangle: Callable[[Tuple, Tuple, Tuple], Shape],
    make_smooth_triangle: Callable[[Tuple, Tuple, Tuple, Tuple, Tuple, Tuple], Shape],
) -> list[Shape]:
    """Chapter 15: a polygon as triangles sharing its first corner (a fan)."""
    with_normals = [normal is not None for _, normal in corners]
    if any(with_normals) and not all(with_normals):
        raise line.error("expected a normal for every corner of the face or for none")
    shapes: list[Shape] = []
    for index in range(1, len(corners) - 1):
        (p1, n1), (p2, n2), (p3, n3) = corners[0], corners[index], corners[index + 1]
        if n1 is not None and n2 is not None and n3 is not None:
            shapes.append(make_smooth_triangle(p1, p2, p3, n1, n2, n3))
        else:
            shapes.append(make_triangle(p1, p2, p3))
    return shapes


def obj_to_group(parser: ObjParser, *, make_group: Callable[[], Group] = group) -> Group:
    """Chapter 15: one group holding the parsed faces: the default group (when it has any)
    and every named group, which become its children."""
    result = make_group()
    if parser.default_group.children:
        add_child(result, parser.default_group)
    for named in parser.groups.values():
        add_child(result, named)
    return result
