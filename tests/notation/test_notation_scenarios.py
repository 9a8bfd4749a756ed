"""``notation.feature``: every form of the book's notation, once per ``--variant``.

Chapters 14 and 15 (groups, the OBJ parser) are beyond the reference for now; where a variant
lacks those names, tiny stand-ins fill in so that the notation forms they appear in are still
exercised. A variant's own versions always win.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pytest
from pytest_bdd import scenarios

from steps.book import Book

scenarios("notation.feature")


@dataclass(eq=False)
class StandInGroup:
    children: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class StandInTriangle:
    p1: Any
    p2: Any
    p3: Any


@dataclass
class StandInParser:
    vertices: list[Any]
    groups: dict[str, StandInGroup]
    default_group: StandInGroup
    ignored_lines: int


def _add_child(group: Any, shape: Any) -> None:
    group.children.append(shape)
    shape.parent = group


def _parse_obj_file(text: str, point: Any) -> StandInParser:
    """Vertices, fan-triangulated faces and named groups; everything else is ignored."""
    parser = StandInParser([None], {}, StandInGroup(), 0)
    current = parser.default_group
    for line in text.splitlines():
        words = line.split()
        if words[:1] == ["v"] and len(words) == 4:
            parser.vertices.append(point(*(float(word) for word in words[1:])))
        elif words[:1] == ["f"] and len(words) >= 4:
            corners = [parser.vertices[int(word)] for word in words[1:]]
            for index in range(1, len(corners) - 1):
                triangle = StandInTriangle(corners[0], corners[index], corners[index + 1])
                current.children.append(triangle)
        elif words[:1] == ["g"] and len(words) == 2:
            current = parser.groups.setdefault(words[1], StandInGroup())
        else:
            parser.ignored_lines += 1
    return parser


def _obj_to_group(parser: StandInParser) -> StandInGroup:
    group = StandInGroup()
    for child in [parser.default_group, *parser.groups.values()]:
        _add_child(group, child)
    return group


@pytest.fixture
def book(book: Book) -> Book:
    """The plugin's namespace, with stand-ins for the names the variant does not have yet."""
    point = book.api["point"]
    stand_ins = {
        "group": StandInGroup,
        "add_child": _add_child,
        "parse_obj_file": lambda text: _parse_obj_file(text, point),
        "obj_to_group": _obj_to_group,
    }
    book.api = {**stand_ins, **book.api}
    return book
