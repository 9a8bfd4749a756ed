"""The numba variant's fast paths for worlds of balls (issue 36): the shadow ray's tests of
every ball before the ray is normalized (``kernels_hits.balls_may_shadow``, and
``ball_surely_shadows``) against the exact test along the unit vector, on random balls, on
rays that graze a ball and on rays whose light is on a ball."""

from __future__ import annotations

import numpy as np
from numba import njit

from variants.numba import layout as L
from variants.numba.kernels_geometry import ball_first
from variants.numba.kernels_hits import ball_soa_terms, ball_surely_shadows, balls_may_shadow


@njit(error_model="numpy")
def _answers(balls, n, rays):
    """Per shadow ray (origin, vector to the light): (the filter's answer, the exact one:
    does a shadow-casting ball meet the unit ray before the light?, does the exact test
    meet a ball whose value the filter left below 0?, does ``ball_surely_shadows`` say a
    ball is in the way, does it where the exact test finds that ball not?)."""
    out = np.zeros((len(rays), 5), np.bool_)
    tb = np.zeros(max(n, 1))
    for k in range(len(rays)):
        ox, oy, oz, vx, vy, vz = rays[k]
        out[k, 0] = balls_may_shadow(balls, n, ox, oy, oz, vx, vy, vz, tb)
        distance = np.sqrt(vx * vx + vy * vy + vz * vz)
        dx, dy, dz = vx / distance, vy / distance, vz / distance
        a = dx * dx + dy * dy + dz * dz
        length2 = vx * vx + vy * vy + vz * vz
        for j in range(n):
            sure = ball_surely_shadows(balls, n, j, ox, oy, oz, vx, vy, vz, length2)
            out[k, 3] = out[k, 3] or sure
            hb, cc = ball_soa_terms(balls, n, j, ox, oy, oz, dx, dy, dz)
            out[k, 4] = out[k, 4] or (sure and not ball_first(hb, cc, a, distance)[0])
            if balls[L.B_SHADOW * n + j] != 0.0:
                hb, cc = ball_soa_terms(balls, n, j, ox, oy, oz, dx, dy, dz)
                found, _, _ = ball_first(hb, cc, a, distance)
                out[k, 1] = out[k, 1] or found
                out[k, 2] = out[k, 2] or (found and tb[j] < 0.0)
    return out


def _balls(rng: np.random.Generator, n: int) -> np.ndarray:
    """n random balls as the packed ball list (a row per field, flat), one in four casting
    no shadow."""
    table = np.zeros((L.B_PRIM + 1, n))
    table[L.B_X : L.B_Z + 1] = rng.uniform(-3, 3, (3, n))
    table[L.B_R2] = rng.uniform(0.1, 1.5, n) ** 2
    table[L.B_SHADOW] = (np.arange(n) % 4 != 3).astype(float)
    table[L.B_PRIM] = np.arange(n)
    return np.ascontiguousarray(table.ravel())


def _grazing(rng: np.random.Generator, balls: np.ndarray, n: int, count: int) -> np.ndarray:
    """Shadow rays along a line tangent to a ball (nudged by a few units in the last place
    or not at all), starting before the tangent point or on it and ending beyond it."""
    table = balls.reshape(L.B_PRIM + 1, n)
    rays = np.zeros((count, 6))
    for k in range(count):
        j = k % n
        centre = table[L.B_X : L.B_Z + 1, j]
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        along = np.cross(normal, rng.normal(size=3))
        along /= np.linalg.norm(along)
        touch = centre + np.sqrt(table[L.B_R2, j]) * normal * (1 + rng.choice([-1, 0, 1]) * 1e-15)
        before, after = rng.choice([0.0, 0.5, 3.0]), rng.uniform(0.001, 4.0)
        origin = touch - before * along
        rays[k, :3] = origin
        rays[k, 3:] = touch + after * along - origin
    return rays


def _ending_on_a_ball(
    rng: np.random.Generator, balls: np.ndarray, n: int, count: int
) -> np.ndarray:
    """Shadow rays whose light is on a ball's surface (nudged by a few units in the last
    place or not at all), from inside it, or from outside (through it, or towards it)."""
    table = balls.reshape(L.B_PRIM + 1, n)
    rays = np.zeros((count, 6))
    for k in range(count):
        j = k % n
        centre = table[L.B_X : L.B_Z + 1, j]
        radius = np.sqrt(table[L.B_R2, j])
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        light = centre + radius * normal * (1 + rng.choice([-1, 0, 1]) * 1e-15)
        inside = centre + rng.uniform(-0.9, 0.9, 3) * radius / np.sqrt(3)
        outside = centre + rng.choice([-1, 1]) * rng.uniform(1.01, 3.0) * radius * normal
        origin = inside if k % 2 == 0 else outside
        rays[k, :3] = origin
        rays[k, 3:] = light - origin
    return rays


def test_the_shadow_filter_never_turns_down_a_ball_the_exact_test_meets() -> None:
    """Wherever the exact test finds a shadow-casting ball before the light, the filter
    says a ball may be in the way (its answer no lets ``shadowed`` return at once), and
    that ball's value is not below 0 (``shadowed`` tests exactly only those balls); on
    random rays it also says no often, and both exact answers occur."""
    rng = np.random.default_rng(36)
    n = 9
    balls = _balls(rng, n)
    random_rays = np.concatenate([rng.uniform(-4, 4, (6000, 3)), rng.normal(size=(6000, 3))], 1)
    random_rays[::5, 3:] *= 1e-3  # lights very near the point
    random_rays[::7, 3:] *= 1e3  # and very far
    ending = _ending_on_a_ball(rng, balls, n, 6000)
    for rays in (random_rays, _grazing(rng, balls, n, 6000), ending):
        answers = _answers(balls, n, rays)
        missed = answers[:, 1] & ~answers[:, 0]
        assert not missed.any(), f"{missed.sum()} shadow rays let through: {rays[missed][:3]}"
        dropped = answers[:, 2]
        assert not dropped.any(), f"{dropped.sum()} balls met but turned down: {rays[dropped][:3]}"
        assert 0 < answers[:, 1].sum() < len(rays)
        wrong = answers[:, 4]
        assert not wrong.any(), f"{wrong.sum()} balls surely in the way, not: {rays[wrong][:3]}"
        assert answers[:, 3].sum() > len(rays) // 50  # it is sure often enough to matter
    answers = _answers(balls, n, random_rays)
    assert (~answers[:, 0]).sum() > len(random_rays) // 10  # the filter answers no often


def test_with_no_ball_nothing_is_in_the_way() -> None:
    assert not _answers(np.zeros(0), 0, np.array([[0.0, 0, 0, 1, 2, 3]]))[0, 0]
