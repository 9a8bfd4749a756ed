"""Transform lists (chapter 4's matrices): ``[[translate, x, y, z], [scale, ...], a-name, ...]``.

Each entry is applied after the previous one, so the list ``[A, B, C]`` is the matrix
``C * B * A``. A name stands for a transform list defined earlier.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from yaml.nodes import Node, ScalarNode, SequenceNode

from scene.context import Context
from scene.reader import describe

if TYPE_CHECKING:
    from fractions import Fraction

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


def _exact_determinant(rows: list[list[float]]) -> Fraction:
    """The determinant of the matrix the floats ``rows`` hold exactly (no rounding)."""
    # deferred: fractions (with decimal) is for the rare transform that cannot be inverted
    from fractions import Fraction

    m = [[Fraction(value) for value in row] for row in rows]
    n, det = len(m), Fraction(1)
    for col in range(n):
        pivot = next((r for r in range(col, n) if m[r][col] != 0), None)
        if pivot is None:
            return Fraction(0)
        if pivot != col:
            m[col], m[pivot] = m[pivot], m[col]
            det = -det
        det *= m[col][col]
        for r in range(col + 1, n):
            factor = m[r][col] / m[col][col]
            if factor:
                m[r] = [a - factor * b for a, b in zip(m[r], m[col], strict=True)]
    return det


def _exponent(value: Fraction) -> float:
    """``log10(|value|)`` of a non-zero exact number (which may be far outside a float)."""
    return math.log10(abs(value.numerator)) - math.log10(value.denominator)


def _inverse_is_finite(ctx: Context, matrix: Any, size: int) -> bool:
    """Whether the variant's ``inverse`` of ``matrix`` is a matrix of finite floats; if so,
    it is kept in ``ctx.inverses`` for the packer."""
    try:
        inverted = ctx.api["inverse"](matrix)
        finite = all(
            math.isfinite(float(inverted[r, c])) for r in range(size) for c in range(size)
        )
    except (ValueError, ZeroDivisionError, OverflowError):
        return False
    if finite:
        ctx.inverses[id(matrix)] = (matrix, inverted)
    return finite


def transform_problem(ctx: Context, matrix: Any) -> str | None:
    """What makes ``matrix`` unusable as a transform, as the end of a sentence naming it
    (None: nothing). A shape's transform is inverted for every ray: the variant's
    ``inverse`` must give a matrix of finite floats. When it cannot, the exact determinant
    of the floats says why: 0; next to 0 for the lengths of its rows (space flattened almost
    onto a plane); or merely outside the range of a float (a scale of 1e-200)."""
    size = matrix.size
    rows = [[float(matrix[r, c]) for c in range(size)] for r in range(size)]
    bad = next((v for row in rows for v in row if not math.isfinite(v)), None)
    if bad is not None:
        return (
            f"has an entry that is not a finite number ({bad}): its scales or translations "
            "multiply past the largest float (about 1.8e308)"
        )
    if _inverse_is_finite(ctx, matrix, size):
        return None
    det = _exact_determinant(rows)
    if det == 0:
        return (
            "is not invertible: its determinant is 0 (a scale by 0, or a shear that flattens "
            "space onto a plane); expected an invertible transform"
        )
    # |det| / the product of the lengths of the linear part's rows (translation left out):
    # 1 for a rotation or a scale, near 0 when the rows nearly lie in a plane, however large
    # or small the transform is
    linear = [row[:3] for row in rows[:3]] if size == 4 else rows
    flatness = _exponent(det) - sum(math.log10(math.hypot(*row)) for row in linear)
    if flatness < -12:
        return (
            "is not invertible in floating point: it flattens space almost onto a plane (its "
            f"determinant is about 1e{round(flatness)} of what its rows' lengths allow); "
            "expected a transform that keeps some thickness along every axis"
        )
    exponent = round(_exponent(det))
    size_word, bound = (
        ("small", "below the smallest") if exponent < 0 else ("large", "above the largest")
    )
    return (
        f"is not invertible in floating point: it is too {size_word} (its determinant, about "
        f"1e{exponent}, is not 0 but {bound} float, about 1e{'-' if exponent < 0 else ''}308); "
        "keep the product of its scales between about 1e-300 and 1e300"
    )
