"""Colors (chapter 2) as the scene format writes them: ``[r, g, b]``."""

from __future__ import annotations

from typing import Any

from yaml.nodes import Node

from scene.context import Context


def read_color(ctx: Context, node: Node, what: str) -> Any:
    """``[r, g, b]`` (each 0 or more; above 1 is brighter than white) as the variant's
    color."""
    r, g, b = ctx.reader.numbers(node, what, 3)
    for item, value, name in zip(
        ctx.reader.sequence(node, what), (r, g, b), ("red", "green", "blue"), strict=True
    ):
        if value < 0:
            ctx.reader.fail(
                item,
                f"{what}: {name} is {value}; a color's components are 0 or more (a negative "
                "amount of light does not exist)",
            )
    return ctx.need("color", node, what)(r, g, b)
