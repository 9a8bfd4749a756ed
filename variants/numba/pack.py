"""Packing a world, a shape or a camera into the flat arrays the kernels read (``layout``).

A world is packed once per render: every leaf shape becomes one row of ``pf``/``pi`` with
its transform composed through its groups and CSG parents (chapter 14), its material and
its pattern (chapters 6, 10, 11) and its own parameters (chapters 12, 13, 15); CSG trees
become a range of rows plus their operations in post-order (chapter 16). How the items are
arranged is the ``bvh`` option (``variants.numba.bvh``): by default the groups are
flattened and a bounding-volume hierarchy is built over the items with a box (``sah``);
``groups`` keeps each group's box as an item the ray can skip (chapter 14); ``off`` none.
Every light is packed (one row each).

A group's run of plain triangles (a mesh: ``Triangle`` or ``SmoothTriangle`` with no
transform of their own) is packed at once with numpy (``add_triangles``): the rows
``leaf_row`` would make one at a time, about ten times faster (a million triangles in
seconds, not a minute).

Only the reference's own shape and pattern classes are packed (or subclasses that do not
change how they intersect, shade or color); anything else is refused with a ``PackError``
naming the object, never approximated. Inverses are the reference's ``inverse`` (cofactor
expansion), so the kernels start from the very numbers the reference uses.

Two precomputed values let the kernels take shortcuts (see their docstrings for the
effect on the picture):

- a sphere whose composed transform is a similarity (rotation, uniform scale, translation:
  the reference scene's and the C++ workload's spheres) also gets its world-space centre,
  radius squared and 1 / radius (``SPH_*``, ``WORLD_SPHERE``): the kernels intersect it in
  world space, without the object-space transform; an ellipsoid keeps the transform;
- ``POW_FLOOR``: the cosine below which the specular factor ``cos ** shininess`` is under
  1e-9, so the kernels skip ``pow`` and the term (at most 1e-9 of the light's intensity).
"""

from __future__ import annotations

import itertools
import math
import operator
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from raytracer.camera import Camera
from raytracer.colors import Color
from raytracer.lights import Light
from raytracer.materials import Material
from raytracer.matrices import Matrix, identity_matrix, inverse
from raytracer.patterns import (
    CheckersPattern,
    GradientPattern,
    Pattern,
    RingPattern,
    StripePattern,
    TestPattern,
)
from raytracer.shapes.cone import Cone
from raytracer.shapes.csg import CSG
from raytracer.shapes.cube import Cube
from raytracer.shapes.cylinder import Cylinder
from raytracer.shapes.group import Group
from raytracer.shapes.plane import Plane
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.test_shape import TestShape
from raytracer.shapes.triangle import Triangle
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.kinds import PATTERN_METHODS, SHAPE_METHODS, reference_kind, unchanged
from variants.numba import layout as L
from variants.numba.bvh import BALLS_MAX, DEFAULT, STRUCTURES, Hierarchy, build_tree
from variants.numba.lights import light_rows
from variants.numba.textures import TextureTable, texture_kind

# leaf classes, most derived first (a smooth triangle is a triangle)
SHAPE_KINDS: tuple[tuple[type[Shape], int], ...] = (
    (SmoothTriangle, L.K_SMOOTH_TRIANGLE),
    (Triangle, L.K_TRIANGLE),
    (Sphere, L.K_SPHERE),
    (Plane, L.K_PLANE),
    (Cube, L.K_CUBE),
    (Cylinder, L.K_CYLINDER),
    (Cone, L.K_CONE),
    (TestShape, L.K_TEST),
)
PATTERN_KINDS: tuple[tuple[type[Pattern], int], ...] = (
    (StripePattern, L.P_STRIPE),
    (GradientPattern, L.P_GRADIENT),
    (RingPattern, L.P_RING),
    (CheckersPattern, L.P_CHECKERS),
    (TestPattern, L.P_TEST),
)
KIND_NAMES = {
    L.K_SPHERE: "sphere",
    L.K_PLANE: "plane",
    L.K_CUBE: "cube",
    L.K_CYLINDER: "cylinder",
    L.K_CONE: "cone",
    L.K_TRIANGLE: "triangle",
    L.K_SMOOTH_TRIANGLE: "smooth_triangle",
    L.K_TEST: "test_shape",
}
PATTERN_NAMES = {
    L.P_STRIPE: "stripe",
    L.P_GRADIENT: "gradient",
    L.P_RING: "ring",
    L.P_CHECKERS: "checkers",
    L.P_TEST: "test_pattern",
    L.P_MAP: "texture_map",
    L.P_CUBE_MAP: "cube_map",
}
# how many intersections one primitive can give at most
MAX_HITS = {
    L.K_SPHERE: 2,
    L.K_PLANE: 1,
    L.K_CUBE: 2,
    L.K_CYLINDER: 4,
    L.K_CONE: 4,
    L.K_TRIANGLE: 1,
    L.K_SMOOTH_TRIANGLE: 1,
    L.K_TEST: 0,
}
OPERATIONS = {"union": L.OP_UNION, "intersection": L.OP_INTERSECTION, "difference": L.OP_DIFFERENCE}
UNBOUNDED = None

Box = tuple[tuple[float, float, float], tuple[float, float, float]] | None


class PackError(ValueError):
    """Something the numba kernels cannot compile; the message names the object."""


