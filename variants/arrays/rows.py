"""The reference's values as the rows of the array tracers' tables (chapters 1-4, 6): a
transform's top three rows, the inverse transpose that carries normals, a tuple's x, y, z,
a colour's red, green, blue; and how much a transform can lengthen a vector (the world-space
balls that hold a shape). Plain Python floats: the packers collect them into NumPy tables.
"""

from __future__ import annotations

import math

from raytracer.colors import Color
from raytracer.matrices import Matrix
from raytracer.tuples import Tuple


def rows3x4(m: Matrix) -> list[float]:
    """Rows 0-2 of a 4x4 affine ``m`` (12 values, row by row; row 3 is 0 0 0 1)."""
    return [float(v) for row in m.rows[:3] for v in row]


def normal_rows(inv: Matrix) -> list[float]:
    """Chapter 6: rows 0-2 of the inverse transpose (3x3), which carries an object-space
    normal to world space: element (r, c) is ``inv[c][r]``."""
    return [float(inv.rows[c][r]) for r in range(3) for c in range(3)]


def xyz(t: Tuple) -> list[float]:
    """A point's or a vector's x, y, z (its w is known by what the table holds)."""
    return [float(t.x), float(t.y), float(t.z)]


def rgb(c: Color) -> list[float]:
    """A colour's red, green, blue."""
    return [float(c.red), float(c.green), float(c.blue)]


def stretch(m: Matrix) -> float:
    """An upper bound of how much the 3x3 part A of ``m`` can lengthen a vector: the square
    root of the largest row sum of |AᵀA| (Gershgorin; exact for a rotation times a scale
    along the axes). Plain Python: a NumPy call here would wake BLAS threads, which then
    spin beside the render's threads."""
    a = [[float(v) for v in row[:3]] for row in m.rows[:3]]
    gram = [[sum(a[k][i] * a[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return math.sqrt(max(sum(abs(v) for v in row) for row in gram))
