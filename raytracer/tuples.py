"""Tuples, points and vectors (chapter 1); ``reflect`` (chapter 6).

A point has ``w == 1``, a vector ``w == 0``. Every operation returns a new ``Tuple``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from raytracer.tolerance import EPSILON


@dataclass(frozen=True, slots=True)
class Tuple:
    """The book's tuple: ``(x, y, z, w)``; ``w`` is 1 for a point and 0 for a vector."""

    x: float
    y: float
    z: float
    w: float

    def __add__(self, other: Tuple) -> Tuple:
        return Tuple(self.x + other.x, self.y + other.y, self.z + other.z, self.w + other.w)

    def __sub__(self, other: Tuple) -> Tuple:
        return Tuple(self.x - other.x, self.y - other.y, self.z - other.z, self.w - other.w)

    def __neg__(self) -> Tuple:
        return Tuple(-self.x, -self.y, -self.z, -self.w)

    def __mul__(self, k: float) -> Tuple:
        return Tuple(self.x * k, self.y * k, self.z * k, self.w * k)

    def __rmul__(self, k: float) -> Tuple:
        return Tuple(self.x * k, self.y * k, self.z * k, self.w * k)

    def __truediv__(self, k: float) -> Tuple:
        return Tuple(self.x / k, self.y / k, self.z / k, self.w / k)


def equal(a: float, b: float) -> bool:
    """Chapter 1: two floats are equal when they differ by less than ``EPSILON``."""
    return abs(a - b) < EPSILON


def tuple_(x: float, y: float, z: float, w: float) -> Tuple:
    """Chapter 1: the book's ``tuple(x, y, z, w)`` (``tuple_`` in Python)."""
    return Tuple(x, y, z, w)


def point(x: float, y: float, z: float) -> Tuple:
    """Chapter 1: a point, ``w = 1``."""
    return Tuple(x, y, z, 1.0)


def vector(x: float, y: float, z: float) -> Tuple:
    """Chapter 1: a vector, ``w = 0``."""
    return Tuple(x, y, z, 0.0)


def magnitude(v: Tuple) -> float:
    """Chapter 1: the length of ``v`` (all four components, as in the book)."""
    return math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z + v.w * v.w)


def normalize(v: Tuple) -> Tuple:
    """Chapter 1: ``v`` scaled to length 1."""
    m = magnitude(v)
    return Tuple(v.x / m, v.y / m, v.z / m, v.w / m)


def dot(a: Tuple, b: Tuple) -> float:
    """Chapter 1: the dot product of two tuples."""
    return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w


def cross(a: Tuple, b: Tuple) -> Tuple:
    """Chapter 1: the cross product of two vectors (a vector perpendicular to both)."""
    return vector(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)


def reflect(v: Tuple, n: Tuple) -> Tuple:
    """Chapter 6: ``v`` reflected around the normal ``n``.

    v: the incoming vector; n: the (unit) surface normal.
    """
    return v - n * 2 * dot(v, n)
