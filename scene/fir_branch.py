"""The fir branch of the book forum's christmas scene: a structure of the scene format, not a
shape of the book. ``- add: fir_branch`` becomes a group of a closed cylinder (the stem, 2
units long, radius 0.025, bark material) and 480 needle triangles in 20 segment groups of
24, each needle turned about the stem by a random angle, as the scene's header describes.

The needles are a ``Mesh`` (``scene.obj_mesh``) with one group per segment, so every tracer
takes them as it takes an OBJ model's triangles. Each needle's turn (``rotation_y``) is
applied to its three corners when they are made. The random numbers come from Python's
``random.Random`` seeded with ``seed`` (its sequence for a given seed is the same on every
machine and version): the same file always draws the same branches.
"""

from __future__ import annotations

import math
import random

import numpy as np

from scene.obj_mesh import Mesh

LENGTH = 2.0
RADIUS = 0.025
SEGMENTS = 20
PER_SEGMENT = 24
NEEDLES = SEGMENTS * PER_SEGMENT
BARK = {"color": (0.5, 0.35, 0.26), "ambient": 0.2, "specular": 0.0, "diffuse": 0.6}
NEEDLE = {"color": (0.26, 0.36, 0.16), "specular": 0.1}
"""The stem's and the needles' materials (book property names; colors as numbers)."""


def needle_corners(seed: int) -> np.ndarray:
    """Every needle's three corners in the branch's space: (480, 3, 3) floats, segment by
    segment, drawn from ``random.Random(seed)`` in the header's order (base height, tip
    drop, angle, length)."""
    rand = random.Random(seed).random
    seg_size = LENGTH / (SEGMENTS - 1)
    theta = 2.1 * math.pi / PER_SEGMENT
    max_length = 20 * RADIUS
    ofs = RADIUS / 2
    corners = np.empty((NEEDLES, 3, 3))
    n = 0
    for y in range(SEGMENTS):
        for i in range(PER_SEGMENT):
            y_base = seg_size * y + rand() * seg_size
            y_tip = y_base - rand() * seg_size
            angle = i * theta + rand() * theta
            needle_length = max_length / 2 * (1 + rand())
            c, s = math.cos(angle), math.sin(angle)
            # rotation_y(angle) applied to (ofs, y_base, ofs), (-ofs, y_base, ofs), (0, y_tip, len)
            corners[n] = (
                (c * ofs + s * ofs, y_base, -s * ofs + c * ofs),
                (-c * ofs + s * ofs, y_base, s * ofs + c * ofs),
                (s * needle_length, y_tip, c * needle_length),
            )
            n += 1
    return corners


def needle_mesh(seed: int, source: str) -> Mesh:
    """The needles as a mesh: one group per segment ("segment-1" ...), flat triangles;
    ``source`` names the branch in messages."""
    corners = needle_corners(seed)
    return Mesh(
        source=source,
        positions=corners.reshape(-1, 3),
        normals=np.empty((0, 3)),
        triangles=np.arange(NEEDLES * 3, dtype=np.int32).reshape(NEEDLES, 3),
        corner_normals=None,
        groups=tuple((f"segment-{y + 1}", PER_SEGMENT) for y in range(SEGMENTS)),
    )
