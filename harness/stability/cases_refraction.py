"""Refraction cases (chapter 11), each with an exact oracle.

- the critical angle: a ray inside a glass sphere (index 1.5) meeting its surface 1e-9
  (relative) past and short of the critical angle: total internal reflection (Schlick's
  reflectance 1, no refracted color) on one side, the refracted color and the exact
  reflectance on the other;
- very high indices: entering a sphere of index 1e6 at 45 degrees, and leaving one of index
  1e200 along its normal (where ``(n1/n2)² (1 - cos²)`` is ``inf * 0`` in floating point);
- index 1.0 against 1.0: a sphere of "glass" with the index of air must be invisible (the
  colors along a grid of 169 rays, with it and without it);
- nested glass with coincident surfaces: two identical spheres of index 1.5 and 2.0; the
  colors must be those of one of them alone (one medium, entered and left);
- the depth limit: a ray trapped between two parallel mirrors, depth 0, 5 and 100; the
  color is exactly the surface color times (depth + 1).

The glass here has no surface color of its own (``scenes.pure_glass``) and the background
glows with an exact color (``scenes.glowing``), so the oracle's colors are exact.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np

from harness.instruments.imagediff import image_error
from harness.stability import oracle
from harness.stability.cases_scale import compare_pictures
from harness.stability.model import Case, Outcome, Probe, Verdict, graded
from harness.stability.scenes import checkered_wall, glowing, material, pure_glass, world_of

TOLERANCE = 1e-6  # reflectance and color channels (both 0 to 1)
WALL = (0.2, 0.4, 0.6)
LIGHT = (-10.0, 10.0, -10.0)


def _wall(api: Any) -> Any:
    wall = api["plane"]()
    api["set_transform"](wall, api["translation"](0, 0, 10) * api["rotation_x"](math.pi / 2))
    wall.material = glowing(api, WALL)
    return wall


def _rgb(c: Any) -> tuple[float, float, float]:
    return float(c.red), float(c.green), float(c.blue)


def surface_case(
    name: str,
    title: str,
    index: float,
    origin: tuple[float, float, float],
    which: int,
    cos_i: Any,
    color: tuple[float, float, float] | None,
) -> Case:
    """Schlick's reflectance and the refracted color at hit ``which`` of the ray from
    ``origin`` along +z through a unit sphere of ``index`` (hit 0: entering from air, 1:
    leaving into air).

    cos_i: the exact cosine of incidence (a function of the float origin); color: the exact
    refracted color, or None where only its finiteness is checked.
    """
    n1, n2 = (1.0, index) if which == 0 else (index, 1.0)

    def check(probe: Probe) -> Outcome:
        api = probe.api
        s = pure_glass(api, index)
        w = world_of(api, [s, _wall(api)], LIGHT)
        r = api["ray"](api["point"](*origin), api["vector"](0, 0, 1))
        xs = api["intersect"](s, r)
        comps = api["prepare_computations"](xs[which], r, xs)
        reflectance = float(api["schlick"](comps))
        refracted = _rgb(api["refracted_color"](w, comps, 5))
        exact_r = oracle.schlick(n1, n2, cos_i(origin))
        seen = (
            f"n1 {float(comps.n1):g}, n2 {float(comps.n2):g}, reflectance {reflectance:.12g} "
            f"(oracle {float(exact_r):.12g}), refracted {refracted}"
        )
        if not all(math.isfinite(v) for v in (reflectance, *refracted)):
            return Outcome(Verdict.NONFINITE, None, TOLERANCE, seen)
        with mpmath.workdps(oracle.DIGITS):
            errors = [float(abs(mpmath.mpf(reflectance) - exact_r))]
        exact = reflectance == float(exact_r)
        if color is not None:
            errors += [abs(a - b) for a, b in zip(refracted, color, strict=True)]
            exact = exact and refracted == color
            seen += f" (oracle {color})"
        return graded(max(errors), TOLERANCE, seen, exact=exact)

    return Case(
        id=f"refract/{name}",
        title=title,
        measure="Schlick reflectance and refracted color: largest absolute error",
        tolerance=f"{TOLERANCE:g}",
        check=check,
    )


def _inside_cos(origin: tuple[float, float, float]) -> Any:
    """A ray from (0, y, 0) along +z meets the unit sphere where cos(incidence) = √(1 - y²)."""
    with mpmath.workdps(oracle.DIGITS):
        y = mpmath.mpf(origin[1])
        return mpmath.sqrt(1 - y * y)


def _critical(sign: int) -> tuple[float, float, float]:
    return (0.0, (1 + sign * 1e-9) / 1.5, 0.0)


def _tir_color(origin: tuple[float, float, float]) -> tuple[float, float, float]:
    """Black under total internal reflection (decided exactly), else the wall's color."""
    with mpmath.workdps(oracle.DIGITS):
        tir = oracle.total_internal_reflection(1.5, 1.0, mpmath.mpf(origin[1]))
    return (0.0, 0.0, 0.0) if tir else WALL


_PAST, _SHORT = _critical(+1), _critical(-1)
_DIAGONAL = (0.0, math.sqrt(0.5), -5.0)

