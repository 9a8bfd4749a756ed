"""The camera (chapter 7): which ray goes through which pixel, and how to render
(``RenderSettings``); the render loop itself is the ``Tracer``'s (``raytracer.tracer``).

Naive on purpose: the camera's half extents and pixel size are computed on every access, and
``ray_for_pixel`` inverts the camera transform for every ray.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from raytracer.matrices import Matrix, identity_matrix, inverse_of
from raytracer.rays import Ray
from raytracer.sampling import MAX_SAMPLES
from raytracer.tolerance import EPSILON
from raytracer.tuples import normalize, point

VIEW_HINT = "; view_transform(from, to, up) needs 'up' across the line from 'from' to 'to'"


@dataclass(frozen=True, slots=True)
class Camera:
    """Chapter 7: a pinhole camera.

    hsize, vsize: the canvas size in pixels; field_of_view: the horizontal or vertical
    angle (radians) the wider side of the canvas spans; transform: the view transformation
    (world space to camera space; the camera looks down -z from the origin).
    """

    hsize: int
    vsize: int
    field_of_view: float
    transform: Matrix = identity_matrix

    def _half_extents(self) -> tuple[float, float]:
        """(half_width, half_height) of the canvas one unit in front of the camera."""
        half_view = math.tan(self.field_of_view / 2)
        aspect = self.hsize / self.vsize
        if aspect >= 1:
            return half_view, half_view / aspect
        return half_view * aspect, half_view

    @property
    def half_width(self) -> float:
        return self._half_extents()[0]

    @property
    def half_height(self) -> float:
        return self._half_extents()[1]

    @property
    def pixel_size(self) -> float:
        """The width (and height) of one pixel one unit in front of the camera."""
        return self._half_extents()[0] * 2 / self.hsize

    @property
    def inverse_transform(self) -> Matrix:
        """The inverse of ``transform``, computed on every access (the naive baseline)."""
        return inverse_of(self.transform, "camera", VIEW_HINT)


def camera(hsize: int, vsize: int, field_of_view: float) -> Camera:
    """Chapter 7: a camera at the origin looking down -z.

    hsize, vsize: the canvas size in pixels; field_of_view: in radians, between 0 and π.
    """
    if isinstance(hsize, bool) or isinstance(vsize, bool) or hsize < 1 or vsize < 1:
        raise ValueError(f"camera({hsize!r}, {vsize!r}, ...): the size must be at least 1x1")
    if hsize != int(hsize) or vsize != int(vsize):
        raise ValueError(f"camera({hsize!r}, {vsize!r}, ...): the size must be whole pixels")
    if not 0 < field_of_view < math.pi:
        raise ValueError(
            f"camera(..., {field_of_view!r}): the field of view must be between 0 and π radians"
        )
    return Camera(int(hsize), int(vsize), field_of_view)


def ray_for_pixel(c: Camera, px: float, py: float) -> Ray:
    """Chapter 7: the ray from the camera through the centre of pixel (px, py).

    px, py: the pixel; floats are allowed (``px + dx - 0.5`` aims at offset dx in the pixel).
    """
    xoffset = (px + 0.5) * c.pixel_size
    yoffset = (py + 0.5) * c.pixel_size
    world_x = c.half_width - xoffset  # the camera looks toward -z, so +x is to the left
    world_y = c.half_height - yoffset
    inv = c.inverse_transform
    pixel = inv * point(world_x, world_y, -1)
    origin = inv * point(0, 0, 0)
    return Ray(origin, normalize(pixel - origin))


WHITTED = "whitted"
PATH = "path"
INTEGRATORS = (WHITTED, PATH)
"""How light is gathered: the book's recursive (Whitted) ray tracing, chapters 7-11, or
Monte Carlo path tracing (chapter 21 here, beyond the book: ``raytracer.path``)."""
MAX_DEPTH = 100  # reflections, refractions or bounces of one ray


@dataclass(frozen=True, slots=True)
class RenderSettings:
    """How to render (not in the book, except ``depth``, its ``remaining``).

    depth: how many times a ray may be reflected or refracted (the book's 5); under the
    path integrator, how many times a path may scatter;
    samples: rays per pixel (1: through the centre, as in the book; more: antialiasing);
    seed: chooses the sample positions when samples > 1 (see ``raytracer.sampling``), and
    the path integrator's random numbers;
    epsilon: the offset for over_point/under_point and friends (``EPSILON`` by default);
    integrator: ``"whitted"`` (the book's, the default) or ``"path"``;
    roulette: the path integrator's Russian roulette from this bounce on (0: off);
    light_sampling: the path integrator aims a shadow ray at every light from each diffuse
    hit (True, the default), or finds an area light only where a path crosses it (False;
    ``raytracer.path``'s docstring gives both).
    """

    depth: int = 5
    samples: int = 1
    seed: int = 0
    epsilon: float = EPSILON
    integrator: str = WHITTED
    roulette: int = 0
    light_sampling: bool = True

    def __post_init__(self) -> None:
        def whole(value: object) -> bool:
            return isinstance(value, int) and not isinstance(value, bool)

        if not whole(self.depth) or not 0 <= self.depth <= MAX_DEPTH:
            raise ValueError(
                f"RenderSettings: depth must be a whole number 0 to {MAX_DEPTH}, got {self.depth!r}"
            )
        if self.integrator not in INTEGRATORS:
            raise ValueError(
                f"RenderSettings: integrator must be {' or '.join(INTEGRATORS)}, got "
                f"{self.integrator!r}"
            )
        if not whole(self.roulette) or not 0 <= self.roulette <= MAX_DEPTH:
            raise ValueError(
                f"RenderSettings: roulette must be a whole number 0 (off) to {MAX_DEPTH}, got "
                f"{self.roulette!r}"
            )
        if not isinstance(self.light_sampling, bool):
            raise ValueError(
                f"RenderSettings: light_sampling must be True or False, got "
                f"{self.light_sampling!r}"
            )
        if not whole(self.samples) or not 1 <= self.samples <= MAX_SAMPLES:
            raise ValueError(
                f"RenderSettings: samples must be a whole number 1 to "
                f"{MAX_SAMPLES}, got {self.samples!r}"
            )
        if not whole(self.seed) or not 0 <= self.seed < 2**64:
            raise ValueError(
                f"RenderSettings: seed must be a whole number 0 to 2**64-1, got {self.seed!r}"
            )
        if (
            isinstance(self.epsilon, bool)
            or not isinstance(self.epsilon, int | float)
            or not (0 < self.epsilon < 1)
        ):
            raise ValueError(
                f"RenderSettings: epsilon must be a number between 0 and 1, got {self.epsilon!r}"
            )


def render_settings(**options: Any) -> RenderSettings:
    """How to render: ``RenderSettings`` with the ``options`` given (depth, samples, seed,
    epsilon, integrator, roulette, light_sampling) and the defaults for the others, e.g.
    ``render_settings(integrator="path", samples=16)`` (chapter 21 here, beyond the book)."""
    return RenderSettings(**options)
