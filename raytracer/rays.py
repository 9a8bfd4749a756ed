"""Rays (chapter 5): an origin and a direction."""

from __future__ import annotations

from dataclasses import dataclass

from raytracer.matrices import Matrix
from raytracer.tuples import Tuple


@dataclass(frozen=True, slots=True)
class Ray:
    """A ray: ``origin`` (a point) and ``direction`` (a vector, not necessarily unit length)."""

    origin: Tuple
    direction: Tuple


def ray(origin: Tuple, direction: Tuple) -> Ray:
    """Chapter 5: a ray from ``origin`` along ``direction``."""
    return Ray(origin, direction)


def position(r: Ray, t: float) -> Tuple:
    """Chapter 5: the point at distance ``t`` along ``r``."""
    return r.origin + r.direction * t


def transform(r: Ray, m: Matrix) -> Ray:
    """Chapter 5: a new ray with ``m`` applied to its origin and its direction."""
    return Ray(m * r.origin, m * r.direction)