SURFACES = [
    surface_case("critical+1e-9", "leaving glass 1.5 just past the critical angle (TIR)",
                 1.5, _PAST, 1, _inside_cos, _tir_color(_PAST)),
    surface_case("critical-1e-9", "leaving glass 1.5 just short of the critical angle",
                 1.5, _SHORT, 1, _inside_cos, _tir_color(_SHORT)),
    surface_case("index-1e6-enter", "entering a sphere of index 1e6 at 45 degrees",
                 1e6, _DIAGONAL, 0, _inside_cos, None),
    surface_case("index-1e200-leave", "leaving a sphere of index 1e200 along its normal",
                 1e200, (0.0, 0.0, 0.0), 1, _inside_cos, WALL),
]  # fmt: skip


# ------------------------------------------------------------------------- pictures


GRID = 13  # rays per side of the grid aimed at the spheres


def _through(probe: Probe, spheres: list[Any]) -> np.ndarray:
    """The colors seen from (0, 0, -5) along a 13 x 13 grid of rays aimed at the square
    [-1.21, 1.034]² of the plane z = 0 (where the unit spheres are), with glowing checks
    behind: an array (13, 13, 3), independent of any render size."""
    api = probe.api
    w = world_of(api, [*spheres, checkered_wall(api, 3.0)], LIGHT)
    eye = api["point"](0, 0, -5)
    rows = []
    for j in range(GRID):
        row = []
        for i in range(GRID):
            # every ray meets the wall at least 0.038 from a checker boundary, where the
            # offset of a refracted ray (1e-4) would flip the check
            x, y = -1.21 + 0.187 * i, 1.21 - 0.187 * j
            r = api["ray"](eye, api["normalize"](api["point"](x, y, 0) - eye))
            row.append(_rgb(api["color_at"](w, r, 5)))
        rows.append(row)
    return np.array(rows, dtype=np.float64)


def _invisible(probe: Probe) -> Outcome:
    seen = _through(probe, [pure_glass(probe.api, 1.0)])
    return compare_pictures(seen, _through(probe, []), "the colors without the sphere", "rays")


def _coincident(probe: Probe) -> Outcome:
    api = probe.api
    both = _through(probe, [pure_glass(api, 1.5), pure_glass(api, 2.0)])
    bad = int(np.count_nonzero(~np.isfinite(both).all(axis=2)))
    if bad:
        return Outcome(Verdict.NONFINITE, None, 0, f"{bad} rays NaN or infinite")
    alone = {n: image_error(both, _through(probe, [pure_glass(api, n)])) for n in (1.5, 2.0)}
    _, nearest = min(alone.items(), key=lambda item: item[1].pixels_over_one_step)
    detail = (
        f"{alone[1.5].pixels_over_one_step} of {nearest.pixels} rays off the colors of "
        f"glass 1.5 alone by more than 1/255, {alone[2.0].pixels_over_one_step} off 2.0 alone"
    )
    if nearest.max_abs == 0:
        return Outcome(Verdict.EXACT, 0.0, 0, detail)
    count = nearest.pixels_over_one_step
    return Outcome(Verdict.WITHIN if count == 0 else Verdict.WRONG, float(count), 0, detail)


PICTURES = [
    Case("refract/index-1-vs-1", "a sphere of index 1.0 in air, in front of checks (169 rays)",
         "rays whose color is off the one without it by > 1/255", "0 rays", _invisible,
         "rays"),
    Case("refract/coincident-nested", "two coincident spheres of index 1.5 and 2.0 (169 rays)",
         "rays off the colors of the nearer single sphere by > 1/255", "0 rays", _coincident,
         "rays"),
]  # fmt: skip


# ------------------------------------------------------------------------- depth limit


def _mirror(api: Any, y: float) -> Any:
    p = api["plane"]()
    api["set_transform"](p, api["translation"](0, y, 0))
    p.material = material(api, reflective=1.0)
    return p


def depth_case(depth: int) -> Case:
    def check(probe: Probe) -> Outcome:
        api = probe.api
        lower, upper = _mirror(api, -1.0), _mirror(api, 1.0)
        w = world_of(api, [lower, upper], (0.0, 0.0, 0.0))
        m = lower.material
        r = api["ray"](api["point"](0, 0, 0), api["vector"](0, 1, 0))
        got = _rgb(api["color_at"](w, r, depth))
        # every bounce sees the light head-on along the normal: ambient + diffuse + specular
        per_bounce = Fraction(m.ambient) + Fraction(m.diffuse) + Fraction(m.specular)
        expected = per_bounce * (depth + 1)
        detail = f"color {got[0]:.12g} per channel; oracle {float(expected):.12g}"
        if not all(math.isfinite(v) for v in got):
            return Outcome(Verdict.NONFINITE, None, TOLERANCE, detail)
        errors = [float(abs(Fraction(v) - expected) / expected) for v in got]
        exact = all(v == float(expected) for v in got)
        return graded(max(errors), TOLERANCE, detail, exact=exact)

    return Case(
        id=f"refract/depth-{depth}",
        title=f"a ray between two parallel mirrors, remaining = {depth}",
        measure="color relative error (oracle: (depth + 1) x the surface color)",
        tolerance=f"{TOLERANCE:g} relative",
        check=check,
    )


CASES = [*SURFACES, *PICTURES, depth_case(0), depth_case(5), depth_case(100)]
