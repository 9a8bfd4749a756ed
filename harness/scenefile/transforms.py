"""Transform lists (chapter 4's matrices): ``[[translate, x, y, z], [scale, ...], a-name, ...]``.

Each entry is applied after the previous one, so the list ``[A, B, C]`` is the matrix
``C * B * A``. A name stands for a transform list defined earlier.
"""

from __future__ import annotations

from typing import Any

from yaml.nodes import Node, ScalarNode, SequenceNode

from harness.scenefile.context import Context
from harness.scenefile.reader import describe

# entry -> (the book's function, the numbers it takes)
TRANSFORMS: dict[str, tuple[str, tuple[str, ...]]] = {
    "translate": ("translation", ("x", "y", "z")),
    "scale": ("scaling", ("x", "y", "z")),
    "rotate-x": ("rotation_x", ("radians",)),
    "rotate-y": ("rotation_y", ("radians",)),
    "rotate-z": ("rotation_z", ("radians",)),
    "shear": ("shearing", ("xy", "xz", "yx", "yz", "zx", "zy")),
}


def _entry(ctx: Context, node: Node, what: str) -> Any:
    """One ``[name, numbers...]`` entry as a matrix."""
    items = ctx.reader.sequence(node, what)
    known = ", ".join(TRANSFORMS)
    if not items or not isinstance(items[0], ScalarNode):
        ctx.reader.fail(node, f"{what}: expected [name, numbers...] with a name from {known}")
    name = ctx.reader.string(items[0], what)
    if name not in TRANSFORMS:
        ctx.reader.fail(items[0], f"{what}: unknown transform {name!r}; known: {known}")
    function, parameters = TRANSFORMS[name]
    numbers = items[1:]
    if len(numbers) != len(parameters):
        plural = "number" if len(parameters) == 1 else "numbers"
        ctx.reader.fail(
            node,
            f"{what}: '{name}' takes {len(parameters)} {plural} ({', '.join(parameters)}), "
            f"got {len(numbers)}",
        )
    values = [
        ctx.reader.number(item, f"{what}: '{name}' {parameter}")
        for item, parameter in zip(numbers, parameters, strict=True)
    ]
    return ctx.need(function, node, f"'{name}'")(*values)


def read_transform(ctx: Context, node: Node, what: str) -> Any:
    """A transform list (or the name of one) as one matrix, built with the variant's API."""
    if isinstance(node, ScalarNode):  # a defined name on its own: transform: my-transform
        return ctx.lookup(node, "transform", what).value
    if not isinstance(node, SequenceNode):
        ctx.reader.fail(
            node, f"{what} must be a list of [translate|scale|rotate-x|...] entries, "
            f"got {describe(node)}"
        )  # fmt: skip
    result = ctx.need("identity_matrix", node, "a transform")
    for item in node.value:
        if isinstance(item, ScalarNode):
            step = ctx.lookup(item, "transform", f"{what} entry").value
        else:
            step = _entry(ctx, item, f"{what} entry")
        result = step * result
    return result


def is_invertible(ctx: Context, matrix: Any) -> bool:
    """Whether the variant can invert ``matrix`` (its determinant is not 0)."""
    try:
        ctx.api["inverse"](matrix)
    except (ValueError, ZeroDivisionError):
        return False
    return True
