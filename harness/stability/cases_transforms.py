"""Transform cases (chapters 3, 4, 14): stiff transforms and singular ones.

- stiff: ``scaling(1e-9, 1, 1)``, shears one step from singular, a chain of 1000 rotations.
  The inverse a variant actually uses is read back through ``world_to_object`` (the basis
  vectors give its columns, the origin its translation), so ``cached``'s stored inverse and
  ``numba``'s packed one are measured, not the reference's ``inverse``. It is compared with
  the exact inverse (rationals) by the largest element error over the largest element, and
  judged against what a backward-stable inverse can promise: 64 κ u (κ: the exact
  infinity-norm condition number, u: the variant's unit roundoff).
- singular: a transform with determinant exactly 0 must be refused with a clear error naming
  the object: by ``set_transform``, by the scene loader (file and line), and, when it was
  assigned directly (``s.transform ← m``, bypassing the check), when the shape is rendered,
  not with a ZeroDivisionError deep in a render.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from harness.stability import oracle
from harness.stability.model import Case, Outcome, Probe, Verdict, crashed, expected_error, graded
from harness.stability.scenes import look, world_of
from scene import SceneError, load_scene_text

SAFETY = 64.0  # within tolerance: error <= SAFETY * κ * u


def _rows(m: Any) -> list[list[float]]:
    return [[float(m[r, c]) for c in range(4)] for r in range(4)]


def used_inverse(probe: Probe, m: Any) -> list[list[float]]:
    """The inverse of ``m`` as the variant applies it: columns 0-2 from ``world_to_object``
    of the basis vectors, column 3 from the origin point."""
    api = probe.api
    s = api["sphere"]()
    api["set_transform"](s, m)
    columns = [
        api["world_to_object"](s, api["vector"](1, 0, 0)),
        api["world_to_object"](s, api["vector"](0, 1, 0)),
        api["world_to_object"](s, api["vector"](0, 0, 1)),
        api["world_to_object"](s, api["point"](0, 0, 0)),
    ]
    return [[float(c.x) for c in columns], [float(c.y) for c in columns],
            [float(c.z) for c in columns], [0.0, 0.0, 0.0, 1.0]]  # fmt: skip


def stiff_case(name: str, title: str, build: Callable[[Any], Any]) -> Case:
    def check(probe: Probe) -> Outcome:
        m = build(probe.api)
        rows = _rows(m)
        truth = oracle.exact_inverse(rows)
        if truth is None:
            raise ValueError(f"stiff case {name}: the matrix is singular")
        kappa = oracle.condition_number(rows)
        got = used_inverse(probe, m)
        values = [v for row in got for v in row]
        if not all(math.isfinite(v) for v in values):
            return Outcome(Verdict.NONFINITE, None, None, f"inverse has {values}")
        largest = max(abs(v) for row in truth for v in row)
        error = max(abs(oracle.exact(got[r][c]) - truth[r][c]) for r in range(4) for c in range(4))
        relative = float(error / largest)
        exact = all(got[r][c] == float(truth[r][c]) for r in range(4) for c in range(4))
        tolerance = SAFETY * kappa * probe.unit_roundoff
        detail = (
            f"largest element error {relative:.3g} of the largest element; κ∞ = {kappa:.3g}, "
            f"bound 64 κ u = {tolerance:.3g}"
        )
        return graded(relative, tolerance, detail, exact=exact)

    return Case(
        id=f"stiff/{name}",
        title=title,
        measure="inverse as used (world_to_object): max element error / max element",
        tolerance="64 κ u",
        check=check,
    )


def _flat(api: Any) -> Any:
    return api["scaling"](1e-9, 1, 1)


def _shear(step: float) -> Callable[[Any], Any]:
    def build(api: Any) -> Any:
        return api["shearing"](1, 0, 1 - step, 0, 0, 0)  # determinant `step`

    return build


def _rotations(api: Any) -> Any:
    m = api["identity_matrix"]
    turns = (api["rotation_x"], api["rotation_y"], api["rotation_z"])
    for k in range(1000):
        m = turns[k % 3](0.1 + 0.37 * k) * m
    return api["translation"](3, -2, 5) * m


def _mixed(api: Any) -> Any:
    """Rotations around a near-singular shear and a thin scale."""
    return (
        api["rotation_x"](0.3)
        * api["shearing"](1, 0, 1 - 1e-8, 0, 0, 0)
        * api["rotation_y"](0.7)
        * api["scaling"](1e-3, 1, 1)
    )


STIFF = [
    stiff_case("scaling-1e-9", "scaling(1e-9, 1, 1): a sheet a nanometre thin", _flat),
    stiff_case("shear-1e-8", "shearing(1, 0, 1 - 1e-8, ...): determinant 1e-8", _shear(1e-8)),
    stiff_case("shear-1e-12", "shearing(1, 0, 1 - 1e-12, ...): determinant 1e-12", _shear(1e-12)),
    stiff_case("rotations-1000", "1000 rotations about x, y, z in turn, then a translation",
               _rotations),
    stiff_case("mixed", "rotate-x, shear(1 - 1e-8), rotate-y, scale(1e-3, 1, 1)",
               _mixed),
]  # fmt: skip


# -------------------------------------------------------------------------- singular


def _singular(api: Any) -> Any:
    return api["scaling"](1, 0, 1)


def _set_transform(probe: Probe) -> Outcome:
    api = probe.api
    s = api["sphere"]()
    return expected_error(
        lambda: api["set_transform"](s, _singular(api)), ("sphere",), "the sphere"
    )


SINGULAR_SCENE = """\
- add: camera
  width: 4
  height: 3
  field-of-view: 1.0
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: sphere
  transform:
    - [scale, 1, 0, 1]
"""


def scene_error(probe: Probe, text: str, line: int, what: str) -> Outcome:
    """Loading ``text`` must raise a ``SceneError`` at ``line``."""
    try:
        load_scene_text(text, probe.api, path="case.yml", variant=probe.variant.name)
    except SceneError as error:
        message = " ".join(str(error).split())
        if f"case.yml:{line}:" in str(error):
            return Outcome(Verdict.EXACT, 0.0, None, message)
        return Outcome(
            Verdict.WRONG, None, None, f"error not at line {line}: {message}", "wrong line"
        )
    except Exception as error:  # anything else is not the loader's clear error
        return crashed(error)
    return Outcome(Verdict.WRONG, None, None, f"loaded; expected an error about {what}", "no error")


def _scene_load(probe: Probe) -> Outcome:
    return scene_error(probe, SINGULAR_SCENE, 12, "the singular transform")


def _assigned(probe: Probe) -> Outcome:
    api = probe.api
    s = api["sphere"]()
    s.transform = _singular(api)  # the book's ``s.transform ← m``: no check
    w = world_of(api, [s], (-10, 10, -10))
    c = look(api, (4, 3), (0, 0, -5), (0, 0, 0))
    return expected_error(
        lambda: api["render"](c, w), ("sphere", "objects[0]"), "the sphere (or objects[0])"
    )


SINGULAR = [
    Case("singular/set_transform", "set_transform(sphere, scaling(1, 0, 1))",
         "a clear error naming the sphere", "-", _set_transform),
    Case("singular/scene-file", "a scene file giving a sphere [scale, 1, 0, 1]",
         "a scene error at the transform's line", "-", _scene_load),
    Case("singular/assigned-render", "s.transform ← scaling(1, 0, 1) (no check), then render",
         "a clear error naming the sphere at render", "-", _assigned),
]  # fmt: skip

CASES = [*STIFF, *SINGULAR]
