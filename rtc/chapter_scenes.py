"""The scenes of chapters 7 to 16's pictures as data: for each chapter its camera, its light
and its shapes, one row per shape; ``rtc.demos`` builds and renders them with the reference.

A shape's ``transform`` is its steps as the book writes them, left to right
(``translation(...) * rotation_y(...) * scaling(...)``: the last step applies first); a
material is ``material()``'s arguments, ``color`` and a pattern's colors as (r, g, b). A
``kind`` that is no shape of the book names one of ``rtc.demos``' builders: the chapter's
hexagon of groups, its OBJ icosahedron, its die.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

PI = math.pi
Step = tuple[Any, ...]  # ("translate", x, y, z), ("scale", x, y, z), ("rotate_y", radians) ...
RGB = tuple[float, float, float]


@dataclass(frozen=True)
class Pattern:
    """A pattern of ``kind`` (``checkers``, ``stripes``, ``gradient``, ``rings``) between
    colors ``a`` and ``b``, with its own ``transform`` (none: the identity)."""

    kind: str
    a: RGB
    b: RGB
    transform: tuple[Step, ...] = ()


@dataclass(frozen=True)
class Shape:
    """One shape: ``kind``; ``transform``: its steps; ``material``: ``material()``'s
    arguments (a ``Pattern`` as ``pattern``); ``options``: the shape's own (``minimum``,
    ``maximum``, ``closed``, ``casts_shadow``)."""

    kind: str
    transform: tuple[Step, ...] = ()
    material: Mapping[str, Any] = field(default_factory=dict)
    options: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class ChapterScene:
    """A chapter's picture: the camera looks from ``eye`` at ``to`` (up is +y) with a
    ``field_of_view``; one point light of white at ``light``; ``shapes``; ``shadows``: False
    makes no shape cast one (chapter 7 has none yet); ``count``: a line printed with the
    number of shapes in the world (``{count}``)."""

    eye: tuple[float, float, float]
    to: tuple[float, float, float]
    light: tuple[float, float, float]
    shapes: tuple[Shape, ...]
    field_of_view: float = PI / 3
    shadows: bool = True
    count: str = ""


def _wall(turn: float) -> tuple[Step, ...]:
    """The first scene's walls: very flat spheres stood up and turned to face the corner."""
    return (
        ("translate", 0, 0, 5), ("rotate_y", turn), ("rotate_x", PI / 2), ("scale", 10, 0.01, 10),
    )  # fmt: skip


WALL = {"color": (0.95, 0.88, 0.8), "specular": 0}
ROOM = (
    Shape("sphere", (("scale", 10, 0.01, 10),), WALL),
    Shape("sphere", _wall(-PI / 4), WALL),
    Shape("sphere", _wall(PI / 4), WALL),
    Shape("sphere", (("translate", -0.4, 1, 0.7),),
          {"color": (0.15, 0.65, 0.8), "diffuse": 0.7, "specular": 0.3}),
    Shape("sphere", (("translate", 1.4, 0.6, -0.4), ("scale", 0.6, 0.6, 0.6)),
          {"color": (1, 0.5, 0.1), "diffuse": 0.7, "specular": 0.3}),
    Shape("sphere", (("translate", -1.6, 0.35, -0.7), ("scale", 0.35, 0.35, 0.35)),
          {"color": (0.6, 0.3, 0.9), "diffuse": 0.7, "specular": 0.3}),
)  # fmt: skip
"""Chapter 7's three spheres in a corner whose floor and walls are very flat spheres."""

WOOD = {"color": (0.55, 0.33, 0.18), "diffuse": 0.8, "specular": 0.2}
UPRIGHT = ("rotate_x", PI / 2)

