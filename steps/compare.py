"""Approximate equality as the book defines it, and readable descriptions of values.

Duck-typed, because a learner's variant brings its own types: anything with ``x y z w`` is a
tuple, anything with ``red green blue`` a colour, anything with ``size`` and ``m[r, c]`` a
matrix, anything with ``t`` and ``object`` an intersection.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from numbers import Real
from typing import Any

EPSILON = 0.0001  # the book's tolerance for comparing floating-point values

TUPLE_FIELDS = ("x", "y", "z", "w")
COLOR_FIELDS = ("red", "green", "blue")


def is_number(value: object) -> bool:
    return isinstance(value, Real)


def is_tuple_like(value: object) -> bool:
    return all(hasattr(value, name) for name in TUPLE_FIELDS)


def is_color_like(value: object) -> bool:
    return all(hasattr(value, name) for name in COLOR_FIELDS)


def is_intersection_like(value: object) -> bool:
    return hasattr(value, "t") and hasattr(value, "object")


def matrix_shape(value: object) -> tuple[int, int] | None:
    """``(rows, columns)`` of a matrix-like value, or None.

    ``shape`` (NumPy) wins over ``size``; the book's ``size`` is the number of rows of a
    square matrix (a pair is read as rows and columns).
    """
    if isinstance(value, str | bytes) or not hasattr(value, "__getitem__"):
        return None
    shape = getattr(value, "shape", None)
    if isinstance(shape, tuple) and len(shape) == 2:
        return int(shape[0]), int(shape[1])
    size = getattr(value, "size", None)
    if isinstance(size, int) and not isinstance(size, bool):
        return size, size
    if isinstance(size, tuple) and len(size) == 2:
        return int(size[0]), int(size[1])
    return None


def is_sequence(value: object) -> bool:
    return isinstance(value, Sequence) and not isinstance(value, str | bytes)


def numbers_equal(a: float, b: float) -> bool:
    """Equal within EPSILON; infinities equal themselves."""
    if a == b:
        return True
    if math.isinf(a) or math.isinf(b) or math.isnan(a) or math.isnan(b):
        return False
    return abs(a - b) < EPSILON


def approx_equal(a: Any, b: Any) -> bool:
    """The book's equality: EPSILON for numbers and for every component of tuples,
    colours and matrices; an intersection equals a number when its ``t`` does."""
    if a is b:
        return True
    if is_number(a) and is_number(b):
        return numbers_equal(a, b)
    if is_intersection_like(a) and is_number(b):
        return approx_equal(a.t, b)
    if is_number(a) and is_intersection_like(b):
        return approx_equal(a, b.t)
    if is_tuple_like(a) and is_tuple_like(b):
        return _fields_equal(a, b, TUPLE_FIELDS)
    if is_color_like(a) and is_color_like(b):
        return _fields_equal(a, b, COLOR_FIELDS)
    shape_a, shape_b = matrix_shape(a), matrix_shape(b)
    if shape_a is not None and shape_b is not None:
        return shape_a == shape_b and all(
            approx_equal(a[r, c], b[r, c]) for r in range(shape_a[0]) for c in range(shape_a[1])
        )
    if is_sequence(a) and is_sequence(b):
        return len(a) == len(b) and all(approx_equal(x, y) for x, y in zip(a, b, strict=True))
    return bool(a == b)


def _fields_equal(a: object, b: object, names: tuple[str, ...]) -> bool:
    return all(approx_equal(getattr(a, name), getattr(b, name)) for name in names)


def _number(value: float) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if math.isinf(value):
        return "infinity" if value > 0 else "-infinity"
    return f"{float(value):.6g}"


def describe(value: Any, depth: int = 0) -> str:
    """A short, readable description in the book's notation where possible."""
    if value is None:
        return "nothing"
    if is_number(value):
        return _number(value)
    if isinstance(value, str):
        return repr(value) if len(value) <= 200 else repr(value[:200]) + "..."
    if depth > 2:
        return type(value).__name__
    if is_tuple_like(value):
        numbers = ", ".join(describe(getattr(value, name), depth + 1) for name in "xyz")
        w = value.w
        if is_number(w) and w == 1:
            return f"point({numbers})"
        if is_number(w) and w == 0:
            return f"vector({numbers})"
        return f"tuple({numbers}, {describe(w, depth + 1)})"
    if is_color_like(value):
        numbers = ", ".join(describe(getattr(value, name), depth + 1) for name in COLOR_FIELDS)
        return f"color({numbers})"
    if is_intersection_like(value):
        return f"intersection({describe(value.t, depth + 1)}, {_short(value.object)})"
    shape = matrix_shape(value)
    if shape is not None:
        try:
            rows = [
                "| " + " | ".join(_number(value[r, c]) for c in range(shape[1])) + " |"
                for r in range(shape[0])
            ]
        except (TypeError, IndexError, KeyError):
            return _short(value)
        return f"{shape[0]}x{shape[1]} matrix " + " ".join(rows)
    if is_sequence(value):
        items = [describe(item, depth + 1) for item in value[:8]]
        more = f", ... ({len(value)} items)" if len(value) > 8 else ""
        return "[" + ", ".join(items) + more + "]"
    return _short(value)


def _short(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 160 else text[:160] + "..."
