"""The torus's quartic (chapter 20 here) as numba and wavefront solve it, robust's way
(``variants/numba/kernels_quartic.py``, ``variants/wavefront/quartic.py``): the stiff rays,
whose roots are known exactly by construction, and agreement with robust's roots.

A ray along x at height y across the torus of radii R and r meets it where
x² + y² + R² - r² = ±2 R x, so at x = ±R ± √(r² - y²): with r = 5/16 and y = 3/16 that
root is 1/4 exactly, and every distance below is a float, at every power-of-two scale.
"""

from __future__ import annotations

import functools
import math
import random
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from raytracer.shapes.torus import torus_coefficients
from variants.registry import load_variant
from variants.robust.geometry import torus_roots
from variants.robust.roots import derivative, rounding_at, value_at
from variants.wavefront.geometry import torus as wavefront_torus

Solver = Callable[[tuple[float, ...], tuple[float, ...], float, float], list[float]]


@functools.cache
def _numba() -> Any:
    return load_variant("numba").api


def numba_roots(
    o: tuple[float, ...], d: tuple[float, ...], big: float, small: float
) -> list[float]:
    api = _numba()
    shape = api["torus"]()
    shape.major_radius, shape.minor_radius = big, small
    return [
        float(i.t) for i in api["intersect"](shape, api["ray"](api["point"](*o), api["vector"](*d)))
    ]


def wavefront_roots(
    o: tuple[float, ...], d: tuple[float, ...], big: float, small: float
) -> list[float]:
    found = wavefront_torus(*(np.array([v]) for v in (*o, *d)), big, small)
    return [float(ts[0]) for ts in found if np.isfinite(ts[0])]


def robust_roots(
    o: tuple[float, ...], d: tuple[float, ...], big: float, small: float
) -> list[float]:
    return torus_roots(*o, *d, big, small)


SOLVERS = {"numba": numba_roots, "wavefront": wavefront_roots, "robust": robust_roots}
SCALES = [2.0**k for k in (-14, -7, 0, 7, 14)]  # about 1e-4 ... 1e4, exactly


def _stiff(
    s: float,
) -> list[tuple[str, tuple[float, ...], tuple[float, ...], float, float, list[float]]]:
    """(name, origin, direction, R, r, the exact roots) at scale ``s``."""
    r = 5 / 16 * s
    return [
        ("across", (-5 * s, 3 / 16 * s, 0.0), (1.0, 0.0, 0.0), s, r,
         [3.75 * s, 4.25 * s, 5.75 * s, 6.25 * s]),
        ("tangent", (-5 * s, r, 0.0), (1.0, 0.0, 0.0), s, r, [4 * s, 4 * s, 6 * s, 6 * s]),
        ("above", (-5 * s, r * (1 + 2.0**-30), 0.0), (1.0, 0.0, 0.0), s, r, []),
        ("short direction", (-5 * s, 3 / 16 * s, 0.0), (0.125, 0.0, 0.0), s, r,
         [30 * s, 34 * s, 46 * s, 50 * s]),
        ("far", (-(2.0**14) * s, 3 / 16 * s, 0.0), (1.0, 0.0, 0.0), s, r,
         [(2.0**14 + x) * s for x in (-1.25, -0.75, 0.75, 1.25)]),
        ("axis, thin hole", (0.0, -5 * s, 0.0), (0.0, 1.0, 0.0), s, s * (1 - 2.0**-20), []),
        ("from the tube's centre line", (s, 0.0, 0.0), (1.0, 0.0, 0.0), s, r,
         [-2.3125 * s, -1.6875 * s, -0.3125 * s, 0.3125 * s]),
    ]  # fmt: skip


CASES = [case for s in SCALES for case in _stiff(s)]


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("case", CASES, ids=[f"{name}-{o[0]:g}" for name, o, *_ in CASES])
def test_the_stiff_rays_give_their_exact_roots(solver: str, case: Any) -> None:
    """Double roots twice, no root made up within a hair of a tangent, none lost at any
    scale or distance: each root within 4 units in the last place of the exact one."""
    _, origin, direction, big, small, exact = case
    got = SOLVERS[solver](origin, direction, big, small)
    assert len(got) == len(exact), f"{solver}: {got}, exactly {exact}"
    for t, x in zip(got, exact, strict=True):
        assert abs(t - x) <= 4 * math.ulp(x) + 1e-15 * abs(x), f"{solver}: {got}, exactly {exact}"


