"""Where a path goes at a hit (chapter 21 here, beyond the book): which of a material's
lobes scatters it, and the direction of a diffuse bounce. Pure functions of the material,
the normal and the random numbers given; ``raytracer.path`` draws the numbers.

**Lobes.** The book's material is read as a mixture: a share ``t'`` of glass, ``r'`` of
mirror and the rest diffuse, where r = ``reflective``, t = ``transparency`` and, when
r + t > 1, both are scaled by 1 / (r + t). With s = r + t (a float sum) and u in [0, 1)::

    glass    when u < (t / s if s > 1 else t)
    mirror   else when u < min(s, 1)
    diffuse  otherwise

**A diffuse direction** (cosine-weighted over the hemisphere around the unit normal n),
from u1, u2 in [0, 1)::

    r = sqrt(u1), phi = 2 pi u2
    local = (r cos phi, r sin phi, sqrt(max(0, 1 - u1)))
    direction = T * local.x + B * local.y + n * local.z     (each component summed in
                                                             that order, not normalized)

with (T, B) the orthonormal basis of Duff et al., "Building an orthonormal basis,
revisited" (JCGT 2017), which has no branch but the sign::

    sign = copysign(1, n.z); a = -1 / (sign + n.z); b = n.x n.y a
    T = (1 + sign n.x n.x a, sign b, -sign n.x)
    B = (b, sign + n.y n.y a, -n.y)

The pdf of such a direction is cos(theta) / pi, so a Lambertian bounce's weight is exactly
its albedo: the mean of cos(theta) over many directions is 2/3, of cos^2 1/2.
"""

from __future__ import annotations

import math

from raytracer.materials import Material
from raytracer.tuples import Tuple, vector

GLASS = "glass"
MIRROR = "mirror"
DIFFUSE = "diffuse"
LOBES = (GLASS, MIRROR, DIFFUSE)
"""A material's lobes, in the order ``choose_lobe`` tests them."""


def choose_lobe(m: Material, u: float) -> str:
    """Which lobe of ``m`` scatters a path whose lobe number is ``u`` (in [0, 1)): "glass",
    "mirror" or "diffuse", with the shares of the module docstring."""
    r, t = m.reflective, m.transparency
    s = r + t
    if u < (t / s if s > 1.0 else t):
        return GLASS
    if u < min(s, 1.0):
        return MIRROR
    return DIFFUSE


def orthonormal_basis(n: Tuple) -> tuple[Tuple, Tuple]:
    """Two unit vectors (T, B), perpendicular to each other and to the unit vector ``n``,
    with (T, B, n) right-handed (Duff et al. 2017: the module docstring)."""
    sign = math.copysign(1.0, n.z)
    a = -1.0 / (sign + n.z)
    b = n.x * n.y * a
    return (
        vector(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vector(b, sign + n.y * n.y * a, -n.y),
    )


def cosine_direction(n: Tuple, u1: float, u2: float) -> Tuple:
    """A direction in the hemisphere around the unit normal ``n``, cosine-weighted, from
    two numbers in [0, 1) (the module docstring gives the arithmetic)."""
    r = math.sqrt(u1)
    phi = 2.0 * math.pi * u2
    x, y, z = r * math.cos(phi), r * math.sin(phi), math.sqrt(max(0.0, 1.0 - u1))
    t, b = orthonormal_basis(n)
    return vector(
        t.x * x + b.x * y + n.x * z,
        t.y * x + b.y * y + n.y * z,
        t.z * x + b.z * y + n.z * z,
    )
