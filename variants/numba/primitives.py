"""One primitive row per leaf of a flattened scene (chapters 5-15): its composed transform
(chapter 14), its material and pattern (chapters 6, 10, 11), its kind's own parameters
(chapters 12, 13, 15), and the numbers that let the kernels take shortcuts (see their
docstrings for the effect on the picture):

- a world-space bounding sphere, which lets a ray skip the exact test;
- a sphere whose composed transform is a similarity (rotation, uniform scale, translation:
  the reference scene's and the C++ workload's spheres) also gets its world-space centre,
  radius squared and 1 / radius (``SPH_*``, ``WORLD_SPHERE``): the kernels intersect it in
  world space, without the object-space transform; an ellipsoid keeps the transform;
- ``POW_FLOOR``: the cosine below which the specular factor ``cos ** shininess`` is under
  1e-9, so the kernels skip ``pow`` and the term (at most 1e-9 of the light's intensity).

A run of triangles (an OBJ model's group, a group's run of the book's triangles) becomes a
block of rows at once, with NumPy (``Rows.triangles``). ``pack`` arranges the rows into
items.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from raytracer.materials import Material
from raytracer.matrices import Matrix
from raytracer.patterns import Pattern
from raytracer.shapes.shape import Shape
from scene.pattern_kinds import PATTERN_KINDS, PatternKind, names, reference_pattern_kind
from variants.arrays import flatten as F
from variants.arrays.rows import normal_rows, rgb, rows3x4, stretch
from variants.numba import layout as L
from variants.numba.errors import PackError, refusal
from variants.numba.textures import TextureTable


def pattern_kind(pattern: Pattern, where: str) -> PatternKind:
    """The kind of a pattern (``scene.pattern_kinds``); a ``PackError`` for anything else."""
    kind = reference_pattern_kind(pattern)
    if kind is not None:
        return kind
    known = names(PATTERN_KINDS)
    raise PackError(
        f"numba: cannot compile the pattern of {where}, a {type(pattern).__name__}: the "
        f"kernels know the patterns {known}"
    )


def inverse(m: Matrix, what: str) -> Matrix:
    """The reference's inverse of an affine ``m``; a ``PackError`` when it has none."""
    try:
        return F.inverse_affine(m, what)
    except F.FlattenError as error:
        raise refusal(error) from None


SPECULAR_CUTOFF = 1e-9  # the specular factor below which the kernels leave the term out


def _pow_floor(shininess: float) -> float:
    """Chapter 6: the reflect_dot_eye at or below which the specular factor
    ``reflect_dot_eye ** shininess`` is below ``SPECULAR_CUTOFF`` (-inf: never, for a
    shininess that is not a positive finite number)."""
    if not shininess > 0 or not math.isfinite(shininess):
        return -math.inf
    return SPECULAR_CUTOFF ** (1.0 / shininess) * (1.0 - 1e-12)


