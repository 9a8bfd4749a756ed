"""Matrix and tuple arithmetic into caller-owned buffers (chapters 1, 3, 5 and 6).

Every function here computes exactly what its naive twin computes, in the same order of
floating-point operations (all four components, ``w`` included), so the results are equal
bit for bit; only the Tuple/Matrix/Ray objects are gone. Output buffers may be the input
buffers: inputs are read into locals before anything is written.
"""

from __future__ import annotations

import math

from raytracer.matrices import Matrix
from variants.prealloc.buffers import Vec


def flat_matrix(m: Matrix) -> Vec:
    """A 4x4 ``Matrix`` as a flat list of 16 floats, row by row."""
    if m.size != 4:
        raise ValueError(f"prealloc: expected a 4x4 transform, got a {m.size}x{m.size} matrix")
    return [float(value) for row in m.rows for value in row]


def transform_point_into(m: Vec, p: Vec, out: Vec) -> None:
    """``out = m * p`` for a flat 4x4 ``m`` (naive twin: ``Matrix * Tuple``)."""
    x, y, z, w = p
    out[0] = m[0] * x + m[1] * y + m[2] * z + m[3] * w
    out[1] = m[4] * x + m[5] * y + m[6] * z + m[7] * w
    out[2] = m[8] * x + m[9] * y + m[10] * z + m[11] * w
    out[3] = m[12] * x + m[13] * y + m[14] * z + m[15] * w


def transform_ray_into(m: Vec, ray: Vec, out: Vec) -> None:
    """Chapter 5: ``out = transform(ray, m)``, the Go write-up's ``TransformRayPtr``
    (naive twin: ``raytracer.rays.transform``, which returns a new Ray of new Tuples)."""
    ox, oy, oz, ow, dx, dy, dz, dw = ray
    out[0] = m[0] * ox + m[1] * oy + m[2] * oz + m[3] * ow
    out[1] = m[4] * ox + m[5] * oy + m[6] * oz + m[7] * ow
    out[2] = m[8] * ox + m[9] * oy + m[10] * oz + m[11] * ow
    out[3] = m[12] * ox + m[13] * oy + m[14] * oz + m[15] * ow
    out[4] = m[0] * dx + m[1] * dy + m[2] * dz + m[3] * dw
    out[5] = m[4] * dx + m[5] * dy + m[6] * dz + m[7] * dw
    out[6] = m[8] * dx + m[9] * dy + m[10] * dz + m[11] * dw
    out[7] = m[12] * dx + m[13] * dy + m[14] * dz + m[15] * dw


def position_into(ray: Vec, t: float, out: Vec) -> None:
    """Chapter 5: ``out = position(ray, t)`` (naive twin: ``raytracer.rays.position``)."""
    ox, oy, oz, ow, dx, dy, dz, dw = ray
    out[0] = ox + dx * t
    out[1] = oy + dy * t
    out[2] = oz + dz * t
    out[3] = ow + dw * t


def normalize_into(v: Vec, out: Vec) -> None:
    """Chapter 1: ``out = normalize(v)`` (naive twin: ``raytracer.tuples.normalize``)."""
    x, y, z, w = v
    m = math.sqrt(x * x + y * y + z * z + w * w)
    out[0] = x / m
    out[1] = y / m
    out[2] = z / m
    out[3] = w / m


def reflect_into(v: Vec, n: Vec, out: Vec) -> None:
    """Chapter 6: ``out = reflect(v, n)`` = v - n * 2 * dot(v, n) (naive twin:
    ``raytracer.tuples.reflect``)."""
    vx, vy, vz, vw = v
    nx, ny, nz, nw = n
    d = vx * nx + vy * ny + vz * nz + vw * nw
    out[0] = vx - nx * 2 * d
    out[1] = vy - ny * 2 * d
    out[2] = vz - nz * 2 * d
    out[3] = vw - nw * 2 * d
