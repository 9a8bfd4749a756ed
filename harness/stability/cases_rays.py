"""Ray cases (chapters 5, 9, 12, 13): cancellation in the textbook quadratic, and grazing
rays, each compared with the exact intersections of the same float ray (``oracle``).

- cancellation: a unit sphere far away (1e6 and 1e8 units). The textbook discriminant
  ``b² - 4ac`` subtracts two numbers of size 4 D² to get one of size about 4, so its
  absolute error grows like D² u: the measure is the hit-distance error in sphere radii.
- grazing: rays tangent to a sphere within 1e-12, nearly parallel to a plane, along cube
  edges and through corners, along a cylinder's axis, through a cone's apex and parallel to
  one of its halves: the hits must be the oracle's (a consistent hit or miss), their
  distances within a relative 1e-6, never NaN.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import mpmath

from harness.stability import oracle
from harness.stability.model import Case, Outcome, Probe, Verdict, graded

RELATIVE = 1e-6  # grazing: largest relative error of a hit distance
RADII = 1e-6  # cancellation: largest hit-distance error, in radii of the sphere


def _fmt(ts: Sequence[Any]) -> str:
    return "[" + ", ".join(f"{float(t):.13g}" for t in ts) + "]"


def cast(
    probe: Probe, shape: Any, origin: oracle.Vec, direction: oracle.Vec, unit: bool
) -> tuple[list[float], oracle.Vec]:
    """The variant's intersections of ``shape`` with the ray (``unit``: its direction
    normalized by the variant's ``normalize``), and the float direction it used."""
    api = probe.api
    d = api["vector"](*direction)
    if unit:
        d = api["normalize"](d)
    r = api["ray"](api["point"](*origin), d)
    ts = [float(i.t) for i in api["intersect"](shape, r)]
    return ts, (float(r.direction.x), float(r.direction.y), float(r.direction.z))


def compare_hits(
    got: list[float], expected: list[Any], tolerance: float, absolute_unit: float | None = None
) -> Outcome:
    """The variant's distances against the oracle's (both as multisets): the same count,
    then the largest error, relative to each distance (or in ``absolute_unit`` units)."""
    if any(not math.isfinite(t) for t in got):
        return Outcome(Verdict.NONFINITE, None, tolerance, f"hits at {got}")
    got = sorted(got)
    if len(got) != len(expected):
        return Outcome(
            Verdict.WRONG, None, tolerance,
            f"{len(got)} hit(s) {_fmt(got)}; the oracle: {len(expected)} {_fmt(expected)}",
            "lost hit" if len(got) < len(expected) else "extra hit",
        )  # fmt: skip
    if not got:
        return Outcome(Verdict.EXACT, 0.0, tolerance, "no hit, as the oracle")
    errors = []
    with mpmath.workdps(oracle.DIGITS):
        for t, t_exact in zip(got, expected, strict=True):
            scale = absolute_unit if absolute_unit is not None else abs(mpmath.mpf(t_exact))
            difference = abs(mpmath.mpf(t) - mpmath.mpf(t_exact))
            errors.append(float(difference / scale) if scale else float(difference))
    exact = all(t == float(t_exact) for t, t_exact in zip(got, expected, strict=True))
    detail = f"hits {_fmt(got)}, oracle {_fmt(expected)}, largest error {max(errors):.2g}"
    return graded(max(errors), tolerance, detail, exact=exact)


# ---------------------------------------------------------------------- cancellation


def cancellation_case(label: str, distance: float) -> Case:
    center = (0.3, 0.2, distance)
    aim = (0.9, -0.3, distance)  # passes 0.78 from the centre

    def check(probe: Probe) -> Outcome:
        api = probe.api
        s = api["sphere"]()
        api["set_transform"](s, api["translation"](*center))
        got, direction = cast(probe, s, (0.0, 0.0, 0.0), aim, unit=True)
        expected = oracle.sphere_ts((0.0, 0.0, 0.0), direction, center)
        return compare_hits(got, expected, RADII, absolute_unit=1.0)

    return Case(
        id=f"cancel/sphere-{label}",
        title=f"a unit sphere {distance:g} away, hit 0.78 off its centre",
        measure="hit-distance error in sphere radii",
        tolerance=f"{RADII:g} radii",
        check=check,
    )


# --------------------------------------------------------------------------- grazing

Build = Callable[[Any], Any]
Oracle = Callable[[oracle.Vec, oracle.Vec], list[Any]]


def _sphere(api: Any) -> Any:
    return api["sphere"]()


def _plane(api: Any) -> Any:
    return api["plane"]()


def _cube(api: Any) -> Any:
    return api["cube"]()


def _cylinder(api: Any) -> Any:
    return api["cylinder"]()


def _capped_cylinder(api: Any) -> Any:
    c = api["cylinder"]()
    c.minimum, c.maximum, c.closed = -1.0, 1.0, True
    return c


