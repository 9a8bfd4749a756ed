"""Degenerate input (chapters 6-9, 15, and the scene format): what a tracer meets when the
input is at the edge of meaning.

- zero-area triangles (a repeated corner, corners on one line): never hit, never NaN;
- an OBJ model with repeated vertices (duplicate and degenerate faces): the real faces hit
  where the oracle says, the degenerate ones never, the color finite;
- the camera's ``up`` along its view direction: a clear error, in a scene file (its line)
  and through the API (at render, naming the camera);
- a light lying on a surface: nothing shadows the points above it (a shadow ray ending on
  the plane the light lies on must not count that plane as in the way);
- fields of view near 0 and near pi: each pixel's ray direction against the exact one, in
  units of the angle between neighbouring pixels;
- NaN and infinity in a scene file: a clear error at its line.
"""

from __future__ import annotations

import math
import random

import mpmath

from harness.stability import oracle
from harness.stability.cases_rays import compare_hits
from harness.stability.cases_transforms import scene_error
from harness.stability.model import Case, Outcome, Probe, Verdict, expected_error, graded
from harness.stability.scenes import look, with_transform, world_of

# ------------------------------------------------------------------ zero-area triangles

FLAT_TRIANGLES = (
    ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 0.0)),  # a repeated corner
    ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (3.0, 3.0, 3.0)),  # on one line
    ((0.0, 0.0, 0.0), (0.5, 0.25, 0.125), (1.5, 0.75, 0.375)),  # on one line, fractions
)
FLAT_DIRECTIONS = ((0.0, 0.0, 1.0), (0.3, -0.2, 1.0), (1.0, 1.0, 1.0))


def _flat_triangles(probe: Probe) -> Outcome:
    api = probe.api
    seen: list[str] = []
    for corners in FLAT_TRIANGLES:
        tri = api["triangle"](*(api["point"](*p) for p in corners))
        middle = tuple((a + b) / 2 for a, b in zip(corners[0], corners[2], strict=True))
        for d in FLAT_DIRECTIONS:
            origin = tuple(m - 5 * v for m, v in zip(middle, d, strict=True))
            r = api["ray"](api["point"](*origin), api["vector"](*d))
            ts = [float(i.t) for i in api["intersect"](tri, r)]
            truth = oracle.triangle_t(origin, d, corners)  # type: ignore[arg-type]
            if truth:
                raise ValueError(f"zero-area case: the oracle hits {corners}")
            if any(not math.isfinite(t) for t in ts):
                return Outcome(Verdict.NONFINITE, None, 0, f"hit at {ts} on {corners}")
            if ts:
                seen.append(f"{corners} hit at {ts}")
    rays = len(FLAT_TRIANGLES) * len(FLAT_DIRECTIONS)
    if seen:
        return Outcome(Verdict.WRONG, float(len(seen)), 0, f"{len(seen)} of {rays} rays hit: "
                       + "; ".join(seen))  # fmt: skip
    return Outcome(Verdict.EXACT, 0.0, 0, f"none of {rays} rays through them hits")


# --------------------------------------------------------------------- OBJ repeated vertices

VERTICES = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0))
FACES = ((1, 2, 3), (4, 5, 3), (1, 4, 2), (1, 2, 3, 4))  # 1-based; the last is a fan


def _obj_text() -> str:
    lines = [f"v {x:g} {y:g} {z:g}" for x, y, z in VERTICES]
    lines += ["f " + " ".join(str(i) for i in face) for face in FACES]
    return "\n".join(lines) + "\n"


def _fan(face: tuple[int, ...]) -> list[tuple[int, int, int]]:
    """Chapter 15's fan triangulation of a polygon (1-based vertex numbers)."""
    return [(face[0], face[k], face[k + 1]) for k in range(1, len(face) - 1)]


def _obj(probe: Probe) -> Outcome:
    api = probe.api
    group = api["obj_to_group"](api["parse_obj_file"](_obj_text()))
    origin, direction = (0.25, 0.25, -1.0), (0.0, 0.0, 1.0)
    r = api["ray"](api["point"](*origin), api["vector"](*direction))
    got = [float(i.t) for i in api["intersect"](group, r)]
    truth = [
        t
        for face in FACES
        for a, b, c in _fan(face)
        for t in oracle.triangle_t(origin, direction, (VERTICES[a - 1], VERTICES[b - 1],
                                                       VERTICES[c - 1]))
    ]  # fmt: skip
    outcome = compare_hits(got, sorted(truth), 1e-6)
    if outcome.verdict not in (Verdict.EXACT, Verdict.WITHIN):
        return outcome
    w = world_of(api, [group], (-10.0, 10.0, -10.0))
    seen = api["color_at"](w, r, 5)
    channels = (float(seen.red), float(seen.green), float(seen.blue))
    if not all(math.isfinite(v) for v in channels):
        return Outcome(Verdict.NONFINITE, None, outcome.tolerance, f"color {channels}")
    return Outcome(outcome.verdict, outcome.error, outcome.tolerance,
                   f"{outcome.detail}; color {tuple(round(v, 6) for v in channels)}")  # fmt: skip


# ------------------------------------------------------------------------ the camera's up

UP_ALONG_VIEW = """\
- add: camera
  width: 4
  height: 3
  field-of-view: 1.0
  from: [0, 5, 0]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
"""


def _up_scene(probe: Probe) -> Outcome:
    return scene_error(probe, UP_ALONG_VIEW, 7, "the camera's up")


