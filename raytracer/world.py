"""The world (chapter 7): objects and a light. Shading it (chapters 7, 8 and 11) is the
``Tracer``'s (``raytracer.tracer``).

A world is an entity: ``w.light ← ...`` and "s is added to w" change it in place.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.colors import color
from raytracer.lights import PointLight, point_light
from raytracer.materials import material
from raytracer.shapes.shape import Shape
from raytracer.shapes.sphere import Sphere
from raytracer.transformations import scaling
from raytracer.tuples import point


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
