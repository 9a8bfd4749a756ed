"""The world (chapter 7): objects and lights. Shading it (chapters 7, 8 and 11) is the
``Tracer``'s (``raytracer.tracer``).

A world is an entity: ``w.light ← ...`` and "s is added to w" change it in place. The book's
world has one light, ``w.light``; the published scenes light theirs with several, so a world
holds a list, ``lights``, and ``light`` is its first. A light is a point light (chapter 6)
or an area light (the bonus chapter "Rendering soft shadows"). A world may also have a sky
(chapter 21 here, beyond the book), which only the path integrator sees.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.colors import color
from raytracer.lights import Light, point_light
from raytracer.materials import material
from raytracer.shapes.shape import Shape
from raytracer.shapes.sphere import Sphere
from raytracer.sky import Sky
from raytracer.transformations import scaling
from raytracer.tuples import point


@dataclass(slots=True, eq=True)
class World:
    """Chapter 7: ``objects`` (a list of shapes) lit by ``lights`` (a list of lights, in
    order; empty: no light yet, and every point shades black); ``sky``: what a path that
    escapes sees (``raytracer.sky``; None: black, and the Whitted integrator never looks)."""

    objects: list[Shape] = field(default_factory=list)
    lights: list[Light] = field(default_factory=list)
    sky: Sky | None = None

    @property
    def light(self) -> Light | None:
        """Chapter 7: the world's (first) light, or None when it has none."""
        return self.lights[0] if self.lights else None

    @light.setter
    def light(self, value: Light | None) -> None:
        """``w.light ← l`` replaces the first light (or gives the world one);
        ``w.light ← nothing`` removes every light."""
        if value is None:
            self.lights.clear()
        elif self.lights:
            self.lights[0] = value
        else:
            self.lights.append(value)


def world() -> World:
    """Chapter 7: an empty world with no light."""
    return World()


def default_world() -> World:
    """Chapter 7: the book's test world: two concentric spheres lit from the upper left."""
    s1 = Sphere(material=material(color=color(0.8, 1.0, 0.6), diffuse=0.7, specular=0.2))
    s2 = Sphere(transform=scaling(0.5, 0.5, 0.5))
    return World([s1, s2], [point_light(point(-10, 10, -10), color(1, 1, 1))])