def shape_kind(shape: Shape, where: str) -> int:
    """The kernel kind of a leaf shape; a ``PackError`` for anything the kernels do not know."""
    kind, changed = reference_kind(shape, SHAPE_KINDS, SHAPE_METHODS)
    if kind is not None:
        return kind
    if changed is not None:
        raise PackError(
            f"numba: cannot compile {where}, a {type(shape).__name__}: it changes how a "
            f"{changed.__name__} intersects or computes normals, and the kernels only know "
            "the reference's"
        )
    known = ", ".join(sorted(KIND_NAMES.values())) + ", group, csg"
    raise PackError(
        f"numba: cannot compile {where}, a {type(shape).__name__}: the kernels know {known}"
    )


def pattern_kind(pattern: Pattern, where: str) -> int:
    """The kernel kind of a pattern; a ``PackError`` for anything else."""
    texture = texture_kind(pattern)
    if texture is not None:
        return texture
    kind, _ = reference_kind(pattern, PATTERN_KINDS, PATTERN_METHODS)
    if kind is not None:
        return kind
    known = ", ".join(PATTERN_NAMES.values())
    raise PackError(
        f"numba: cannot compile the pattern of {where}, a {type(pattern).__name__}: the "
        f"kernels know the patterns {known}"
    )


def _affine(m: Matrix, what: str) -> Matrix:
    """``m`` if it is a 4x4 affine matrix (bottom row 0 0 0 1), else a ``PackError``."""
    if not isinstance(m, Matrix) or m.size != 4:
        raise PackError(f"numba: {what} is not a 4x4 matrix")
    if tuple(m.rows[3]) != (0.0, 0.0, 0.0, 1.0):
        raise PackError(
            f"numba: {what} is not affine (its bottom row is {list(m.rows[3])}, not "
            "[0, 0, 0, 1]); the kernels only apply affine transforms"
        )
    return m


def _inverse(m: Matrix, what: str) -> Matrix:
    """The reference's inverse of an affine ``m``; a ``PackError`` when it has none."""
    _affine(m, what)
    if m == identity_matrix:
        return identity_matrix
    try:
        return inverse(m)
    except ValueError:
        raise PackError(f"numba: {what} is not invertible (determinant 0)") from None


def _compose(a: Matrix, b: Matrix) -> Matrix:
    """``a * b``, skipping identities (so a shape outside groups keeps its exact inverse)."""
    if b is identity_matrix or b == identity_matrix:
        return a
    if a is identity_matrix or a == identity_matrix:
        return b
    return a * b


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


def _rows3x4(m: Matrix) -> list[float]:
    return [float(v) for row in m.rows[:3] for v in row]


def _normal_rows(inv: Matrix) -> list[float]:
    """Rows 0-2 of the inverse transpose (3x3): element (r, c) is inv[c][r]."""
    return [float(inv.rows[c][r]) for r in range(3) for c in range(3)]


def _xyz(t: Tuple) -> list[float]:
    return [float(t.x), float(t.y), float(t.z)]


def _rgb(c: Color) -> list[float]:
    return [float(c.red), float(c.green), float(c.blue)]


def _box_of_points(points: list[tuple[float, float, float]]) -> Box:
    if any(not math.isfinite(v) for p in points for v in p):
        return UNBOUNDED
    lo = tuple(min(p[k] for p in points) for k in range(3))
    hi = tuple(max(p[k] for p in points) for k in range(3))
    pad = [1e-9 * (1.0 + abs(lo[k]) + abs(hi[k])) for k in range(3)]
    return (
        (lo[0] - pad[0], lo[1] - pad[1], lo[2] - pad[2]),
        (hi[0] + pad[0], hi[1] + pad[1], hi[2] + pad[2]),
    )


def _apply(m: Matrix, x: float, y: float, z: float) -> tuple[float, float, float]:
    r = m.rows
    return (
        r[0][0] * x + r[0][1] * y + r[0][2] * z + r[0][3],
        r[1][0] * x + r[1][1] * y + r[1][2] * z + r[1][3],
        r[2][0] * x + r[2][1] * y + r[2][2] * z + r[2][3],
    )


def _union(boxes: list[Box]) -> Box:
    if not boxes or any(b is None for b in boxes):
        return UNBOUNDED
    real = [b for b in boxes if b is not None]
    return (
        (
            min(b[0][0] for b in real),
            min(b[0][1] for b in real),
            min(b[0][2] for b in real),
        ),
        (
            max(b[1][0] for b in real),
            max(b[1][1] for b in real),
            max(b[1][2] for b in real),
        ),
    )


def _bounding_sphere(shape: Shape, kind: int, fwd: Matrix | None) -> list[float]:
    """A world-space sphere (centre, radius) that holds the shape; radius inf when it is
    unbounded (planes, infinite cylinders and cones) or its transform is unknown."""
    none = [0.0, 0.0, 0.0, math.inf]
    points = _local_bounds(shape, kind)
    if points is None or fwd is None:
        return none
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
    # a sphere lies in its unit ball, not only in the corners' hull
    radius = 1.0 if kind == L.K_SPHERE else max(math.dist(centre, p) for p in points)
    world_centre = _apply(fwd, *centre)
    world_radius = radius * _stretch(fwd) * (1.0 + 1e-6) + 1e-9
    if not (math.isfinite(world_radius) and all(math.isfinite(v) for v in world_centre)):
        return none
    return [*world_centre, world_radius]


