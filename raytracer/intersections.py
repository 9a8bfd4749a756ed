"""Intersections (chapter 5), their precomputed state (chapters 7, 8 and 11), and Schlick's
approximation of the Fresnel effect (chapter 11).

``Intersection`` and its constructors are defined beside ``Shape`` (``raytracer.shapes.shape``:
a shape's ``local_intersect`` makes them, and each names the other); they are this module's
names too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from raytracer.rays import Ray, position
from raytracer.shapes.shape import (  # chapter 5's, defined beside Shape (each names the other)
    Intersection,
    Shape,
    intersection,
    intersection_with_uv,
    intersections,
    normal_at,
)
from raytracer.tolerance import epsilon
from raytracer.tuples import Tuple, dot, reflect

__all__ = [
    "Computations",
    "Intersection",
    "computations_at",
    "hit",
    "intersection",
    "intersection_with_uv",
    "intersections",
    "prepare_computations",
    "schlick",
]


def hit(xs: Sequence[Intersection]) -> Intersection | None:
    """Chapter 5: the visible intersection: the lowest non-negative ``t``, or None."""
    best: Intersection | None = None
    for i in xs:
        if i.t >= 0 and (best is None or i.t < best.t):
            best = i
    return best


@dataclass(frozen=True, slots=True)
class Computations:
    """Chapter 7 (with chapter 8's ``over_point`` and chapter 11's additions): what shading
    needs to know about a hit.

    eyev: towards the eye; normalv: the surface normal, flipped to face the eye;
    inside: True when the hit is inside the object (the normal was flipped);
    over_point / under_point: the point nudged by epsilon along / against the normal;
    reflectv: the ray direction reflected around the normal;
    n1 / n2: refractive indices on the incoming / outgoing side of the surface.
    """

    t: float
    object: Shape
    point: Tuple
    eyev: Tuple
    normalv: Tuple
    inside: bool
    over_point: Tuple
    under_point: Tuple
    reflectv: Tuple
    n1: float
    n2: float


def _same(i: Intersection, hit: Intersection) -> bool:
    """The same intersection: identical, or the same ``t`` on the identical object."""
    return i is hit or (i.t == hit.t and i.object is hit.object)


def _refractive_indices(hit: Intersection, xs: Sequence[Intersection]) -> tuple[float, float]:
    """Chapter 11: n1 and n2 from the objects the ray is inside of at the hit.

    The ``containers`` list tracks objects by identity (two equal spheres are still two).
    """
    n1 = n2 = 1.0
    containers: list[Shape] = []
    for i in xs:
        is_hit = _same(i, hit)
        if is_hit:
            n1 = containers[-1].material.refractive_index if containers else 1.0
        for index, obj in enumerate(containers):
            if obj is i.object:
                del containers[index]
                break
        else:
            containers.append(i.object)
        if is_hit:
            n2 = containers[-1].material.refractive_index if containers else 1.0
            break
    return n1, n2


def prepare_computations(
    hit: Intersection, ray: Ray, xs: Sequence[Intersection] | None = None
) -> Computations:
    """Chapters 7, 8, 11: precompute the state shading needs for ``hit``.

    hit: the intersection being shaded; ray: the ray that produced it;
    xs: all intersections along the ray, for n1/n2 (default: just ``hit``).
    """
    point = position(ray, hit.t)
    normalv = normal_at(hit.object, point, hit)
    n1, n2 = _refractive_indices(hit, [hit] if xs is None else xs)
    return computations_at(hit, ray, point, normalv, epsilon(), n1, n2)


def computations_at(
    hit: Intersection,
    ray: Ray,
    point: Tuple,
    normalv: Tuple,
    offset: float,
    n1: float,
    n2: float,
) -> Computations:
    """Chapters 7, 8, 11: the computations at ``point`` on ``hit``, its surface normal
    ``normalv`` flipped to face the eye, over/under points ``offset`` along it."""
    eyev = -ray.direction
    inside = dot(normalv, eyev) < 0
    if inside:
        normalv = -normalv
    nudge = normalv * offset
    return Computations(
        t=hit.t,
        object=hit.object,
        point=point,
        eyev=eyev,
        normalv=normalv,
        inside=inside,
        over_point=point + nudge,
        under_point=point - nudge,
        reflectv=reflect(ray.direction, normalv),
        n1=n1,
        n2=n2,
    )


def schlick(comps: Computations) -> float:
    """Chapter 11: Schlick's approximation of the reflectance (0 to 1) at the hit."""
    cos = dot(comps.eyev, comps.normalv)
    if comps.n1 > comps.n2:
        n = comps.n1 / comps.n2
        sin2_t = n * n * (1.0 - cos * cos)
        if sin2_t > 1.0:
            return 1.0  # total internal reflection
        cos = math.sqrt(1.0 - sin2_t)
    r0 = ((comps.n1 - comps.n2) / (comps.n1 + comps.n2)) ** 2
    return r0 + (1 - r0) * (1 - cos) ** 5


def refraction_direction(comps: Computations) -> Tuple | None:
    """Chapter 11: the direction of the ray refracted at the hit (Snell's law, from the
    eye vector and the normal), or None under total internal reflection. Not normalized:
    as the book's ``refracted_color`` computes it."""
    n_ratio = comps.n1 / comps.n2
    cos_i = dot(comps.eyev, comps.normalv)
    sin2_t = n_ratio * n_ratio * (1 - cos_i * cos_i)
    if sin2_t > 1:
        return None  # total internal reflection
    cos_t = math.sqrt(1.0 - sin2_t)
    return comps.normalv * (n_ratio * cos_i - cos_t) - comps.eyev * n_ratio
