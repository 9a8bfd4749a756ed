"""Materials (chapters 6, 10 and 11) and their patterns, as the scene format writes them
(the texture maps of the bonus chapter "Texture mapping": ``textures``).

A material is read into a dict of the book's property names (``refractive_index`` for the
format's ``refractive-index``), so that ``define ... extend`` can merge them; ``make_material``
turns the dict into the variant's material.
"""

from __future__ import annotations

import math
from typing import Any

from yaml.nodes import Node, ScalarNode

from scene.colors import read_color
from scene.context import Context, updated
from scene.pattern_kinds import PATTERN_KINDS
from scene.reader import Entry, line_of
from scene.textures import MAP_KEYS, read_map_pattern
from scene.transforms import read_transform, transform_problem

# the format's key -> the book's material property
NUMBER_PROPERTIES = {
    "ambient": "ambient",
    "diffuse": "diffuse",
    "specular": "specular",
    "shininess": "shininess",
    "reflective": "reflective",
    "transparency": "transparency",
    "refractive-index": "refractive_index",
}
MATERIAL_KEYS = ("color", *NUMBER_PROPERTIES, "pattern", "emissive")
# the format's pattern type -> the book's factory (the pattern table, ``scene.pattern_kinds``)
PATTERNS = {k.key: k.name for k in PATTERN_KINDS if k.key is not None}
MAP = "map"  # a texture map (the bonus chapter): ``scene.textures``
PATTERN_TYPES = (*PATTERNS, MAP)
PATTERN_KEYS = ("type", "colors", "transform")
# the range each number property may take: (low, high, what the error says it must be);
# the book's functions take any number, but outside these a material is not a surface
# (negative light, a highlight over the whole hemisphere, more light out than in)
RANGES = {
    "ambient": (0.0, math.inf, "0 or more"),
    "diffuse": (0.0, math.inf, "0 or more"),
    "specular": (0.0, math.inf, "0 or more"),
    "reflective": (0.0, 1.0, "from 0 to 1"),
    "transparency": (0.0, 1.0, "from 0 to 1"),
}


def read_pattern(ctx: Context, node: Node) -> Any:
    """``{type: checkers, colors: [[1, 1, 1], [0, 0, 0]], transform: [...]}`` as a pattern;
    ``type: map`` is a texture map (``scene.textures``)."""
    reader = ctx.reader
    entries = reader.mapping(node, "a pattern")
    type_node = reader.require(entries, "type", node, "the pattern")
    kind = reader.string(type_node, "the pattern's type")
    if kind == MAP:
        reader.check_keys(entries, MAP_KEYS, "a map pattern")
        pattern = read_map_pattern(ctx, node, entries)
    else:
        reader.check_keys(entries, PATTERN_KEYS, "a pattern")
        if kind not in PATTERNS:
            reader.fail(
                type_node, f"unknown pattern type {kind!r}; known: {', '.join(PATTERN_TYPES)}"
            )
        pattern = _two_color_pattern(ctx, node, entries, kind, type_node)
    if "transform" in entries:
        transform_node = entries["transform"].value
        m = read_transform(ctx, transform_node, f"the {kind} pattern's transform")
        problem = transform_problem(ctx, m)
        if problem is not None:
            reader.fail(
                transform_node,
                f"the transform of the {kind} pattern at line {line_of(node)} {problem}",
            )
        ctx.need("set_pattern_transform", transform_node, "a pattern transform")(pattern, m)
    return pattern


def _two_color_pattern(
    ctx: Context, node: Node, entries: dict[str, Entry], kind: str, type_node: Node
) -> Any:
    """Chapter 10's patterns: stripes, gradient, rings, checkers of two colors."""
    reader = ctx.reader
    colors_node = reader.require(entries, "colors", node, f"the {kind} pattern")
    colors = reader.sequence(colors_node, f"the {kind} pattern's colors")
    if len(colors) != 2:
        reader.fail(
            colors_node,
            f"the {kind} pattern takes 2 colors ([[r, g, b], [r, g, b]]), got {len(colors)}",
        )
    a, b = (read_color(ctx, c, f"the {kind} pattern's color") for c in colors)
    return ctx.need(PATTERNS[kind], type_node, f"a {kind} pattern")(a, b)


def read_material_properties(ctx: Context, node: Node, what: str) -> dict[str, Any]:
    """A material mapping as ``{book property: value}`` (only the properties it gives)."""
    reader = ctx.reader
    entries = reader.mapping(node, what)
    reader.check_keys(entries, MATERIAL_KEYS, what)
    properties: dict[str, Any] = {}
    for key, entry in entries.items():
        if key in ("color", "emissive"):  # emissive: the path integrator's (chapter 21)
            properties[key] = read_color(ctx, entry.value, f"{what}: {key}")
        elif key == "pattern":
            properties["pattern"] = read_pattern(ctx, entry.value)
        else:
            value = reader.number(entry.value, f"{what}: {key}")
            if key in ("refractive-index", "shininess") and value <= 0:
                reader.fail(entry.value, f"{what}: {key} must be above 0, got {value}")
            if key in RANGES:
                low, high, expected = RANGES[key]
                if not low <= value <= high:
                    reader.fail(entry.value, f"{what}: {key} must be {expected}, got {value}")
            properties[NUMBER_PROPERTIES[key]] = value
    return properties


def read_material(ctx: Context, node: Node, what: str) -> dict[str, Any]:
    """A shape's ``material:``: a mapping, or the name of a material defined earlier."""
    if isinstance(node, ScalarNode):
        return dict(ctx.lookup(node, "material", what).value)
    return read_material_properties(ctx, node, what)


def make_material(ctx: Context, properties: dict[str, Any]) -> Any:
    """The variant's default ``material()`` with ``properties`` replaced."""
    return updated(ctx.api["material"](), **properties)
