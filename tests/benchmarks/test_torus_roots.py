"""What robust's root-finding costs (chapter 20 here): the learner's closed-form quartic
(``raytracer.quartic``, Ferrari) against robust's isolation and safeguarded Newton steps
(``variants.robust.roots``), on the same rays across a unit torus, ordinary ones where both
are right (the stiff ones, where only robust is, are ``rtc stability``'s torus rows).

In the normal test run each benchmark runs once, untimed, and the two are checked to agree
on every ray. Time them with::

    .venv/bin/python -m pytest tests/benchmarks/test_torus_roots.py --benchmark-enable \\
        --benchmark-columns=min,median,mean,stddev,rounds
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable

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