def _up_api(probe: Probe) -> Outcome:
    api = probe.api
    view = api["view_transform"](api["point"](0, 5, 0), api["point"](0, 0, 0),
                                 api["vector"](0, 1, 0))  # fmt: skip
    c = with_transform(api["camera"](4, 3, 1.0), view)
    w = world_of(api, [api["sphere"]()], (-10.0, 10.0, -10.0))
    return expected_error(lambda: api["render"](c, w), ("camera",), "the camera")


# ------------------------------------------------------------------------ light on a surface

LIGHT_ON_FLOOR = (0.3, 0.0, -0.7)
SHADOW_POINTS = 1000


def _light_on_surface(probe: Probe) -> Outcome:
    """Points above a floor plane, lit by a light lying on the floor: nothing lies between
    any of them and the light (the floor touches the light only at its position), so
    ``is_shadowed`` must be false for all; a shadow ray ending on the plane the light lies
    on flickers otherwise."""
    api = probe.api
    w = world_of(api, [api["plane"]()], LIGHT_ON_FLOOR)
    chance = random.Random(7)
    shadowed = 0
    for _ in range(SHADOW_POINTS):
        x, y, z = chance.uniform(-3, 3), chance.uniform(0.1, 3), chance.uniform(-3, 3)
        shadowed += bool(api["is_shadowed"](w, api["point"](x, y, z)))
    detail = f"{shadowed} of {SHADOW_POINTS} points above the floor shadowed (oracle: none)"
    if shadowed:
        return Outcome(Verdict.WRONG, float(shadowed), 0, detail)
    return Outcome(Verdict.EXACT, 0.0, 0, detail)


# ------------------------------------------------------------------------ field of view

FOV_SIZE = (16, 12)


def fov_case(name: str, field_of_view: float, title: str) -> Case:
    def check(probe: Probe) -> Outcome:
        api = probe.api
        c = look(api, FOV_SIZE, (-2.0, 1.0, -4.0), (0.0, 0.5, 0.0), field_of_view)
        rows = [[float(c.transform[r, k]) for k in range(4)] for r in range(4)]
        truth = oracle.camera_directions(*FOV_SIZE, field_of_view, rows)
        worst = 0.0
        with mpmath.workdps(oracle.DIGITS):
            for (px, py), d in truth.items():
                ray = api["ray_for_pixel"](c, px, py)
                got = (ray.direction.x, ray.direction.y, ray.direction.z)
                if not all(math.isfinite(v) for v in got):
                    return Outcome(Verdict.NONFINITE, None, None, f"pixel ({px}, {py}): {got}")
                length = mpmath.sqrt(sum(mpmath.mpf(v) ** 2 for v in got))
                error = mpmath.sqrt(sum((mpmath.mpf(v) / length - e) ** 2
                                        for v, e in zip(got, d, strict=True)))  # fmt: skip
                neighbour = truth[(px + 1, py)] if px + 1 < FOV_SIZE[0] else truth[(px - 1, py)]
                step = mpmath.sqrt(sum((a - b) ** 2 for a, b in zip(d, neighbour, strict=True)))
                worst = max(worst, float(error / step))
        tolerance = 1e-3
        return graded(worst, tolerance, f"largest direction error {worst:.3g} pixel",
                      exact=worst == 0.0)  # fmt: skip

    return Case(
        id=f"degen/{name}",
        title=title,
        measure="ray direction error, in pixels (angle to the neighbouring pixel's ray)",
        tolerance="1e-3 pixel",
        check=check,
    )


# ------------------------------------------------------------------------- NaN in scene files

BAD_NUMBERS = (
    ("at: [.nan, 2, 3]", "NaN"),
    ("at: [-10, .inf, -10]", "infinity"),
    ("at: [1e999, 10, -10]", "an overflowing number"),
)


def _bad_numbers(probe: Probe) -> Outcome:
    for text, what in BAD_NUMBERS:
        scene = UP_ALONG_VIEW.replace("from: [0, 5, 0]", "from: [0, 0, -5]").replace(
            "at: [-10, 10, -10]", text
        )
        outcome = scene_error(probe, scene, 9, what)
        if outcome.verdict is not Verdict.EXACT:
            return outcome
    return Outcome(Verdict.EXACT, 0.0, None, f"{len(BAD_NUMBERS)} scene errors at line 9: "
                   "NaN, infinity, 1e999")  # fmt: skip


CASES = [
    Case("degen/zero-area-triangles", "rays through triangles of zero area (3 kinds, 3 rays)",
         "rays that hit (oracle: none)", "0", _flat_triangles, "rays"),
    Case("degen/obj-repeated-vertices", "an OBJ model whose faces repeat vertices",
         "hits as the oracle's (degenerate faces never), finite color", "1e-6 relative", _obj),
    Case("degen/camera-up-scene", "a scene file whose camera 'up' is along its view",
         "a scene error at the 'up' line", "-", _up_scene),
    Case("degen/camera-up-api", "view_transform with 'up' along the view, then render",
         "a clear error naming the camera", "-", _up_api),
    Case("degen/light-on-surface", "a point light lying on a floor; 1000 points above it",
         "points wrongly in shadow (oracle: none)", "0", _light_on_surface, "points"),
    fov_case("fov-1e-10", 1e-10, "a field of view of 1e-10 radians"),
    fov_case("fov-pi-1e-10", math.pi - 1e-10, "a field of view of pi - 1e-10 radians"),
    Case("degen/scene-nan-inf", "NaN, infinity and 1e999 as a light's position in a scene file",
         "a scene error at the line", "-", _bad_numbers),
]  # fmt: skip
