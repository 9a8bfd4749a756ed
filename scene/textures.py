"""Texture-mapped patterns in a scene file (the bonus chapter "Texture mapping").

A material's ``pattern:`` with ``type: map``::

    pattern:
      type: map
      mapping: spherical          # spherical | planar | cylindrical | cube
      uv_pattern:
        type: checkers            # checkers | align_check | image
        width: 16                 # squares along u (a whole number from 1)
        height: 8                 # squares along v
        colors: [[1, 1, 1], [0, 0, 0]]
      transform: [...]            # as for every pattern

``mapping: cube`` takes a UV pattern per face instead: ``left``, ``front``, ``right``,
``back``, ``up``, ``down`` (``uv_pattern`` then stands for every face not given). The other
UV patterns: ``{type: align_check, colors: {main: [r, g, b], ul: ..., ur: ..., bl: ...,
br: ...}}`` and ``{type: image, file: NAME}`` (relative to the scene file: ``images``).
"""

from __future__ import annotations

from typing import Any

from yaml.nodes import Node

from scene.colors import read_color
from scene.context import Context
from scene.reader import Entry

# the format's mapping -> the book's function (the cube has its own pattern, cube_map)
MAPPINGS = {
    "spherical": "spherical_map",
    "planar": "planar_map",
    "cylindrical": "cylindrical_map",
    "cube": "cube_map",
}
FACES = ("left", "front", "right", "back", "up", "down")  # cube_map's order
MAP_KEYS = ("type", "mapping", "uv_pattern", *FACES, "transform")
UV_KEYS = {
    "checkers": ("type", "width", "height", "colors"),
    "align_check": ("type", "colors"),
    "image": ("type", "file"),
}
ALIGN_COLORS = ("main", "ul", "ur", "bl", "br")  # uv_align_check's order
MAX_SQUARES = 100_000  # more checkers than pixels in any texture: a mistake


def read_map_pattern(ctx: Context, node: Node, entries: dict[str, Entry]) -> Any:
    """A ``type: map`` pattern (its keys already checked) as the variant's ``texture_map``
    or ``cube_map``; the caller applies its ``transform``."""
    reader = ctx.reader
    mapping_node = reader.require(entries, "mapping", node, "the map pattern")
    mapping = reader.string(mapping_node, "the map pattern's mapping")
    if mapping not in MAPPINGS:
        reader.fail(mapping_node, f"unknown mapping {mapping!r}; known: {', '.join(MAPPINGS)}")
    if mapping == "cube":
        return _cube_map(ctx, node, entries)
    for face in FACES:
        if face in entries:
            reader.fail(
                entries[face].key_node,
                f"'{face}' is a face of 'mapping: cube'; a {mapping} map takes one uv_pattern",
            )
    uv_node = reader.require(entries, "uv_pattern", node, f"the {mapping} map pattern")
    uv = read_uv_pattern(ctx, uv_node, f"the {mapping} map's uv_pattern")
    function = ctx.need(MAPPINGS[mapping], mapping_node, f"a {mapping} map")
    return ctx.need("texture_map", node, "a map pattern")(uv, function)


def _cube_map(ctx: Context, node: Node, entries: dict[str, Entry]) -> Any:
    reader = ctx.reader
    default = None
    if "uv_pattern" in entries:
        default = read_uv_pattern(ctx, entries["uv_pattern"].value, "the cube map's uv_pattern")
    missing = [face for face in FACES if face not in entries]
    if missing and default is None:
        reader.fail(
            node,
            f"the cube map pattern has no UV pattern for {', '.join(missing)}; give each of "
            f"{', '.join(FACES)} one (or uv_pattern: for the faces not given)",
        )
    faces = [
        read_uv_pattern(ctx, entries[face].value, f"the cube map's {face} face")
        if face in entries
        else default
        for face in FACES
    ]
    return ctx.need("cube_map", node, "a cube map pattern")(*faces)


def read_uv_pattern(ctx: Context, node: Node, what: str) -> Any:
    """``{type: checkers | align_check | image, ...}`` as the variant's UV pattern."""
    reader = ctx.reader
    entries = reader.mapping(node, what)
    type_node = reader.require(entries, "type", node, what)
    kind = reader.string(type_node, f"{what}'s type")
    if kind not in UV_KEYS:
        reader.fail(type_node, f"unknown UV pattern type {kind!r}; known: {', '.join(UV_KEYS)}")
    reader.check_keys(entries, UV_KEYS[kind], f"{what} ({kind})")
    if kind == "checkers":
        width, height = (
            reader.whole(
                reader.require(entries, key, node, f"{what} (checkers)"),
                f"{what}: the checkers' {key} (squares along {axis})",
                1,
                MAX_SQUARES,
            )
            for key, axis in (("width", "u"), ("height", "v"))
        )
        colors_node = reader.require(entries, "colors", node, f"{what} (checkers)")
        colors = reader.sequence(colors_node, f"{what}: the checkers' colors")
        if len(colors) != 2:
            reader.fail(
                colors_node,
                f"{what}: checkers take 2 colors ([[r, g, b], [r, g, b]]), got {len(colors)}",
            )
        a, b = (read_color(ctx, c, f"{what}: a checkers color") for c in colors)
        return ctx.need("uv_checkers", type_node, "a checkers UV pattern")(width, height, a, b)
    if kind == "align_check":
        colors_node = reader.require(entries, "colors", node, f"{what} (align_check)")
        named = reader.mapping(colors_node, f"{what}: the align check's colors")
        reader.check_keys(named, ALIGN_COLORS, f"{what}: the align check's colors")
        missing = [name for name in ALIGN_COLORS if name not in named]
        if missing:
            reader.fail(
                colors_node,
                f"{what}: the align check's colors have no {', '.join(missing)}; it needs "
                f"{', '.join(ALIGN_COLORS)}",
            )
        colors = [read_color(ctx, named[name].value, f"{what}: {name}") for name in ALIGN_COLORS]
        return ctx.need("uv_align_check", type_node, "an align_check UV pattern")(*colors)
    file_node = reader.require(entries, "file", node, f"{what} (image)")
    from scene.images import load_image  # deferred: a PNG or PPM decoder for a scene that has one

    image = load_image(ctx, file_node)
    return ctx.need("uv_image", type_node, "an image UV pattern")(image)
