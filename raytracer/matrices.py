"""Matrices (chapter 3): 2x2, 3x3 and 4x4, with the book's cofactor-expansion inverse.

A ``Matrix`` is an immutable value holding a tuple of row tuples. The algorithms are the
book's, naive on purpose: ``inverse`` expands cofactors recursively every time it is called.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import overload

from raytracer.tuples import Tuple


class NotInvertibleError(ValueError):
    """Raised for a matrix whose determinant is 0 where an inverse is needed."""


@dataclass(frozen=True, slots=True)
class Matrix:
    """A square matrix; ``rows`` is a tuple of row tuples. ``M[r, c]`` reads one element."""

    rows: tuple[tuple[float, ...], ...]

    @property
    def size(self) -> int:
        """The number of rows (and columns)."""
        return len(self.rows)

    def __getitem__(self, key: tuple[int, int]) -> float:
        row, col = key
        return self.rows[row][col]

    @overload
    def __mul__(self, other: Matrix) -> Matrix: ...
    @overload
    def __mul__(self, other: Tuple) -> Tuple: ...
    def __mul__(self, other: Matrix | Tuple) -> Matrix | Tuple:
        if isinstance(other, Tuple):
            return _multiply_tuple(self, other)
        if isinstance(other, Matrix):
            return _multiply_matrix(self, other)
        return NotImplemented


def _multiply_matrix(a: Matrix, b: Matrix) -> Matrix:
    """Chapter 3: the matrix product ``a * b`` (both the same size)."""
    n = a.size
    if b.size != n:
        raise ValueError(f"cannot multiply a {n}x{n} matrix by a {b.size}x{b.size} matrix")
    return Matrix(
        tuple(
            tuple(sum(a.rows[r][k] * b.rows[k][c] for k in range(n)) for c in range(n))
            for r in range(n)
        )
    )


def _multiply_tuple(a: Matrix, t: Tuple) -> Tuple:
    """Chapter 3: a 4x4 matrix times a tuple, treating the tuple as a column."""
    if a.size != 4:
        raise ValueError(f"only a 4x4 matrix can multiply a tuple, not a {a.size}x{a.size} one")
    r0, r1, r2, r3 = a.rows
    return Tuple(
        r0[0] * t.x + r0[1] * t.y + r0[2] * t.z + r0[3] * t.w,
        r1[0] * t.x + r1[1] * t.y + r1[2] * t.z + r1[3] * t.w,
        r2[0] * t.x + r2[1] * t.y + r2[2] * t.z + r2[3] * t.w,
        r3[0] * t.x + r3[1] * t.y + r3[2] * t.z + r3[3] * t.w,
    )


def matrix(rows: Sequence[Sequence[float]]) -> Matrix:
    """Chapter 3: a matrix from a sequence of rows; it must be square, 2x2 to 4x4.

    rows: e.g. ``[[1, 2], [3, 4]]``; the numbers are stored as floats.
    """
    lengths = [len(row) for row in rows]
    n = len(lengths)
    if not 2 <= n <= 4 or any(length != n for length in lengths):
        shape = ", ".join(str(length) for length in lengths) or "none"
        raise ValueError(
            f"matrix: expected a square 2x2, 3x3 or 4x4 matrix, got {n} rows of lengths {shape}"
        )
    return Matrix(tuple(tuple(float(value) for value in row) for row in rows))


identity_matrix = Matrix(
    (
        (1.0, 0.0, 0.0, 0.0),
        (0.0, 1.0, 0.0, 0.0),
        (0.0, 0.0, 1.0, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    )
)
"""Chapter 3: the 4x4 identity matrix."""


def transpose(m: Matrix) -> Matrix:
    """Chapter 3: rows become columns."""
    return Matrix(tuple(zip(*m.rows, strict=True)))


def determinant(m: Matrix) -> float:
    """Chapter 3: the determinant; 2x2 directly, larger by cofactor expansion on row 0."""
    if m.size == 2:
        (a, b), (c, d) = m.rows
        return a * d - b * c
    return sum(m.rows[0][col] * cofactor(m, 0, col) for col in range(m.size))


def submatrix(m: Matrix, row: int, col: int) -> Matrix:
    """Chapter 3: ``m`` without the given row and column (one size smaller)."""
    return Matrix(
        tuple(
            tuple(value for c, value in enumerate(values) if c != col)
            for r, values in enumerate(m.rows)
            if r != row
        )
    )


def minor(m: Matrix, row: int, col: int) -> float:
    """Chapter 3: the determinant of ``submatrix(m, row, col)``."""
    return determinant(submatrix(m, row, col))


def cofactor(m: Matrix, row: int, col: int) -> float:
    """Chapter 3: the minor, negated when ``row + col`` is odd."""
    value = minor(m, row, col)
    return -value if (row + col) % 2 else value


def is_invertible(m: Matrix) -> bool:
    """Chapter 3: a matrix is invertible when its determinant is not 0."""
    return determinant(m) != 0


def inverse(m: Matrix) -> Matrix:
    """Chapter 3: the inverse: the transposed cofactor matrix divided by the determinant.

    Raises ``NotInvertibleError`` (a ``ValueError``) when the determinant is 0.
    """
    det = determinant(m)
    if det == 0:
        raise NotInvertibleError(
            f"inverse: the {m.size}x{m.size} matrix is not invertible (determinant 0)"
        )
    n = m.size
    # element [row][col] of the inverse is cofactor(col, row) / det: the transpose is built in
    return Matrix(tuple(tuple(cofactor(m, c, r) / det for c in range(n)) for r in range(n)))


def inverse_of(m: Matrix, owner: str, hint: str = "") -> Matrix:
    """Chapter 3's inverse of ``owner``'s transform ``m``; a singular one is reported by
    naming ``owner`` (and ``hint``: what to do about it), not as a bare matrix."""
    try:
        return inverse(m)
    except NotInvertibleError:
        raise NotInvertibleError(
            f"{owner}: its transform is not invertible (determinant 0){hint}"
        ) from None


def book_name(thing: object) -> str:
    """The name of ``thing``'s class in the reference (``Sphere`` for a variant's twin of
    a sphere), for messages."""
    for cls in type(thing).__mro__:
        if cls.__module__.startswith("raytracer."):
            return cls.__name__
    return type(thing).__name__
