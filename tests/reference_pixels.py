"""``naive``'s colours at chosen pixels of a picture, for the tests that compare a variant's
whole picture with naive's where naive's whole picture costs tens of CPU seconds.

Naive draws each chosen pixel through the pixel loop its ``render`` runs
(``Tracer.render_region``, over a one-pixel region). A pixel's colour depends on its own rays
alone (its samples and a jittered light's points are drawn from the seed and the pixel's
own x and y), so it is the whole picture's pixel, bit for bit. Not so for a light placed by
a ``sequence``: the sequence moves on from pixel to pixel in the render's order, so a test
of one draws the whole picture.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from raytracer.camera import RenderSettings
from variants.registry import load_variant

Pixels = Sequence[tuple[int, int]]


def lattice(width: int, height: int) -> list[tuple[int, int]]:
    """Every other pixel of every other row, (0, 0) first: a quarter of the picture,
    spread over all of it."""
    return [(x, y) for y in range(0, height, 2) for x in range(0, width, 2)]


def checkerboard(width: int, height: int) -> list[tuple[int, int]]:
    """The pixels whose x + y is even: half of every row and of every column."""
    return [(x, y) for y in range(height) for x in range(width) if (x + y) % 2 == 0]


def naive_at(
    build: Callable[[Any], tuple[Any, Any]], settings: RenderSettings, pixels: Pixels
) -> np.ndarray:
    """Naive's colours at ``pixels`` ((x, y) each) of the picture ``build(api) -> (camera,
    world)`` renders with ``settings``: an array of ``len(pixels)`` rows of (r, g, b)."""
    naive = load_variant("naive")
    camera, world = build(naive.api)
    naive.tracer.forget()
    values: list[float] = []
    for x, y in pixels:
        values += naive.tracer.render_region(camera, world, settings, (x, y, x + 1, y + 1))
    naive.tracer.forget()
    return np.array(values, dtype=np.float64).reshape(-1, 3)


def picture_at(picture: np.ndarray, pixels: Pixels) -> np.ndarray:
    """The rows of a (height, width, 3) picture at ``pixels``, as ``naive_at`` gives them."""
    return np.array([picture[y, x] for x, y in pixels], dtype=np.float64).reshape(-1, 3)
