"""The world (chapter 7): objects and a light; shading with shadows (chapter 8), and
reflection and refraction (chapter 11).

A world is an entity: ``w.light ← ...`` and "s is added to w" change it in place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from raytracer.colors import BLACK, Color, color
from raytracer.intersections import (
    Computations,
    Intersection,
    hit,
    intersections,
    prepare_computations,
    schlick,
)
from raytracer.lights import PointLight, point_light
from raytracer.materials import lighting, material
from raytracer.rays import Ray, ray
from raytracer.shapes.shape import Shape, intersect
from raytracer.shapes.sphere import Sphere
from raytracer.transformations import scaling
from raytracer.tuples import Tuple, dot, magnitude, normalize, point


@dataclass(slots=True, eq=True)
class World:
    """Chapter 7: ``objects`` (a list of shapes) lit by ``light`` (None: no light yet)."""

    objects: list[Shape] = field(default_factory=list)
    light: PointLight | None = None


def world() -> World:
    """Chapter 7: an empty world with no light."""
    return World()


def default_world() -> World:
    """Chapter 7: the book's test world: two concentric spheres lit from the upper left."""
    s1 = Sphere(material=material(color=color(0.8, 1.0, 0.6), diffuse=0.7, specular=0.2))
    s2 = Sphere(transform=scaling(0.5, 0.5, 0.5))
    return World([s1, s2], point_light(point(-10, 10, -10), color(1, 1, 1)))


def intersect_world(w: World, r: Ray) -> list[Intersection]:
    """Chapter 7: every intersection of ``r`` with every object, in a new list sorted by t."""
    xs: list[Intersection] = []
    for obj in w.objects:
        xs.extend(intersect(obj, r))
    return intersections(*xs)


def _light(w: World, caller: str) -> PointLight:
    if w.light is None:
        raise ValueError(f"{caller}: the world has no light source")
    return w.light


def shade_hit(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapters 7, 8, 11: the color at a hit: surface (shadowed or not), plus reflection
    and refraction, blended with Schlick's reflectance for reflective, transparent surfaces.

    remaining: how many more reflected or refracted rays may be spawned.
    """
    light = _light(w, "shade_hit")
    shadowed = is_shadowed(w, comps.over_point)
    m = comps.object.material
    surface = lighting(
        m, comps.object, light, comps.over_point, comps.eyev, comps.normalv, shadowed
    )
    reflected = reflected_color(w, comps, remaining)
    refracted = refracted_color(w, comps, remaining)
    if m.reflective > 0 and m.transparency > 0:
        reflectance = schlick(comps)
        return surface + reflected * reflectance + refracted * (1 - reflectance)
    return surface + reflected + refracted


def color_at(w: World, r: Ray, remaining: int = 5) -> Color:
    """Chapter 7: the color seen along ``r``: black when it hits nothing.

    remaining: how many more reflected or refracted rays may be spawned.
    """
    xs = intersect_world(w, r)
    h = hit(xs)
    if h is None:
        return BLACK
    return shade_hit(w, prepare_computations(h, r, xs), remaining)


def is_shadowed(w: World, point: Tuple) -> bool:
    """Chapter 8: True when an object (one that casts shadows) lies between ``point`` and the
    light."""
    light = _light(w, "is_shadowed")
    v = light.position - point
    distance = magnitude(v)
    r = ray(point, normalize(v))
    xs = [i for i in intersect_world(w, r) if i.object.casts_shadow]
    h = hit(xs)
    return h is not None and h.t < distance


def reflected_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: the color reflected at the hit, scaled by the material's reflectivity.

    remaining: how many more reflected or refracted rays may be spawned; at 0, black.
    """
    reflective = comps.object.material.reflective
    if reflective == 0 or remaining <= 0:
        return BLACK
    reflect_ray = ray(comps.over_point, comps.reflectv)
    return color_at(w, reflect_ray, remaining - 1) * reflective


def refracted_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: the color seen through the surface (Snell's law), scaled by transparency.

    remaining: how many more reflected or refracted rays may be spawned; at 0, black.
    Black too under total internal reflection.
    """
    transparency = comps.object.material.transparency
    if transparency == 0 or remaining <= 0:
        return BLACK
    n_ratio = comps.n1 / comps.n2
    cos_i = dot(comps.eyev, comps.normalv)
    sin2_t = n_ratio * n_ratio * (1 - cos_i * cos_i)
    if sin2_t > 1:
        return BLACK  # total internal reflection
    cos_t = math.sqrt(1.0 - sin2_t)
    direction = comps.normalv * (n_ratio * cos_i - cos_t) - comps.eyev * n_ratio
    refract_ray = ray(comps.under_point, direction)
    return color_at(w, refract_ray, remaining - 1) * transparency