SCENES: dict[int, ChapterScene] = {
    7: ChapterScene((0, 1.6, -5.2), (0, 1, 0), (-8, 10, -10), ROOM, shadows=False),
    8: ChapterScene((0, 1.6, -5.2), (0, 1, 0), (-8, 10, -10), ROOM),
    9: ChapterScene((0, 2.2, -5.5), (0, 0.8, 1), (-6, 8, -8), (
        Shape("plane", (), {"color": (0.85, 0.9, 0.8), "specular": 0}),
        Shape("plane", (("translate", 0, 0, 7), UPRIGHT),
              {"color": (0.7, 0.75, 0.95), "specular": 0}),
        Shape("sphere", (("translate", -1.3, 0.3, 1.2), ("scale", 0.9, 0.9, 0.9)),
              {"color": (0.9, 0.3, 0.3), "diffuse": 0.8, "specular": 0.4}),
        Shape("sphere", (("translate", 0.6, 0.7, 0.2), ("scale", 0.7, 0.7, 0.7)),
              {"color": (0.2, 0.7, 0.4), "diffuse": 0.8, "specular": 0.4}),
        Shape("sphere", (("translate", 1.8, 1.6, 2.2), ("scale", 0.4, 0.4, 0.4)),
              {"color": (0.95, 0.8, 0.2), "diffuse": 0.8, "specular": 0.4}),
    )),
    10: ChapterScene((0.5, 2.4, -5), (0, 0.7, 1), (-5, 9, -8), (
        Shape("plane", (), {"pattern": Pattern("checkers", (0.95, 0.95, 0.95), (0.25, 0.25, 0.3),
                                               (("rotate_y", PI / 7),)), "specular": 0}),
        Shape("plane", (("translate", 0, 0, 6), UPRIGHT),
              {"pattern": Pattern("stripes", (0.9, 0.85, 0.6), (0.75, 0.6, 0.4),
                                  (("rotate_y", PI / 4), ("scale", 0.5, 0.5, 0.5))),
               "specular": 0}),
        # the gradient runs x from -1 to 1 across the sphere, so the blend spans it once
        Shape("sphere", (("translate", -1.5, 1, 1),),
              {"pattern": Pattern("gradient", (1, 0.2, 0.2), (0.2, 0.3, 1),
                                  (("translate", -1, 0, 0), ("scale", 2, 1, 1))),
               "specular": 0.4}),
        Shape("sphere", (("translate", 0.9, 0.8, 0.3), ("scale", 0.8, 0.8, 0.8)),
              {"pattern": Pattern("rings", (0.2, 0.7, 0.3), (0.95, 0.95, 0.8),
                                  (UPRIGHT, ("scale", 0.2, 0.2, 0.2))),
               "specular": 0.4}),
        Shape("sphere", (("translate", 0.1, 0.4, -1.2), ("scale", 0.4, 0.4, 0.4)),
              {"pattern": Pattern("checkers", (1, 0.75, 0.1), (0.3, 0.15, 0.05),
                                  (("scale", 0.5, 0.5, 0.5),)),
               "specular": 0.4}),
    )),
    11: ChapterScene((0, 1.8, -5), (0.2, 0.8, 1), (-4, 9, -8), (
        Shape("plane", (), {"pattern": Pattern("checkers", (0.9, 0.9, 0.9), (0.1, 0.1, 0.15)),
                            "specular": 0.2, "reflective": 0.3}),
        Shape("plane", (("translate", 0, 0, 8), UPRIGHT),
              {"color": (0.55, 0.7, 0.9), "specular": 0}),
        # clear glass lets the light through (the scene files' shadow: false)
        Shape("sphere", (("translate", -0.3, 1, 0),),
              {"color": (0.05, 0.08, 0.05), "ambient": 0.02, "diffuse": 0.1, "specular": 1,
               "shininess": 300, "reflective": 0.9, "transparency": 0.9,
               "refractive_index": 1.5}, {"casts_shadow": False}),
        Shape("sphere", (("translate", 1.8, 0.7, 1.5), ("scale", 0.7, 0.7, 0.7)),
              {"color": (0.15, 0.15, 0.2), "diffuse": 0.4, "specular": 0.9, "reflective": 0.8}),
        # seen through the glass, upside down
        Shape("sphere", (("translate", -1.3, 0.5, 3), ("scale", 0.5, 0.5, 0.5)),
              {"color": (1, 0.35, 0.1), "diffuse": 0.8}),
    )),
    12: ChapterScene((0.8, 3, -4.5), (0, 1.2, 0), (-2.5, 5, -3.5), (
        # the room is one big cube seen from inside, its checks one unit in world space
        Shape("cube", (("translate", 0, 3, 0), ("scale", 5, 3, 5)),
              {"pattern": Pattern("checkers", (0.85, 0.8, 0.7), (0.65, 0.6, 0.52),
                                  (("scale", 0.1, 0.1667, 0.1),)), "specular": 0}),
        Shape("cube", (("translate", 0, 1.5, 0), ("scale", 1.5, 0.08, 1)), WOOD),
        *(Shape("cube", (("translate", x, 0.71, z), ("scale", 0.08, 0.71, 0.08)), WOOD)
          for x in (-1.35, 1.35) for z in (-0.85, 0.85)),
        Shape("cube", (("translate", 0.6, 1.83, 0.1), ("rotate_y", 0.5),
                       ("scale", 0.25, 0.25, 0.25)),
              {"color": (0.85, 0.15, 0.1), "specular": 0.5}),
        Shape("cube", (("translate", -0.5, 1.73, -0.3), ("rotate_y", -0.4),
                       ("scale", 0.15, 0.15, 0.15)),
              {"color": (0.15, 0.35, 0.85), "specular": 0.5}),
    ), count="{count} cubes"),
    13: ChapterScene((0, 2.3, -4.3), (0, 0.55, 0.3), (-5, 8, -6), (
        Shape("plane", (), {"color": (0.8, 0.85, 0.8), "specular": 0}),
        Shape("cylinder", (("translate", -1.9, 0, 0.8), ("scale", 0.5, 1.2, 0.5)),
              {"color": (0.85, 0.2, 0.15), "specular": 0.6},
              {"minimum": 0, "maximum": 1, "closed": True}),
        # an open pipe: the inside shows
        Shape("cylinder", (("translate", -0.3, 0, 1.4), ("scale", 0.6, 1, 0.6)),
              {"color": (0.2, 0.65, 0.3), "specular": 0.3}, {"minimum": 0, "maximum": 0.7}),
        Shape("cylinder", (("translate", -0.9, 0, -1.0), ("scale", 0.4, 1, 0.4)),
              {"color": (0.9, 0.75, 0.2), "specular": 0.9, "reflective": 0.2},
              {"minimum": 0, "maximum": 0.08, "closed": True}),
        # a traffic cone: the lower half, tip up, widest (radius 1) at the floor
        Shape("cone", (("translate", 1.5, 1.4, 0.8), ("scale", 0.5, 1.4, 0.5)),
              {"color": (1, 0.5, 0.05), "specular": 0.4},
              {"minimum": -1, "maximum": 0, "closed": True}),
        # an hourglass: a double cone
        Shape("cone", (("translate", 0.5, 0.6, -0.8), ("scale", 0.35, 0.6, 0.35)),
              {"color": (0.3, 0.4, 0.9), "specular": 0.6},
              {"minimum": -1, "maximum": 1, "closed": True}),
    )),
    14: ChapterScene((0, 2.4, -3.8), (0, 0.75, 0), (-4, 8, -6), (
        Shape("plane", (), {"color": (0.3, 0.35, 0.45), "specular": 0}),
        Shape("hexagon", (("translate", 0, 1, 0), ("rotate_x", -PI / 5))),
    )),
    15: ChapterScene((0, 0.9, -4.4), (0, 0, 0), (-6, 6, -8), (
        Shape("icosahedron", (),
              {"color": (0.25, 0.6, 0.9), "diffuse": 0.8, "specular": 0.6, "shininess": 100}),
    )),
    16: ChapterScene((1.9, 2.3, -2.7), (0, 0.62, 0), (5, 7, -5), (
        Shape("plane", (), {"pattern": Pattern("checkers", (0.35, 0.5, 0.35),
                                               (0.25, 0.38, 0.25)), "specular": 0}),
        Shape("die", (("translate", 0, 0.7, 0), ("rotate_y", 0.2), ("scale", 0.7, 0.7, 0.7))),
    ), field_of_view=PI / 4),
}  # fmt: skip
"""Each chapter's scene, by chapter."""