def _world_sphere(inv: Matrix) -> list[float] | None:
    """Chapter 5: a sphere whose world-to-object transform ``inv`` is a similarity (AᵀA is
    a multiple of the identity, to 1e-12 relative, for its 3x3 part A) is the world-space
    ball |x - centre| = radius: [centre x, y, z, radius², 1 / radius]; None for an
    ellipsoid (the kernels then intersect in object space)."""
    a = [[float(v) for v in row[:3]] for row in inv.rows[:3]]
    b = [float(row[3]) for row in inv.rows[:3]]
    gram = [[sum(a[k][i] * a[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    k = gram[0][0]  # 1 / s² for inv = (1 / s) R (x - centre)
    if not (k > 0 and math.isfinite(k)):
        return None
    scaled = (abs(gram[i][j] - (k if i == j else 0.0)) for i in range(3) for j in range(3))
    if max(scaled) > 1e-12 * k:
        return None
    # a centre + b = 0, and the inverse of a is aᵀ / k
    centre = [-sum(a[r][c] * b[r] for r in range(3)) / k for c in range(3)]
    radius = 1.0 / math.sqrt(k)
    values = [*centre, radius * radius, 1.0 / radius]
    if not all(math.isfinite(v) for v in values):
        return None
    return values


def _bounding_sphere(local: np.ndarray | None, kind: int, fwd: Matrix | None) -> list[float]:
    """A world-space sphere (centre, radius) holding a leaf whose object-space box has the
    corners ``local``; radius inf when it is unbounded (planes, infinite cylinders and
    cones) or its transform is unknown."""
    none = [0.0, 0.0, 0.0, math.inf]
    if local is None or fwd is None:
        return none
    points = [tuple(map(float, p)) for p in local]
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
    # a sphere lies in its unit ball, not only in the corners' hull
    radius = 1.0 if kind == L.K_SPHERE else max(math.dist(centre, p) for p in points)
    world_centre = F.apply(fwd, np.array(centre)).tolist()
    world_radius = radius * stretch(fwd) * (1.0 + 1e-6) + 1e-9
    if not (math.isfinite(world_radius) and all(math.isfinite(v) for v in world_centre)):
        return none
    return [*world_centre, world_radius]


def triangle_spheres(points: np.ndarray, fwd: Matrix) -> np.ndarray:
    """``_bounding_sphere`` of many triangles (points: triangle, corner, axis) at once:
    n x 4 (world centre, radius; radius inf where not finite)."""
    a, b, c = points[:, 0], points[:, 1], points[:, 2]
    lo, hi = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
    centre = (lo + hi) / 2
    radius = np.sqrt(((points - centre[:, None, :]) ** 2).sum(axis=2)).max(axis=1)
    out = np.empty((len(points), 4), dtype=np.float64)
    out[:, 0:3] = F.apply(fwd, centre)
    out[:, 3] = radius * stretch(fwd) * (1.0 + 1e-6) + 1e-9
    bad = ~np.isfinite(out).all(axis=1)
    out[bad] = (0.0, 0.0, 0.0, math.inf)
    return out


class Rows:
    """The primitive rows of a packed world, as single rows (lists) or blocks (arrays: a
    run of triangles, packed at once), with the shape each came from; the compact
    triangles' numbers (``tg``, ``tn``); the texture records the rows' patterns need."""

    def __init__(self, dtype: Any, allow_test_shape: bool) -> None:
        self.dtype = dtype
        self.allow_test_shape = allow_test_shape
        self.tg: list[np.ndarray] = []
        self.tn: list[np.ndarray] = []
        self.n_tg = 0
        self.n_tn = 0
        self.rows_f: list[Any] = []
        self.rows_i: list[Any] = []
        self.n_rows = 0
        self.shapes: list[Shape | None] = []
        self.capacity = 0
        self.textures = TextureTable()

    def row(
        self,
        kind: int,
        inv: Matrix,
        where: str,
        m: Any,
        shadow: bool,
        params: dict[str, Any] | None = None,
        local: np.ndarray | None = None,
        fwd: Matrix | None = None,
        pattern: Pattern | None = None,
    ) -> tuple[list[float], list[int]]:
        """One primitive row (floats, ints): ``kind``, world-to-object ``inv``, material
        ``m`` (``pattern`` in place of its own), its parameters, and for the bounding sphere
        its object-space box corners ``local`` and object-to-world ``fwd`` (None: no
        bounding sphere). A triangle's own numbers are filled in by ``triangles``."""
        if kind == L.K_TEST and not self.allow_test_shape:
            raise PackError(
                f"numba: cannot render {where}, a TestShape: it records rays in Python "
                "(chapter 9's test double), which compiled kernels cannot do"
            )
        if not isinstance(m, Material):
            raise PackError(f"numba: {where} has no material (got {type(m).__name__})")
        f = [0.0] * L.NF
        i = [0] * L.NI
        f[L.INV : L.INV + 12] = rows3x4(inv)
        f[L.NRM : L.NRM + 9] = normal_rows(inv)
        f[L.COLOR : L.COLOR + 3] = rgb(m.color)
        f[L.AMBIENT] = float(m.ambient)
        f[L.DIFFUSE] = float(m.diffuse)
        f[L.SPECULAR] = float(m.specular)
        f[L.SHININESS] = float(m.shininess)
        f[L.POW_FLOOR] = _pow_floor(float(m.shininess))
        f[L.REFLECTIVE] = float(m.reflective)
        f[L.TRANSPARENCY] = float(m.transparency)
        f[L.REFRACTIVE_INDEX] = float(m.refractive_index)
        f[L.EMISSIVE : L.EMISSIVE + 3] = rgb(m.emissive)
        used = pattern if pattern is not None else m.pattern
        if used is not None:
            pattern_kind_ = pattern_kind(used, where)
            i[L.PATTERN] = pattern_kind_.number
            pattern_inv = inverse(used.transform, f"the pattern transform of {where}")
            f[L.PAT : L.PAT + 12] = rows3x4(pattern_inv)
            if pattern_kind_.texture:
                i[L.PAT_TEX] = self.textures.pattern(used, where)
            elif pattern_kind_.two_colors:
                f[L.PAT_A : L.PAT_A + 3] = rgb(used.a)  # type: ignore[attr-defined]
                f[L.PAT_B : L.PAT_B + 3] = rgb(used.b)  # type: ignore[attr-defined]
        i[L.KIND] = kind
        i[L.CASTS_SHADOW] = 1 if shadow else 0
        i[L.TRI_FIRST] = -1  # a primitive of its own, not a run of compact triangles
        i[L.TN_FIRST] = -1
        numbers = [v for v in (params or {}).values() if not isinstance(v, bool)]
        flags = [v for v in (params or {}).values() if isinstance(v, bool)]
        f[L.PARAMS : L.PARAMS + len(numbers)] = [float(v) for v in numbers]  # table order
        if flags:
            i[L.CLOSED] = 1 if flags[0] else 0
        f[L.BOUND : L.BOUND + 4] = _bounding_sphere(local, kind, fwd)
        ball = _world_sphere(inv) if kind == L.K_SPHERE else None
        if ball is not None:
            f[L.SPH_CENTER : L.SPH_INV_R + 1] = ball
            i[L.WORLD_SPHERE] = 1
        return f, i

    def leaf_rows(
        self, leaf: F.Leaf, pattern: Pattern | None = None, bound: bool = True
    ) -> tuple[int, np.ndarray]:
        """Append a leaf's row; returns (its index, its world box). ``bound=False``: no
        bounding sphere and no box (a surface packed alone, for the book's API)."""
        local = leaf.local_corners() if bound else None
        f, i = self.row(
            leaf.kind.number, leaf.inv, leaf.where, leaf.material, leaf.shadow, dict(leaf.params),
            local, leaf.fwd if bound else None, pattern,
        )  # fmt: skip
        self.rows_f.append(f)
        self.rows_i.append(i)
        self.shapes.append(leaf.source)
        self.capacity += leaf.kind.max_hits
        self.n_rows += 1
        return self.n_rows - 1, F.leaf_box(leaf) if bound else np.full(6, np.nan)

    def triangles(self, run: F.Triangles, pattern: Pattern | None = None) -> np.ndarray:
        """Chapter 15, at scale: a run of triangles as one block of rows, built with numpy:
        the same rows ``row`` would make one at a time (``pattern``: in place of their
        material's). Returns their world boxes (n, 6)."""
        n = run.count
        kind = run.kind.number
        # one template row per (material, casts_shadow)
        key = run.material_of * 2 + run.shadow.astype(np.int64)
        _, first, which = np.unique(key, return_index=True, return_inverse=True)
        rows_f: list[list[float]] = []
        rows_i: list[list[int]] = []
        for j in first.tolist():
            material = run.materials[int(run.material_of[j])]
            f, i = self.row(kind, run.inv, f"{run.where} (its triangle {j})", material,
                            bool(run.shadow[j]), pattern=pattern)  # fmt: skip
            rows_f.append(f)
            rows_i.append(i)
        pf = np.array(rows_f, dtype=np.float64)[which.reshape(-1)]
        pi = np.array(rows_i, dtype=np.int64)[which.reshape(-1)]
        tg, bounds = run.geometry()
        pf[:, L.TRI_P1 : L.TRI_P1 + 3] = tg[:, L.TG_P1 : L.TG_P1 + 3]
        pf[:, L.TRI_E1 : L.TRI_E1 + 3] = tg[:, L.TG_E1 : L.TG_E1 + 3]
        pf[:, L.TRI_E2 : L.TRI_E2 + 3] = tg[:, L.TG_E2 : L.TG_E2 + 3]
        pf[:, L.TRI_NORMAL : L.TRI_NORMAL + 3] = tg[:, L.TG_NORMAL : L.TG_NORMAL + 3]
        normals = run.normals()
        if normals is not None:
            pf[:, L.TRI_N1 : L.TRI_N3 + 3] = normals.reshape(n, 9)
        pf[:, L.BOUND : L.BOUND + 4] = triangle_spheres(run.corners(), run.fwd)
        self.rows_f.append(pf)
        self.rows_i.append(pi)
        self.shapes.extend(run.sources if run.sources is not None else [None] * n)
        self.n_rows += n
        self.capacity += n * run.kind.max_hits
        return bounds
