"""Camera rays for many pixels at once (chapter 7's ``ray_for_pixel``), the project's
sample positions (``raytracer.sampling.sample_offset``) and the path integrator's random
numbers (``raytracer.sampling.path_random``) in unsigned 64-bit NumPy integers, so that all
three are the reference's, bit for bit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import Camera
from raytracer.sampling import GAMMA, MASK64, MAX_COORDINATE, MAX_SAMPLES, PATH_TAG
from raytracer.tuples import point

_GAMMA = np.uint64(GAMMA)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_UNIT = 2.0**-53


def _mix64(z: np.ndarray) -> np.ndarray:
    """splitmix64's output function (wrapping uint64 arithmetic)."""
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    return z ^ (z >> np.uint64(31))


def sample_keys(seed: int, x: np.ndarray, y: np.ndarray, i: np.ndarray) -> np.ndarray:
    """``sample_key(seed, x, y, i)`` for arrays of pixels and sample indices (uint64)."""
    if len(x) and not (
        int(x.min()) >= 0 and int(x.max()) < MAX_COORDINATE
        and int(y.min()) >= 0 and int(y.max()) < MAX_COORDINATE
    ):  # fmt: skip
        raise ValueError(f"sample_offset: pixels must lie within 0..{MAX_COORDINATE - 1}")
    if len(i) and not (int(i.min()) >= 0 and int(i.max()) < MAX_SAMPLES):
        raise ValueError(f"sample_offset: sample indices must lie within 0..{MAX_SAMPLES - 1}")
    if not 0 <= seed <= MASK64:
        raise ValueError(f"sample_offset: seed {seed} is outside 0..2**64-1")
    u = np.uint64
    return u((seed * GAMMA) & MASK64) ^ (
        (y.astype(u) << u(34)) | (x.astype(u) << u(20)) | i.astype(u)
    )


def _unit(z: np.ndarray) -> np.ndarray:
    """The top 53 bits of ``z`` as a float64 in [0, 1)."""
    return (z >> np.uint64(11)).astype(np.float64) * _UNIT


def sample_offsets(
    seed: int, x: np.ndarray, y: np.ndarray, i: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``sample_offset(seed, x, y, i)`` for arrays of pixels and sample indices."""
    key = sample_keys(seed, x, y, i)
    return _unit(_mix64(key + _GAMMA)), _unit(_mix64(key + _GAMMA + _GAMMA))


def path_numbers(keys: np.ndarray, bounce: int, dimension: int) -> np.ndarray:
    """``path_random_key(key, bounce, dimension)`` for an array of sample keys (uint64):
    the path integrator's numbers, float64 in [0, 1)."""
    step = np.uint64(((1 + (bounce << 32) + dimension) * GAMMA) & MASK64)
    return _unit(_mix64((keys ^ np.uint64(PATH_TAG)) + step))


@dataclass(frozen=True)
class Lens:
    """A camera's numbers, taken once: pixel size, half extents, the inverse view
    transform's rows 0-2 and the ray origin (computed by the reference's ``Matrix *``)."""

    pixel_size: float
    half_width: float
    half_height: float
    inv: tuple[float, ...]
    origin: tuple[float, float, float]


def lens(c: Camera) -> Lens:
    inv = c.inverse_transform
    o = inv * point(0, 0, 0)
    return Lens(
        float(c.pixel_size),
        float(c.half_width),
        float(c.half_height),
        tuple(float(v) for row in inv.rows[:3] for v in row),
        (float(o.x), float(o.y), float(o.z)),
    )


def camera_rays(lens: Lens, px: Any, py: Any, dtype: Any) -> tuple[np.ndarray, ...]:
    """Chapter 7: the rays through (px, py) (floats allowed) in ``dtype``, computed in
    float64 as the reference computes them: the camera's origin (three scalars) and three
    arrays of directions."""
    m = lens.inv
    world_x = lens.half_width - (px + 0.5) * lens.pixel_size
    world_y = lens.half_height - (py + 0.5) * lens.pixel_size
    ox, oy, oz = lens.origin
    x = m[0] * world_x + m[1] * world_y + m[2] * -1 + m[3] - ox
    y = m[4] * world_x + m[5] * world_y + m[6] * -1 + m[7] - oy
    z = m[8] * world_x + m[9] * world_y + m[10] * -1 + m[11] - oz
    length = np.sqrt(x * x + y * y + z * z)
    scalar = np.dtype(dtype).type
    return (
        scalar(ox),  # one origin for every ray: scalars
        scalar(oy),
        scalar(oz),
        (x / length).astype(dtype, copy=False),
        (y / length).astype(dtype, copy=False),
        (z / length).astype(dtype, copy=False),
    )