def _random_rays(count: int) -> list[tuple[tuple[float, ...], tuple[float, ...], float, float]]:
    rand = random.Random(36)
    rays = []
    for _ in range(count):
        s = 10 ** rand.uniform(-4, 4)
        big = s * rand.uniform(0.5, 2)
        small = big * rand.uniform(0.05, 1.1)
        o = tuple(rand.uniform(-4, 4) * s for _ in range(3))
        reach = big + small  # aimed at a point of the torus's box
        at = (rand.uniform(-reach, reach), rand.uniform(-small, small), rand.uniform(-reach, reach))
        d = tuple((a - b) * rand.uniform(0.1, 10) / s for a, b in zip(at, o, strict=True))
        rays.append((o, d, big, small))
    return rays


def noise(o: tuple[float, ...], d: tuple[float, ...], big: float, small: float, t: float) -> float:
    """How far apart two correct answers for the root near ``t`` can be: the rounding of the
    quartic's value there (``roots.rounding_at``) over its slope, on the quartic robust
    solves (the ray's origin at its closest approach to the centre)."""
    dd = sum(v * v for v in d)
    shift = -sum(a * b for a, b in zip(o, d, strict=True)) / dd
    c = torus_coefficients(*(a + shift * b for a, b in zip(o, d, strict=True)), *d, big, small)
    return rounding_at(c, t - shift) / abs(value_at(derivative(c), t - shift))


@pytest.mark.parametrize("solver", ["numba", "wavefront"])
def test_the_compiled_and_array_solvers_find_robusts_roots(solver: str) -> None:
    """Random rays across random tori from 1e-4 to 1e4: the same number of roots as robust,
    each within 4 units in the last place, or within the quartic's rounding at the root
    over its slope where that is more (numba's closed form, polished by Newton's steps,
    stops where the steps are that rounding's noise; robust halves its bracket on)."""
    rays = _random_rays(300)
    hits = 0
    for o, d, big, small in rays:
        expected = robust_roots(o, d, big, small)
        got = SOLVERS[solver](o, d, big, small)
        hits += bool(expected)
        assert len(got) == len(expected), (o, d, big, small, got, expected)
        for t, x in zip(got, expected, strict=True):
            allowed = 4 * math.ulp(x) + noise(o, d, big, small, x)
            assert abs(t - x) <= allowed, (o, d, big, small, got, expected)
    assert hits > len(rays) // 3, "the rays must meet the tori often"


def test_wavefront_solves_many_rays_at_once_as_one_by_one() -> None:
    """The array solver on a whole pass (rays of one torus) gives each ray's own roots."""
    rays = [(o, d) for o, d, _, _ in _random_rays(200)]
    big, small = 1.0, 0.25
    columns = [np.array([ray[0][i] for ray in rays]) for i in range(3)]
    columns += [np.array([ray[1][i] for ray in rays]) for i in range(3)]
    together = wavefront_torus(*columns, big, small)
    for k, (o, d) in enumerate(rays):
        alone = wavefront_roots(o, d, big, small)
        assert [float(ts[k]) for ts in together if np.isfinite(ts[k])] == alone


def _shifted_quartic(
    o: tuple[float, ...], d: tuple[float, ...], big: float, small: float
) -> tuple[float, ...]:
    """The quartic numba and robust solve: the ray's origin moved to its closest approach."""
    dd = sum(v * v for v in d)
    shift = -sum(a * b for a, b in zip(o, d, strict=True)) / dd
    return torus_coefficients(*(a + shift * b for a, b in zip(o, d, strict=True)), *d, big, small)


def test_the_certified_closed_form_proves_ordinary_rays_and_declines_grazing_ones() -> None:
    """numba's fast path (``kernels_quartic.certified_roots``): on random rays it proves its
    answer almost always, and every answer it proves has robust's count of roots; a ray
    grazing the tube (double roots) or along the axis (a double complex pair) it leaves to
    the isolation."""
    from variants.numba.kernels_quartic import certified_roots
    from variants.robust.roots import real_roots

    proved = 0
    rays = _random_rays(300)
    for o, d, big, small in rays:
        c = _shifted_quartic(o, d, big, small)
        done, n, *_ = certified_roots(*c)
        if done:
            proved += 1
            assert n == len(real_roots(c)), (o, d, big, small)
    assert proved >= 0.9 * len(rays)
    for s in SCALES:
        for name, origin, direction, big, small, exact in _stiff(s):
            done, n, *_ = certified_roots(*_shifted_quartic(origin, direction, big, small))
            assert not done or n == len(exact), (name, s)
            if name in ("tangent", "axis, thin hole"):
                assert not done, (name, s)