def _cone(api: Any) -> Any:
    return api["cone"]()


def _sphere_oracle(o: oracle.Vec, d: oracle.Vec) -> list[Any]:
    return oracle.sphere_ts(o, d, (0.0, 0.0, 0.0))


def _capped_oracle(o: oracle.Vec, d: oracle.Vec) -> list[Any]:
    return oracle.cylinder_ts(o, d, -1.0, 1.0, True)


def grazing_case(
    name: str,
    title: str,
    build: Build,
    exact_ts: Oracle,
    origin: oracle.Vec,
    direction: oracle.Vec,
    unit: bool = False,
) -> Case:
    def check(probe: Probe) -> Outcome:
        got, used = cast(probe, build(probe.api), origin, direction, unit)
        return compare_hits(got, exact_ts(origin, used), RELATIVE)

    return Case(
        id=f"graze/{name}",
        title=title,
        measure="hits as the oracle's; largest relative error of t",
        tolerance=f"same hits, {RELATIVE:g} relative",
        check=check,
    )


GRAZING = [
    grazing_case("sphere-inside-1e-12", "ray 1e-12 inside the tangent of a unit sphere",
                 _sphere, _sphere_oracle, (0.0, 1 - 1e-12, -5.0), (0.0, 0.0, 1.0)),
    grazing_case("sphere-tangent", "ray exactly tangent to a unit sphere (a double hit)",
                 _sphere, _sphere_oracle, (0.0, 1.0, -5.0), (0.0, 0.0, 1.0)),
    grazing_case("sphere-outside-1e-12", "ray 1e-12 outside the tangent of a unit sphere",
                 _sphere, _sphere_oracle, (0.0, 1 + 1e-12, -5.0), (0.0, 0.0, 1.0)),
    grazing_case("plane-1e-12", "ray 1e-12 radians from parallel to a plane, 1 above it",
                 _plane, oracle.plane_ts, (0.0, 1.0, 0.0), (1.0, -1e-12, 0.0), unit=True),
    grazing_case("plane-1e-20", "ray 1e-20 radians from parallel to a plane, 1 above it",
                 _plane, oracle.plane_ts, (0.0, 1.0, 0.0), (1.0, -1e-20, 0.0), unit=True),
    grazing_case("cube-along-edge", "ray running along an edge of a cube",
                 _cube, oracle.cube_ts, (-5.0, 1.0, 1.0), (1.0, 0.0, 0.0)),
    grazing_case("cube-across-edges", "ray entering through one edge, leaving through another",
                 _cube, oracle.cube_ts, (-2.0, 2.0, 0.0), (1.0, -1.0, 0.0)),
    grazing_case("cube-diagonal", "unit ray along the main diagonal, corner to corner",
                 _cube, oracle.cube_ts, (-2.0, -2.0, -2.0), (1.0, 1.0, 1.0), unit=True),
    grazing_case("cube-touch-corner", "ray touching a cube at one corner only",
                 _cube, oracle.cube_ts, (-1.0, -1.0, 3.0), (1.0, 1.0, -1.0)),
    grazing_case("cylinder-axis", "ray along the axis of an open, infinite cylinder",
                 _cylinder, oracle.cylinder_ts, (0.0, -5.0, 0.0), (0.0, 1.0, 0.0)),
    grazing_case("cylinder-axis-capped", "ray along the axis of a closed cylinder (caps)",
                 _capped_cylinder, _capped_oracle, (0.0, -5.0, 0.0), (0.0, 1.0, 0.0)),
    grazing_case("cylinder-axis-1e-12", "ray 1e-12 off an infinite cylinder's axis",
                 _cylinder, oracle.cylinder_ts, (0.0, -5.0, 0.0), (1e-12, 1.0, 0.0)),
    grazing_case("cone-apex-axis", "ray along a cone's axis, through its apex",
                 _cone, oracle.cone_ts, (0.0, -5.0, 0.0), (0.0, 1.0, 0.0)),
    grazing_case("cone-apex-across", "horizontal ray through a cone's apex",
                 _cone, oracle.cone_ts, (-4.0, 0.0, -3.0), (4.0, 0.0, 3.0)),
    grazing_case("cone-in-surface", "ray lying in a cone's surface, through the apex",
                 _cone, oracle.cone_ts, (-1.0, -1.0, 0.0), (1.0, 1.0, 0.0)),
    grazing_case("cone-parallel-half", "the book's ray parallel to one half of a cone",
                 _cone, oracle.cone_ts, (0.0, 0.0, -1.0), (0.0, 1.0, 1.0), unit=True),
    grazing_case("cone-parallel-1e-12", "ray 1e-12 from parallel to one half of a cone",
                 _cone, oracle.cone_ts, (0.0, 0.0, -1.0), (0.0, 1.0, 1 + 1e-12), unit=True),
]  # fmt: skip

CASES = [cancellation_case("1e6", 1e6), cancellation_case("1e8", 1e8), *GRAZING]