def _stretch(m: Matrix) -> float:
    """An upper bound of how much the 3x3 part A of ``m`` can lengthen a vector: the square
    root of the largest row sum of |AᵀA| (Gershgorin; exact for a rotation times a scale
    along the axes). Plain Python: a numpy call here would wake BLAS threads, which then
    spin beside the render's threads."""
    a = [row[:3] for row in m.rows[:3]]
    gram = [[sum(a[k][i] * a[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return math.sqrt(max(sum(abs(v) for v in row) for row in gram))


def _local_bounds(shape: Shape, kind: int) -> list[tuple[float, float, float]] | None:
    """Points whose hull holds the shape in object space; None when it is unbounded."""
    if kind in (L.K_SPHERE, L.K_CUBE, L.K_TEST):  # the test shape's box is the unit cube's
        lo_y, hi_y, radius = -1.0, 1.0, 1.0
    elif kind in (L.K_CYLINDER, L.K_CONE):
        lo_y, hi_y = float(shape.minimum), float(shape.maximum)  # type: ignore[attr-defined]
        if not (math.isfinite(lo_y) and math.isfinite(hi_y)):
            return None
        radius = 1.0 if kind == L.K_CYLINDER else max(abs(lo_y), abs(hi_y))
    elif kind in (L.K_TRIANGLE, L.K_SMOOTH_TRIANGLE):
        corners = (shape.p1, shape.p2, shape.p3)  # type: ignore[attr-defined]
        return [(float(p.x), float(p.y), float(p.z)) for p in corners]
    else:
        return None
    return [(x, y, z) for x in (-radius, radius) for y in (lo_y, hi_y) for z in (-radius, radius)]


@dataclass
class Packed:
    """A packed world or shape: the arrays (see ``layout``) and what they came from.

    shapes: the leaf shape of each primitive row; capacity: the most intersections a ray
    can have with everything packed; cs_size, cs_prims: the largest CSG tree's intersection
    list and primitive count (per-thread scratch sizes, at least 1); hierarchy: how the
    items are arranged (``bvh``).
    """

    pf: np.ndarray
    pi: np.ndarray
    items: np.ndarray
    boxes: np.ndarray
    csg: np.ndarray
    lights: np.ndarray
    shapes: list[Shape]
    capacity: int
    cs_size: int
    cs_prims: int
    balls: np.ndarray = field(default_factory=lambda: np.zeros((L.NBALL, 0)), repr=False)
    hierarchy: Hierarchy = field(default_factory=lambda: Hierarchy("off"))
    seconds: float = 0.0  # the time packing took, the hierarchy's build included
    textures: TextureTable = field(default_factory=TextureTable, repr=False)
    light_values: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    _rows_by_id: dict[int, int] | None = field(default=None, repr=False)
    _texture_arrays: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)

    def row_of(self, shape: Shape) -> int:
        """The primitive row of ``shape`` (by identity), or -1."""
        if self._rows_by_id is None:
            self._rows_by_id = {id(shape): row for row, shape in enumerate(self.shapes)}
        return self._rows_by_id.get(id(shape), -1)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """(pf, pi, items, boxes, csg): the tables (2-D, one row per primitive, item ...)."""
        return self.pf, self.pi, self.items, self.boxes, self.csg

    def flat(self) -> tuple[Any, ...]:
        """(pf, pi, items, n_items, boxes, csg, balls, n_balls): the tables flattened
        (row-major; ``layout``) and the counts, as the kernels take a world."""
        return (
            _flat(self.pf), _flat(self.pi), _flat(self.items), len(self.items),
            _flat(self.boxes), _flat(self.csg), _flat(self.balls), self.balls.shape[1],
        )  # fmt: skip

    def light_table(self) -> tuple[np.ndarray, int]:
        """(lights, n_lights): the lights flattened (``layout``), their sequences' values
        after them, and their number."""
        rows = np.ascontiguousarray(self.lights).reshape(-1)
        table = np.concatenate([rows, self.light_values.astype(rows.dtype, copy=False)])
        return (table if table.size else np.zeros(1, dtype=rows.dtype)), len(self.lights)

    def texture_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(ti, tf): the texture patterns' records (``layout``, ``textures``), in the
        primitives' precision."""
        if self._texture_arrays is None:
            self._texture_arrays = self.textures.arrays(self.pf.dtype)
        return self._texture_arrays


def _flat(table: np.ndarray) -> np.ndarray:
    """A table as the 1-D, C-contiguous array the kernels index (at least one element, so
    that a pointer to it is valid)."""
    flat = np.ascontiguousarray(table).reshape(-1)
    return flat if flat.size else np.zeros(1, dtype=table.dtype)


def _stack(parts: list[Any], width: int, dtype: Any) -> np.ndarray:
    """Rows (lists) and blocks (2-D arrays) as one table, in order."""
    blocks: list[np.ndarray] = []
    pending: list[Any] = []
    for part in parts:
        if isinstance(part, np.ndarray):
            if pending:
                blocks.append(np.array(pending, dtype=dtype).reshape(len(pending), width))
                pending = []
            blocks.append(part.astype(dtype, copy=False))
        else:
            pending.append(part)
    if pending:
        blocks.append(np.array(pending, dtype=dtype).reshape(len(pending), width))
    if not blocks:
        return np.zeros((0, width), dtype=dtype)
    return blocks[0] if len(blocks) == 1 else np.concatenate(blocks)


def _outward(boxes: np.ndarray, dtype: Any) -> np.ndarray:
    """Boxes (lo x, y, z, hi x, y, z) in ``dtype``, rounded outwards (float32 would
    otherwise shrink a box by up to half a unit in the last place, and lose hits)."""
    if np.dtype(dtype) == boxes.dtype:
        return boxes
    rounded = boxes.astype(dtype)
    lo, hi = rounded[:, 0:3], rounded[:, 3:6]
    with np.errstate(invalid="ignore"):
        low = lo.astype(boxes.dtype) > boxes[:, 0:3]
        high = hi.astype(boxes.dtype) < boxes[:, 3:6]
    lo[low] = np.nextafter(lo[low], np.array(-np.inf, dtype=dtype))
    hi[high] = np.nextafter(hi[high], np.array(np.inf, dtype=dtype))
    return rounded


NO_BOX = (math.nan,) * 6  # an item's bounds when it has none (unbounded, or not a leaf)
FAST_TRIANGLES: dict[type, int] = {Triangle: L.K_TRIANGLE, SmoothTriangle: L.K_SMOOTH_TRIANGLE}
_TRANSFORM = operator.attrgetter("transform")
_MATERIAL = operator.attrgetter("material")
_CASTS_SHADOW = operator.attrgetter("casts_shadow")
_CORNERS = operator.attrgetter(
    *[f"{corner}.{axis}" for corner in ("p1", "p2", "p3", "e1", "e2", "normal") for axis in "xyz"]
)
_NORMALS = operator.attrgetter(*[f"{n}.{axis}" for n in ("n1", "n2", "n3") for axis in "xyz"])


class _Packer:
    """Collects rows and items while walking shapes, then builds the arrays.

    Rows and items are kept as single rows (lists) or as blocks (arrays: a group's run of
    triangles, packed at once); ``bounds`` holds, per item, a box item's box or a leaf
    item's world-space box (NaN: none)."""

    def __init__(
        self, dtype: Any, allow_test_shape: bool, structure: str = DEFAULT, every_box: bool = False
    ) -> None:
        if structure not in STRUCTURES:
            raise ValueError(f"numba: unknown bvh structure {structure!r}: {STRUCTURES}")
        self.dtype = dtype
        self.allow_test_shape = allow_test_shape
        self.structure = structure
        self.every_box = every_box
        self.rows_f: list[Any] = []
        self.rows_i: list[Any] = []
        self.n_rows = 0
        self.items: list[Any] = []
        self.bounds: list[Any] = []
        self.n_items = 0
        self.csg: list[list[int]] = []
        self.shapes: list[Shape] = []
        self.capacity = 0
        self.cs_size = 1
        self.cs_prims = 1
        self.textures = TextureTable()

    # -- rows

    def row(
        self,
        shape: Shape,
        kind: int,
        inv: Matrix,
        where: str,
        material: Material | None = None,
        pattern: Pattern | None = None,
        fwd: Matrix | None = None,
    ) -> tuple[list[float], list[int]]:
        """One primitive row (floats, ints). ``fwd``: object to world space (for the
        bounding sphere; None: no bounding sphere)."""
        if kind == L.K_TEST and not self.allow_test_shape:
            raise PackError(
                f"numba: cannot render {where}, a TestShape: it records rays in Python "
                "(chapter 9's test double), which compiled kernels cannot do"
            )
        m = shape.material if material is None else material
        if not isinstance(m, Material):
            raise PackError(f"numba: {where} has no material (got {type(m).__name__})")
        f = [0.0] * L.NF
        i = [0] * L.NI
        f[L.INV : L.INV + 12] = _rows3x4(inv)
        f[L.NRM : L.NRM + 9] = _normal_rows(inv)
        f[L.COLOR : L.COLOR + 3] = _rgb(m.color)
        f[L.AMBIENT] = float(m.ambient)
        f[L.DIFFUSE] = float(m.diffuse)
        f[L.SPECULAR] = float(m.specular)
        f[L.SHININESS] = float(m.shininess)
        f[L.POW_FLOOR] = _pow_floor(float(m.shininess))
        f[L.REFLECTIVE] = float(m.reflective)
        f[L.TRANSPARENCY] = float(m.transparency)
        f[L.REFRACTIVE_INDEX] = float(m.refractive_index)
        used = pattern if pattern is not None else m.pattern
        if used is not None:
            i[L.PATTERN] = pattern_kind(used, where)
            pattern_inv = _inverse(used.transform, f"the pattern transform of {where}")
            f[L.PAT : L.PAT + 12] = _rows3x4(pattern_inv)
            if i[L.PATTERN] in (L.P_MAP, L.P_CUBE_MAP):
                i[L.PAT_TEX] = self.textures.pattern(used, where)
            elif i[L.PATTERN] != L.P_TEST:
                f[L.PAT_A : L.PAT_A + 3] = _rgb(used.a)  # type: ignore[attr-defined]
                f[L.PAT_B : L.PAT_B + 3] = _rgb(used.b)  # type: ignore[attr-defined]
        i[L.KIND] = kind
        i[L.CASTS_SHADOW] = 1 if getattr(shape, "casts_shadow", True) else 0
        if kind in (L.K_CYLINDER, L.K_CONE):
            f[L.MINIMUM] = float(shape.minimum)  # type: ignore[attr-defined]
            f[L.MAXIMUM] = float(shape.maximum)  # type: ignore[attr-defined]
            i[L.CLOSED] = 1 if shape.closed else 0  # type: ignore[attr-defined]
        if kind in (L.K_TRIANGLE, L.K_SMOOTH_TRIANGLE):
            t: Any = shape
            f[L.TRI_P1 : L.TRI_P1 + 3] = _xyz(t.p1)
            f[L.TRI_E1 : L.TRI_E1 + 3] = _xyz(t.e1)
            f[L.TRI_E2 : L.TRI_E2 + 3] = _xyz(t.e2)
            f[L.TRI_NORMAL : L.TRI_NORMAL + 3] = _xyz(t.normal)
            if kind == L.K_SMOOTH_TRIANGLE:
                f[L.TRI_N1 : L.TRI_N1 + 3] = _xyz(t.n1)
                f[L.TRI_N2 : L.TRI_N2 + 3] = _xyz(t.n2)
                f[L.TRI_N3 : L.TRI_N3 + 3] = _xyz(t.n3)
        f[L.BOUND : L.BOUND + 4] = _bounding_sphere(shape, kind, fwd)
        ball = _world_sphere(inv) if kind == L.K_SPHERE else None
        if ball is not None:
            f[L.SPH_CENTER : L.SPH_INV_R + 1] = ball
            i[L.WORLD_SPHERE] = 1
        return f, i

    def leaf_row(
        self,
        shape: Shape,
        kind: int,
        inv: Matrix,
        where: str,
        material: Material | None = None,
        pattern: Pattern | None = None,
        fwd: Matrix | None = None,
    ) -> int:
        """Append one primitive row (``row``); returns its index."""
        f, i = self.row(shape, kind, inv, where, material, pattern, fwd)
        self.rows_f.append(f)
        self.rows_i.append(i)
        self.shapes.append(shape)
        self.capacity += MAX_HITS[kind]
        self.n_rows += 1
        return self.n_rows - 1

    def item(self, values: list[int], bounds: Box) -> int:
        """Append one item with its bounds; returns its index in ``items``."""
        self.items.append(values)
        self.bounds.append(NO_BOX if bounds is None else (*bounds[0], *bounds[1]))
        self.n_items += 1
        return len(self.items) - 1

    # -- trees

    def add(
        self, shape: Shape, parent_inv: Matrix, parent_fwd: Matrix, where: str, own: bool = True
    ) -> Box:
        """Add a shape (leaf, group or CSG) as items; returns its world-space box.
        ``own=False`` leaves out the shape's own transform (``local_intersect``)."""
        if own:
            m = _affine(shape.transform, f"the transform of {where}")
            inv = _compose(_inverse(m, f"the transform of {where}"), parent_inv)
            fwd = _compose(parent_fwd, m)
        else:
            inv, fwd = parent_inv, parent_fwd
        if isinstance(shape, Group) and unchanged(type(shape), Group, SHAPE_METHODS):
            return self.add_group(shape, inv, fwd, where)
        if isinstance(shape, CSG) and unchanged(type(shape), CSG, SHAPE_METHODS):
            return self.add_csg(shape, inv, fwd, where)
        kind = shape_kind(shape, where)
        row = self.leaf_row(shape, kind, inv, where, fwd=fwd)
        box = self.world_box(shape, kind, fwd)
        self.item([L.I_PRIM, row, 0, 0, 0], box)
        return box

    def world_box(self, shape: Shape, kind: int, fwd: Matrix) -> Box:
        points = _local_bounds(shape, kind)
        if points is None:
            return UNBOUNDED
        return _box_of_points([_apply(fwd, *p) for p in points])

    def open_box(self) -> tuple[int, int]:
        """A box item (``groups``), filled in by ``close_box``: (its index in ``items``,
        its item number); (-1, -1) when the structure has no group boxes."""
        if self.structure != "groups":
            return -1, -1
        return self.item([L.I_BOX, 0, 0, 0, 0], UNBOUNDED), self.n_items - 1

    def close_box(self, opened: tuple[int, int], box: Box) -> None:
        """Fill in the box item ``opened`` (skip to here); drop it when it is useless."""
        at, number = opened
        if at < 0:
            return
        inside = self.n_items - number - 1
        if box is None or inside < (1 if self.every_box else 2):
            self.items[at] = [L.I_SKIP, 0, 0, 0, 0]
            return
        self.items[at][L.ITEM_A] = self.n_items
        self.bounds[at] = (*box[0], *box[1])

    def add_group(self, g: Group, inv: Matrix, fwd: Matrix, where: str) -> Box:
        opened = self.open_box()
        boxes: list[Box] = []
        children = g.children
        # runs of plain triangles of one class with no transform of their own are packed
        # at once (a mesh); -1: any other child
        kinds = [
            FAST_TRIANGLES.get(cls, -1) if m is identity_matrix or m == identity_matrix else -1
            for cls, m in zip(map(type, children), map(_TRANSFORM, children), strict=True)
        ]
        start = 0
        for k in range(len(children) + 1):
            if k < len(children) and kinds[k] >= 0 and kinds[k] == kinds[start]:
                continue
            if start < k and kinds[start] >= 0:
                boxes.append(self.add_triangles(children, start, k, kinds[start], inv, fwd, where))
                start = k
            if k < len(children) and kinds[k] < 0:
                boxes.append(self.add(children[k], inv, fwd, f"{where}.children[{k}]"))
                start = k + 1
        box = _union(boxes)
        self.close_box(opened, box)
        return box

    def add_triangles(
        self,
        children: list[Shape],
        start: int,
        stop: int,
        kind: int,
        inv: Matrix,
        fwd: Matrix,
        where: str,
    ) -> Box:
        """Chapter 15, at scale: a group's children ``start`` to ``stop`` - 1, triangles of
        one ``kind`` with the identity as their own transform, packed as one block of rows
        and items: the same rows as ``leaf_row`` makes one at a time, built with numpy."""
        run = children[start:stop]
        n = len(run)
        # one template row per (material, casts_shadow): the first triangle's
        ids = np.fromiter(map(id, map(_MATERIAL, run)), dtype=np.int64, count=n)
        shadows = np.fromiter(map(bool, map(_CASTS_SHADOW, run)), dtype=np.int64, count=n)
        _, first, which = np.unique(ids * 2 + shadows, return_index=True, return_inverse=True)
        rows_f: list[list[float]] = []
        rows_i: list[list[int]] = []
        for j in first.tolist():
            f, i = self.row(run[j], kind, inv, f"{where}.children[{start + j}]")
            rows_f.append(f)
            rows_i.append(i)
        pf = np.array(rows_f, dtype=np.float64)[which.reshape(-1)]
        pi = np.array(rows_i, dtype=np.int64)[which.reshape(-1)]
        c = np.fromiter(
            itertools.chain.from_iterable(map(_CORNERS, run)), dtype=np.float64, count=n * 18
        ).reshape(n, 18)
        pf[:, L.TRI_P1 : L.TRI_P1 + 3] = c[:, 0:3]
        pf[:, L.TRI_E1 : L.TRI_E1 + 3] = c[:, 9:12]
        pf[:, L.TRI_E2 : L.TRI_E2 + 3] = c[:, 12:15]
        pf[:, L.TRI_NORMAL : L.TRI_NORMAL + 3] = c[:, 15:18]
        if kind == L.K_SMOOTH_TRIANGLE:
            pf[:, L.TRI_N1 : L.TRI_N3 + 3] = np.fromiter(
                itertools.chain.from_iterable(map(_NORMALS, run)), dtype=np.float64, count=n * 9
            ).reshape(n, 9)
        points = c[:, 0:9].reshape(n, 3, 3)  # triangle, corner, axis
        pf[:, L.BOUND : L.BOUND + 4] = _triangle_spheres(points, fwd)
        world = _apply_array(fwd, points)
        lo, hi = _corner_range(world)
        pad = 1e-9 * (1.0 + np.abs(lo) + np.abs(hi))
        bounds = np.concatenate([lo - pad, hi + pad], axis=1)
        bounds[~np.isfinite(bounds).all(axis=1)] = math.nan
        first_row = self.n_rows
        items = np.zeros((n, L.NITEM), dtype=np.int64)
        items[:, L.ITEM_TYPE] = L.I_PRIM
        items[:, L.ITEM_A] = np.arange(first_row, first_row + n)
        self.rows_f.append(pf)
        self.rows_i.append(pi)
        self.shapes.extend(run)
        self.n_rows += n
        self.capacity += n * MAX_HITS[kind]
        self.items.append(items)
        self.bounds.append(bounds)
        self.n_items += n
        if np.isnan(bounds).any():
            return UNBOUNDED
        box_lo, box_hi = bounds[:, 0:3].min(axis=0), bounds[:, 3:6].max(axis=0)
        return (
            (float(box_lo[0]), float(box_lo[1]), float(box_lo[2])),
            (float(box_hi[0]), float(box_hi[1]), float(box_hi[2])),
        )

    def add_csg(self, c: CSG, inv: Matrix, fwd: Matrix, where: str) -> Box:
        opened = self.open_box()
        item = self.item([L.I_CSG, len(self.csg), 0, self.n_rows, 0], UNBOUNDED)
        capacity_before = self.capacity
        box = self.csg_tree(c, inv, fwd, where)
        self.items[item][L.ITEM_B] = len(self.csg)
        self.items[item][L.ITEM_D] = self.n_rows
        self.bounds[item] = NO_BOX if box is None else (*box[0], *box[1])
        self.cs_size = max(self.cs_size, self.capacity - capacity_before)
        self.cs_prims = max(self.cs_prims, self.n_rows - self.items[item][L.ITEM_C])
        self.close_box(opened, box)
        return box

    def csg_tree(self, shape: Shape, inv: Matrix, fwd: Matrix, where: str) -> Box:
        """A CSG operand's rows (and operations, post-order); inv/fwd include ``shape``."""
        if isinstance(shape, CSG) and unchanged(type(shape), CSG, SHAPE_METHODS):
            if shape.operation not in OPERATIONS:
                raise PackError(f"numba: {where} has an unknown operation {shape.operation!r}")
            start = self.n_rows
            left = self.csg_operand(shape.left, inv, fwd, f"{where}.left")
            mid = self.n_rows
            right = self.csg_operand(shape.right, inv, fwd, f"{where}.right")
            self.csg.append([start, mid, self.n_rows, OPERATIONS[shape.operation]])
            return _union([left, right])
        if isinstance(shape, Group) and unchanged(type(shape), Group, SHAPE_METHODS):
            return _union(
                [
                    self.csg_operand(child, inv, fwd, f"{where}.children[{k}]")
                    for k, child in enumerate(shape.children)
                ]
            )
        kind = shape_kind(shape, where)
        self.leaf_row(shape, kind, inv, where, fwd=fwd)
        return self.world_box(shape, kind, fwd)

    def csg_operand(self, shape: Shape, parent_inv: Matrix, parent_fwd: Matrix, where: str) -> Box:
        own = _affine(shape.transform, f"the transform of {where}")
        inv = _compose(_inverse(own, f"the transform of {where}"), parent_inv)
        return self.csg_tree(shape, inv, _compose(parent_fwd, own), where)

    # -- result

    def build(self, lights: Sequence[Light], started: float | None = None) -> Packed:
        """The arrays: rows, items (the balls taken out, empty boxes dropped, and for
        ``sah`` the hierarchy built), boxes, CSG operations, the lights, the textures."""
        dtype = self.dtype
        pf = _stack(self.rows_f, L.NF, np.float64)
        pi = _stack(self.rows_i, L.NI, np.int64)
        items = _stack(self.items, L.NITEM, np.int64)
        bounds = _stack(self.bounds, L.NBOX, np.float64)
        # chapter 5: world spheres reached by a plain item (not in a CSG tree) leave the
        # items for the ball list (``sah``: while there are few of them), in item order
        prim = items[:, L.ITEM_TYPE] == L.I_PRIM
        ball = np.zeros(len(items), dtype=bool)
        ball[prim] = pi[items[prim, L.ITEM_A], L.WORLD_SPHERE] != 0
        if self.structure == "sah" and ball.sum() >= BALLS_MAX:
            ball[:] = False
        ball_rows = items[ball, L.ITEM_A]
        items[ball, L.ITEM_TYPE] = L.I_SKIP
        items, bounds = _drop_skips(items, bounds)
        hierarchy = Hierarchy(self.structure)
        if self.structure == "sah":
            items, boxes, hierarchy = _hierarchy(items, bounds)
        else:
            boxes = np.where((items[:, L.ITEM_TYPE] == L.I_BOX)[:, None], bounds, 0.0)
            boxes = boxes.reshape(len(items), L.NBOX)
            if self.structure == "groups":
                found = int((items[:, L.ITEM_TYPE] == L.I_BOX).sum())
                hierarchy = Hierarchy("groups", boxes=found)
        balls = np.zeros((L.NBALL, len(ball_rows)), dtype=dtype)
        balls[L.B_X : L.B_Z + 1] = pf[ball_rows, L.SPH_CENTER : L.SPH_CENTER + 3].T
        balls[L.B_R2] = pf[ball_rows, L.SPH_R2]
        balls[L.B_SHADOW] = pi[ball_rows, L.CASTS_SHADOW]
        balls[L.B_PRIM] = ball_rows
        csg = np.array(self.csg, dtype=np.int64).reshape(len(self.csg), L.NCSG)
        rows, sequences = light_rows(lights, dtype)
        seconds = time.perf_counter() - started if started is not None else 0.0
        return Packed(
            pf.astype(dtype, copy=False), pi, items, _outward(boxes, dtype), csg,
            rows, self.shapes, max(self.capacity, 1), self.cs_size,
            self.cs_prims, balls, hierarchy, seconds, textures=self.textures,
            light_values=sequences,
        )  # fmt: skip


def _drop_skips(items: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The items without I_SKIP ones and without boxes left with nothing inside; a box's
    jump target moves to the first item kept at or after it."""
    kinds = items[:, L.ITEM_TYPE]
    if not ((kinds == L.I_SKIP) | (kinds == L.I_BOX)).any():
        return items, bounds
    leaf = (kinds == L.I_PRIM) | (kinds == L.I_CSG)
    leaves_before = np.concatenate([[0], np.cumsum(leaf)])
    box = np.flatnonzero(kinds == L.I_BOX)
    empty = leaves_before[items[box, L.ITEM_A]] - leaves_before[box + 1] == 0
    items[box[empty], L.ITEM_TYPE] = L.I_SKIP
    kept = items[:, L.ITEM_TYPE] != L.I_SKIP
    moved = np.concatenate([[0], np.cumsum(kept)])  # old index -> items kept before it
    box = np.flatnonzero(items[:, L.ITEM_TYPE] == L.I_BOX)
    items[box, L.ITEM_A] = moved[items[box, L.ITEM_A]]
    return items[kept], bounds[kept]


def _hierarchy(items: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray, Hierarchy]:
    """``sah``: the unbounded items first, then the hierarchy over the others."""
    bounded = ~np.isnan(bounds).any(axis=1)
    outside = items[~bounded]
    units = items[bounded]
    if len(units) < 2:
        ordered = np.concatenate([outside, units])
        boxes = np.zeros((len(ordered), L.NBOX), dtype=np.float64)
        return ordered, boxes, Hierarchy("sah", len(units), len(outside))
    tree, tree_boxes, hierarchy = build_tree(units, bounds[bounded])
    box = tree[:, L.ITEM_TYPE] == L.I_BOX
    tree[box, L.ITEM_A] += len(outside)
    inner = box & (tree[:, L.ITEM_C] > 0)
    tree[inner, L.ITEM_B] += len(outside)
    boxes = np.concatenate([np.zeros((len(outside), L.NBOX)), tree_boxes])
    return np.concatenate([outside, tree]), boxes, replace(hierarchy, outside=len(outside))


def _apply_array(m: Matrix, points: np.ndarray) -> np.ndarray:
    """``_apply`` on an array of points (..., 3), element by element (as ``_apply`` adds
    its terms; no matrix product, which would wake BLAS threads)."""
    r = m.rows
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    out = np.empty_like(points)
    for k in range(3):
        out[..., k] = r[k][0] * x + r[k][1] * y + r[k][2] * z + r[k][3]
    return out


def _corner_range(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The least and greatest of each triangle's corners (points: triangle, corner, axis),
    axis by axis (explicit: numpy reduces a short axis slowly)."""
    a, b, c = points[:, 0], points[:, 1], points[:, 2]
    return np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)


def _triangle_spheres(points: np.ndarray, fwd: Matrix) -> np.ndarray:
    """``_bounding_sphere`` of many triangles (points: triangle, corner, axis) at once:
    n x 4 (world centre, radius; radius inf where not finite)."""
    lo, hi = _corner_range(points)
    centre = (lo + hi) / 2
    radius = np.sqrt(((points - centre[:, None, :]) ** 2).sum(axis=2)).max(axis=1)
    out = np.empty((len(points), 4), dtype=np.float64)
    out[:, 0:3] = _apply_array(fwd, centre)
    out[:, 3] = radius * _stretch(fwd) * (1.0 + 1e-6) + 1e-9
    bad = ~np.isfinite(out).all(axis=1)
    out[bad] = (0.0, 0.0, 0.0, math.inf)
    return out


def pack_world(
    world: World,
    dtype: Any = np.float64,
    *,
    allow_test_shape: bool = False,
    structure: str = DEFAULT,
) -> Packed:
    """Chapter 7: every object of ``world`` and its lights, packed; ``structure``: how the
    items are arranged (``bvh``)."""
    if not isinstance(world, World):
        raise PackError(f"numba: expected a World, got {type(world).__name__}")
    started = time.perf_counter()
    packer = _Packer(dtype, allow_test_shape, structure)
    for k, shape in enumerate(world.objects):
        packer.add(shape, identity_matrix, identity_matrix, f"world object {k} ({_label(shape)})")
    return packer.build(list(world.lights), started)


def pack_shapes(
    shapes: Sequence[Shape],
    dtype: Any = np.float64,
    *,
    own_transform: bool = True,
    structure: str = DEFAULT,
    every_box: bool = False,
) -> Packed:
    """One or more shapes as the roots of a packed scene, with their own transforms (as
    ``intersect`` sees them: not their parents'), or without (``own_transform=False``, as
    ``local_intersect`` sees them). Test shapes are allowed (the book API's kernels).
    ``every_box`` (with ``structure="groups"``): a box for every bounded group and CSG
    shape, even around one item (where it saves no work, but says, as the reference's
    ``intersect`` does, whether a ray reaches what it holds)."""
    packer = _Packer(dtype, allow_test_shape=True, structure=structure, every_box=every_box)
    for shape in shapes:
        packer.add(shape, identity_matrix, identity_matrix, _label(shape), own=own_transform)
    return packer.build([])


def world_inverse(shape: Shape) -> Matrix:
    """Chapter 14: world space to ``shape``'s object space, through all its parents."""
    where = _label(shape)
    inv = _inverse(
        _affine(shape.transform, f"the transform of {where}"), f"the transform of {where}"
    )
    parent = shape.parent
    while parent is not None:
        what = f"the transform of {_label(parent)}, a parent of {where}"
        inv = _compose(inv, _inverse(_affine(parent.transform, what), what))
        parent = parent.parent
    return inv


def pack_surface(
    shape: Shape | None,
    dtype: Any = np.float64,
    *,
    inv: Matrix | None = None,
    material: Material | None = None,
    pattern: Pattern | None = None,
    leaf: bool = True,
    textures: TextureTable | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """One primitive row (pf, pi, flat) for a single shape's surface, with world-to-object ``inv``
    (default: through its parents), optionally another material or pattern. ``leaf=False``
    packs only the transforms (for ``world_to_object`` / ``normal_to_world`` on a group).
    A texture pattern's records go to ``textures`` (a world's, or a table of its own)."""
    packer = _Packer(dtype, allow_test_shape=True, structure="off")
    if textures is not None:
        packer.textures = textures
    target: Shape = shape if shape is not None else Sphere()
    where = _label(target)
    if inv is None:
        inv = world_inverse(target) if shape is not None else identity_matrix
    kind = shape_kind(target, where) if leaf else L.K_SPHERE
    packer.leaf_row(target, kind, inv, where, material, pattern)
    built = packer.build([])
    return _flat(built.pf), _flat(built.pi)


def _label(shape: object) -> str:
    return f"a {type(shape).__name__}"


@dataclass(frozen=True)
class PackedCamera:
    """Chapter 7: the camera as the kernels read it (``layout`` CAM_*)."""

    array: np.ndarray
    hsize: int
    vsize: int


def pack_camera(c: Camera, dtype: Any = np.float64) -> PackedCamera:
    """The inverse view transform (the reference's), half extents and pixel size."""
    inv = _inverse(_affine(c.transform, "the camera transform"), "the camera transform")
    row = [*_rows3x4(inv), float(c.half_width), float(c.half_height), float(c.pixel_size)]
    return PackedCamera(np.array(row, dtype=dtype), int(c.hsize), int(c.vsize))
