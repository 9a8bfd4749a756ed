"""What robust's root-finding costs (chapter 20 here): the learner's closed-form quartic
(``raytracer.quartic``, Ferrari) against robust's isolation and safeguarded Newton steps
(``variants.robust.roots``), on the same rays across a unit torus, ordinary ones where both
are right (the stiff ones, where only robust is, are ``rtc stability``'s torus rows); and
numba's compiled isolation against its proved closed form (``kernels_quartic``).

In the normal test run each benchmark runs once, untimed, and the two are checked to agree
on every ray. Time them with::

    .venv/bin/python -m pytest tests/benchmarks/test_torus_roots.py --benchmark-enable \\
        --benchmark-columns=min,median,mean,stddev,rounds
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from typing import Any

import pytest

from raytracer.quartic import solve_quartic
from raytracer.shapes.torus import torus_coefficients
from variants.robust.geometry import torus_roots

Ray = tuple[float, float, float, float, float, float]


def _rays(count: int = 200) -> list[Ray]:
    """Rays from 5 units away aimed at random points of the torus's box: about half meet
    it, twice or four times."""
    rand = random.Random(20)
    rays = []
    for _ in range(count):
        theta, phi = rand.uniform(0, 2 * math.pi), rand.uniform(-1.2, 1.2)
        origin = (5 * math.cos(theta) * math.cos(phi), 5 * math.sin(phi),
                  5 * math.sin(theta) * math.cos(phi))  # fmt: skip
        target = (rand.uniform(-1.25, 1.25), rand.uniform(-0.25, 0.25), rand.uniform(-1.25, 1.25))
        direction = [b - a for a, b in zip(origin, target, strict=True)]
        dx, dy, dz = (d / math.hypot(*direction) for d in direction)
        rays.append((*origin, dx, dy, dz))
    return rays


RAYS = _rays()


def learner(rays: list[Ray]) -> list[list[float]]:
    return [solve_quartic(*torus_coefficients(*r, 1.0, 0.25)) for r in rays]


def robust(rays: list[Ray]) -> list[list[float]]:
    return [torus_roots(*r, 1.0, 0.25) for r in rays]


def test_the_two_solvers_agree_on_ordinary_rays() -> None:
    found = learner(RAYS)
    hits = sum(1 for ts in found if ts)
    assert RAYS and hits > len(RAYS) // 4, "the rays must meet the torus often"
    for r, ts, us in zip(RAYS, found, robust(RAYS), strict=True):
        assert len(ts) == len(us), r
        assert all(abs(t - u) <= 1e-9 * max(1.0, abs(u)) for t, u in zip(ts, us, strict=True))


@pytest.mark.parametrize("solver", [learner, robust], ids=["learner", "robust"])
def test_torus_roots(benchmark: Callable[..., object], solver: Callable[..., object]) -> None:
    benchmark.group = "torus quartic, 200 rays"  # type: ignore[attr-defined]
    benchmark(solver, RAYS)


def _numba_solver(name: str) -> Callable[[list[Ray]], Any]:
    """numba's compiled quartic solver ``name`` (``variants/numba/kernels_quartic.py``) on
    each ray's quartic (robust's: the origin at its closest approach), in one compiled loop:
    ``quartic_real_roots`` isolates the roots as robust does, ``quartic_roots`` proves
    Ferrari's closed form first."""
    import numpy as np
    from numba import njit

    from variants.numba import kernels_quartic

    solve = getattr(kernels_quartic, name)

    @njit(cache=False)
    def each(c: Any, out: Any) -> None:  # pragma: no cover - compiled
        for i in range(c.shape[0]):
            n, r0, r1, r2, r3 = solve(c[i, 0], c[i, 1], c[i, 2], c[i, 3], c[i, 4])
            out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4] = n, r0, r1, r2, r3

    def shifted(r: Ray) -> tuple[float, ...]:
        ox, oy, oz, dx, dy, dz = r
        t = -(ox * dx + oy * dy + oz * dz) / (dx * dx + dy * dy + dz * dz)
        return torus_coefficients(ox + t * dx, oy + t * dy, oz + t * dz, dx, dy, dz, 1.0, 0.25)

    coefficients = np.array([shifted(r) for r in RAYS])
    out = np.empty((len(coefficients), 5))

    def solver(rays: list[Ray]) -> Any:  # the timed part: the compiled loop alone
        each(coefficients, out)
        return out

    return solver


def _listed(out: Any) -> list[list[float]]:
    return [list(row[1 : 1 + int(row[0])]) for row in out]


def test_numbas_proved_closed_form_finds_the_isolations_roots() -> None:
    isolated = _listed(_numba_solver("quartic_real_roots")(RAYS))
    proved = _listed(_numba_solver("quartic_roots")(RAYS))
    assert sum(1 for ts in isolated if ts) > len(RAYS) // 4, "the rays must meet the torus often"
    for ts, us in zip(proved, isolated, strict=True):
        assert len(ts) == len(us)
        assert all(abs(t - u) <= 1e-12 * max(1.0, abs(u)) for t, u in zip(ts, us, strict=True))


@pytest.mark.parametrize("name", ["quartic_real_roots", "quartic_roots"],
                         ids=["numba-isolated", "numba-proved-closed-form"])  # fmt: skip
def test_numba_torus_roots(benchmark: Callable[..., object], name: str) -> None:
    benchmark.group = "torus quartic, 200 rays, numba"  # type: ignore[attr-defined]
    solver = _numba_solver(name)
    solver(RAYS)  # compiled before it is timed
    benchmark(solver, RAYS)
