"""Torus cases (chapter 20 here, beyond the book): the quartic, the stiffest equation of the
project, against the exact roots of the same float ray (``oracle.torus_ts``).

- tangent: a ray grazing the top of the tube (two double roots), and 1e-9 inside and
  outside that tangent (two pairs of roots 4.5e-5 apart, or none);
- axis: a ray along the axis through the hole, of an ordinary torus and of one whose hole
  is 1e-6 wide (the minor radius 1 - 1e-6 of the major: a nearly degenerate torus);
- inside: rays starting inside the tube (hits behind the origin count, as in the book);
- scale: the torus with both radii times 1e-4 ... 1e4, the ray with them (the quartic's
  coefficients span the fourth power of the scale), and an ordinary torus seen from 1e4
  away (its coefficients 1e16 apart);
- thin hole: across a torus whose hole is 2e-6 wide (two roots 2e-6 apart).

The ray meets a world holding only the torus (``intersect_world``, chapter 7), so each
variant answers with its own pipeline: numba's compiled kernel, wavefront's arrays. The
measure is the grazing cases': the same hits (a lost or invented root is wrong), then the
largest error of a hit distance relative to it.
"""

from __future__ import annotations

from typing import Any

from harness.stability import oracle
from harness.stability.cases_rays import RELATIVE, compare_hits
from harness.stability.model import Case, Outcome, Probe

THIN = 1 - 1e-6  # the minor radius of the nearly degenerate torus (major 1)


def cast_in_world(
    probe: Probe, shape: Any, origin: oracle.Vec, direction: oracle.Vec, unit: bool
) -> tuple[list[float], oracle.Vec]:
    """The variant's intersections of a world holding only ``shape`` with the ray (``unit``:
    its direction normalized by the variant's ``normalize``), and the float direction it
    used."""
    api = probe.api
    d = api["vector"](*direction)
    if unit:
        d = api["normalize"](d)
    r = api["ray"](api["point"](*origin), d)
    w = api["world"]()
    w.objects.append(shape)
    ts = [float(i.t) for i in api["intersect_world"](w, r)]
    return ts, (float(r.direction.x), float(r.direction.y), float(r.direction.z))


def torus_case(
    name: str, title: str, origin: oracle.Vec, direction: oracle.Vec,
    major: float = 1.0, minor: float = 0.25, unit: bool = False,
) -> Case:  # fmt: skip
    def check(probe: Probe) -> Outcome:
        shape: Any = probe.api["torus"]()
        shape.major_radius, shape.minor_radius = major, minor
        got, used = cast_in_world(probe, shape, origin, direction, unit)
        return compare_hits(got, oracle.torus_ts(origin, used, major, minor), RELATIVE)

    return Case(
        id=f"torus/{name}",
        title=title,
        measure="hits as the oracle's; largest relative error of t",
        tolerance=f"same hits, {RELATIVE:g} relative",
        check=check,
    )


def scale_case(scale: float) -> Case:
    s = scale
    return torus_case(
        f"scale-{s:g}", f"a torus of radii {s:g} and {s / 4:g}, a ray across it, all scaled",
        (-3 * s, 0.1 * s, 0.05 * s), (1.0, 0.0, 0.0), major=s, minor=s / 4,
    )  # fmt: skip


CASES = [
    torus_case("tangent", "ray along the top of the tube (two double roots)",
               (-5.0, 0.25, 0.0), (1.0, 0.0, 0.0)),
    torus_case("tangent-inside-1e-9", "ray 1e-9 below the top of the tube (two close pairs)",
               (-5.0, 0.25 - 1e-9, 0.0), (1.0, 0.0, 0.0)),
    torus_case("tangent-outside-1e-9", "ray 1e-9 above the top of the tube (no hit)",
               (-5.0, 0.25 + 1e-9, 0.0), (1.0, 0.0, 0.0)),
    torus_case("axis", "ray along the axis, through the hole (no hit)",
               (0.0, -5.0, 0.0), (0.0, 1.0, 0.0)),
    torus_case("axis-thin-hole", "ray along the axis of a torus whose hole is 1e-6 wide",
               (0.0, -5.0, 0.0), (0.0, 1.0, 0.0), minor=THIN),
    torus_case("inside-tube", "ray from the tube's centre line, out through its side",
               (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
    torus_case("inside-tube-oblique", "unit ray from inside the tube, oblique",
               (1.05, 0.1, 0.02), (0.3, -0.2, 0.9), unit=True),
    *(scale_case(s) for s in (1e-4, 1e-2, 1e2, 1e4)),
    torus_case("far-1e4", "ray from 1e4 away across an ordinary torus",
               (-1e4, 0.1, 0.05), (1.0, 0.0, 0.0)),
    torus_case("thin-hole-across", "ray across a torus whose hole is 2e-6 wide",
               (-5.0, 0.0, 0.0), (1.0, 0.0, 0.0), minor=THIN),
    torus_case("oblique-unit", "unit ray at an odd angle through both sides of the tube",
               (-3.0, 0.7, -2.0), (3.0, -0.75, 2.1), unit=True),
]  # fmt: skip
