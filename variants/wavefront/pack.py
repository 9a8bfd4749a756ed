"""Packing a world into a ``Scene`` (chapters 5-16): its shapes walked depth first, each leaf
a primitive row, each group's transform composed into its leaves (chapter 14), each CSG
shape a tree over its leaves (chapter 16), materials and transforms shared by identity.

A group's run of plain triangles (a mesh: ``Triangle`` or ``SmoothTriangle`` with no
transform of their own) is packed at once with NumPy (``_Packer.triangles``): the same rows
``_Packer.prim`` makes one at a time, read with ``operator.attrgetter`` and
``np.fromiter``, so that a million triangles pack in seconds.

Only what the vectorized passes know is packed: the reference's shape, pattern, material
and point-light classes (a subclass only when it does not change the methods that matter).
Anything else (an area light, a texture map, a shape of another kind) is refused with an
``Unsupported`` error naming it, never approximated.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import operator
from typing import Any

import numpy as np

from raytracer.colors import Color
from raytracer.lights import PointLight
from raytracer.materials import Material
from raytracer.matrices import Matrix, identity_matrix
from raytracer.patterns import Pattern
from raytracer.shapes.csg import CSG
from raytracer.shapes.group import Group
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.triangle import Triangle
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.kinds import PATTERN_METHODS, SHAPE_METHODS, reference_kind, unchanged
from variants.wavefront.scene import (
    BOX_PAD,
    CONE,
    CUBE,
    CYLINDER,
    KIND_NAMES,
    MATERIAL_FIELDS,
    NO_PATTERN,
    OPERATIONS,
    PATTERN_KINDS,
    PATTERN_NAMES,
    SHAPE_KINDS,
    SLOTS,
    SMOOTH,
    SPHERE,
    TEST_PATTERN,
    TRIANGLE,
    Bunch,
    Combine,
    CsgTree,
    Leaf,
    Node,
    Scene,
    Unsupported,
)

Box = tuple[tuple[float, float, float], tuple[float, float, float]] | None
MESH_KINDS: dict[type, int] = {Triangle: TRIANGLE, SmoothTriangle: SMOOTH}
_CORNERS = operator.attrgetter(
    *[f"{corner}.{axis}" for corner in ("p1", "p2", "p3", "e1", "e2", "normal") for axis in "xyz"]
)
_NORMALS = operator.attrgetter(*[f"{n}.{axis}" for n in ("n1", "n2", "n3") for axis in "xyz"])
_MATERIAL = operator.attrgetter("material")
_SHADOW = operator.attrgetter("casts_shadow")
_TRANSFORM = operator.attrgetter("transform")


def _a(name: str) -> str:
    """``name`` with its indefinite article."""
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _label(shape: object) -> str:
    return _a(type(shape).__name__)


def shape_kind(shape: Shape, where: str) -> int:
    """The primitive kind of a leaf shape; ``Unsupported`` for any other."""
    kind, changed = reference_kind(shape, SHAPE_KINDS, SHAPE_METHODS)
    if kind is not None:
        return kind
    if changed is not None:
        raise Unsupported(
            f"wavefront: {where} is {_a(type(shape).__name__)}, which changes how "
            f"{_a(changed.__name__)} intersects or computes normals; the passes only vectorize "
            "the reference's"
        )
    known = ", ".join(KIND_NAMES)
    raise Unsupported(
        f"wavefront: {where} is {_a(type(shape).__name__)}; the passes vectorize {known}, "
        "groups and CSG"
    )


def pattern_kind(pattern: object, where: str) -> int:
    """The pattern kind of a material's pattern; ``Unsupported`` for any other (a texture
    map, a pattern of patterns)."""
    kind, _ = reference_kind(pattern, PATTERN_KINDS, PATTERN_METHODS)
    if kind is not None:
        return kind
    raise Unsupported(
        f"wavefront: the pattern of {where} is {_a(type(pattern).__name__)}; the passes "
        f"vectorize {PATTERN_NAMES}"
    )


def _check_material(m: object, where: str) -> Material:
    if not isinstance(m, Material):
        raise Unsupported(f"wavefront: {where} has no material (got {type(m).__name__})")
    for f in dataclasses.fields(m):
        if f.name in MATERIAL_FIELDS:
            continue
        default = f.default if f.default is not dataclasses.MISSING else None
        if getattr(m, f.name) != default:
            raise Unsupported(
                f"wavefront: the material of {where} sets {f.name!r}, which the passes do "
                "not vectorize"
            )
    return m


def _rows3x4(m: Matrix) -> list[float]:
    return [float(v) for row in m.rows[:3] for v in row[:4]]


def _normal_rows(inv: Matrix) -> list[float]:
    """Rows 0-2 of the inverse's transpose, 3x3: element (r, c) is inv[c][r]."""
    return [float(inv.rows[c][r]) for r in range(3) for c in range(3)]


def _xyz(t: Tuple) -> list[float]:
    return [float(t.x), float(t.y), float(t.z)]


def _rgb(c: Color) -> list[float]:
    return [float(c.red), float(c.green), float(c.blue)]


def _identity(m: Matrix) -> bool:
    return m is identity_matrix or m == identity_matrix


def _affine(m: Matrix, what: str) -> Matrix:
    if not isinstance(m, Matrix) or m.size != 4:
        raise Unsupported(f"wavefront: {what} is not a 4x4 matrix")
    if tuple(m.rows[3]) != (0.0, 0.0, 0.0, 1.0):
        raise Unsupported(
            f"wavefront: {what} is not affine (bottom row {list(m.rows[3])}); the passes "
            "apply affine transforms only"
        )
    return m


def _compose(a: Matrix, b: Matrix) -> Matrix:
    """``a * b``, skipping identities (a shape outside groups keeps its exact inverse)."""
    if _identity(b):
        return a
    if _identity(a):
        return b
    return a * b


def _inverse(shape: Shape, where: str) -> Matrix:
    m = _affine(shape.transform, f"the transform of {where}")
    if _identity(m):
        return identity_matrix
    try:
        return shape.inverse_transform
    except ValueError:
        raise Unsupported(f"wavefront: the transform of {where} is not invertible") from None


def _pattern_inverse(pattern: Pattern, where: str) -> Matrix:
    m = _affine(pattern.transform, f"the pattern transform of {where}")
    if _identity(m):
        return identity_matrix
    try:
        return pattern.inverse_transform
    except ValueError:
        raise Unsupported(
            f"wavefront: the pattern transform of {where} is not invertible"
        ) from None


def _apply(m: Matrix, points: np.ndarray) -> np.ndarray:
    """``m`` applied to points (..., 3), term by term (no matrix product: it would wake
    BLAS threads)."""
    r = m.rows
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    out = np.empty_like(points)
    for k in range(3):
        out[..., k] = r[k][0] * x + r[k][1] * y + r[k][2] * z + r[k][3]
    return out


def _local_corners(shape: Shape, kind: int) -> np.ndarray | None:
    """Points (n, 3) whose hull holds the shape in object space; None: unbounded."""
    if kind in (SPHERE, CUBE):
        lo_y, hi_y, r = -1.0, 1.0, 1.0
    elif kind in (CYLINDER, CONE):
        lo_y, hi_y = float(shape.minimum), float(shape.maximum)  # type: ignore[attr-defined]
        if not (math.isfinite(lo_y) and math.isfinite(hi_y)):
            return None
        r = 1.0 if kind == CYLINDER else max(abs(lo_y), abs(hi_y))
    elif kind in (TRIANGLE, SMOOTH):
        t: Any = shape
        return np.array([_xyz(p) for p in (t.p1, t.p2, t.p3)])
    else:
        return None
    return np.array([(x, y, z) for x in (-r, r) for y in (lo_y, hi_y) for z in (-r, r)])


def _boxes(points: np.ndarray) -> np.ndarray:
    """Padded boxes (n, 6: lo, hi) of points (n, corners, 3); NaN rows where not finite."""
    lo, hi = points.min(axis=1), points.max(axis=1)
    pad = BOX_PAD * (1.0 + np.abs(lo) + np.abs(hi))
    boxes = np.concatenate([lo - pad, hi + pad], axis=1)
    boxes[~np.isfinite(boxes).all(axis=1)] = np.nan
    return boxes


def _balls(boxes: np.ndarray) -> np.ndarray:
    """Balls (n, 4: centre, radius) holding boxes (n, 6); radius inf for NaN boxes."""
    centre = (boxes[:, 0:3] + boxes[:, 3:6]) / 2
    radius = np.sqrt(((boxes[:, 3:6] - boxes[:, 0:3]) ** 2).sum(axis=1)) / 2
    radius = radius * (1 + 1e-6) + BOX_PAD * (1 + np.abs(centre).max(axis=1))
    balls = np.concatenate([centre, radius[:, None]], axis=1)
    balls[np.isnan(boxes).any(axis=1)] = (0.0, 0.0, 0.0, math.inf)
    return balls


def _sphere_ball(fwd: Matrix) -> list[float]:
    """The world-space ball holding the unit sphere moved by ``fwd``: its centre, and the
    most ``fwd`` can stretch a unit vector (Gershgorin's bound on AᵀA, exact for a rotation
    times a scale along the axes)."""
    a = [[float(v) for v in row[:3]] for row in fwd.rows[:3]]
    gram = [[sum(a[k][i] * a[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    stretch = math.sqrt(max(sum(abs(v) for v in row) for row in gram))
    centre = [float(fwd.rows[k][3]) for k in range(3)]
    radius = stretch * (1 + 1e-6) + BOX_PAD * (1 + max(map(abs, centre)))
    if not (math.isfinite(radius) and all(map(math.isfinite, centre))):
        return [0.0, 0.0, 0.0, math.inf]
    return [*centre, radius]


def _union(boxes: list[np.ndarray]) -> np.ndarray:
    """The box (6,) around boxes (NaN if any is unbounded)."""
    if not boxes:
        return np.full(6, np.nan)
    every = np.concatenate([b.reshape(-1, 6) for b in boxes])
    if not len(every) or np.isnan(every).any():
        return np.full(6, np.nan)
    return np.concatenate([every[:, 0:3].min(axis=0), every[:, 3:6].max(axis=0)])


class Column:
    """Values appended one at a time or as whole blocks, kept in order."""

    def __init__(self, width: int) -> None:
        self.width = width
        self.blocks: list[np.ndarray] = []
        self.pending: list[Any] = []
        self.count = 0

    def append(self, value: Any) -> None:
        self.pending.append(value)
        self.count += 1

    def extend(self, block: np.ndarray) -> None:
        self._flush()
        self.blocks.append(block)
        self.count += len(block)

    def _flush(self) -> None:
        if self.pending:
            shape = (len(self.pending), self.width) if self.width else (len(self.pending),)
            self.blocks.append(np.array(self.pending, dtype=np.float64).reshape(shape))
            self.pending = []

    def array(self, dtype: Any) -> np.ndarray:
        self._flush()
        shape = (0, self.width) if self.width else (0,)
        if not self.blocks:
            return np.zeros(shape, dtype=dtype)
        return np.concatenate([b.astype(dtype, copy=False) for b in self.blocks])


class _Packer:
    """Walks the world's shapes, collecting rows."""

    def __init__(self, shading: bool = True) -> None:
        self.shading = shading  # False: geometry only (materials and patterns not read)
        self.kind, self.row, self.xform, self.mat = Column(0), Column(0), Column(0), Column(0)
        self.shadow = Column(0)
        self.shapes: list[Shape] = []
        self.inv_rows: list[list[float]] = []
        self.nrm_rows: list[list[float]] = []
        self.xform_ids: dict[int, int] = {}
        self.mat_rows: list[list[float]] = []
        self.mat_ids: dict[int, int] = {}
        self.pattern_kinds: list[int] = []
        self.keep: list[object] = []  # keeps the objects whose ids are keys alive
        self.caps = Column(3)
        self.tri = Column(12)
        self.smooth = Column(9)
        self.unit_prim, self.unit_tree = Column(0), Column(0)
        self.unit_box, self.unit_ball = Column(6), Column(4)
        self.trees: list[CsgTree] = []
        self.kinds: list[int] = []  # of the primitives of the CSG tree being packed

    # -- tables

    def transform_row(self, inv: Matrix) -> int:
        key = id(inv)
        found = self.xform_ids.get(key)
        if found is None:
            found = self.xform_ids[key] = len(self.inv_rows)
            self.inv_rows.append(_rows3x4(inv))
            self.nrm_rows.append(_normal_rows(inv))
            self.keep.append(inv)
        return found

    def material_row(self, m: Material, where: str) -> int:
        if not self.shading:
            return 0
        key = id(m)
        found = self.mat_ids.get(key)
        if found is not None:
            return found
        _check_material(m, where)
        values = [
            *_rgb(m.color), float(m.ambient), float(m.diffuse), float(m.specular),
            float(m.shininess), float(m.reflective), float(m.transparency),
            float(m.refractive_index),
        ]  # fmt: skip
        pattern = NO_PATTERN
        pat = [0.0] * 18
        if m.pattern is not None:
            pattern = pattern_kind(m.pattern, where)
            pat[0:12] = _rows3x4(_pattern_inverse(m.pattern, where))
            if pattern != TEST_PATTERN:
                pat[12:15] = _rgb(m.pattern.a)  # type: ignore[attr-defined]
                pat[15:18] = _rgb(m.pattern.b)  # type: ignore[attr-defined]
        found = self.mat_ids[key] = len(self.mat_rows)
        self.mat_rows.append(values + pat)
        self.pattern_kinds.append(pattern)
        self.keep.append(m)
        return found

    def prim(self, shape: Shape, kind: int, inv: Matrix, where: str) -> int:
        """One primitive; returns its index."""
        row = 0
        if kind in (CYLINDER, CONE):
            s: Any = shape
            row = self.caps.count
            self.caps.append([float(s.minimum), float(s.maximum), 1.0 if s.closed else 0.0])
        elif kind in (TRIANGLE, SMOOTH):
            t: Any = shape
            row = self.tri.count
            self.tri.append([*_xyz(t.p1), *_xyz(t.e1), *_xyz(t.e2), *_xyz(t.normal)])
            self.smooth.append(
                [*_xyz(t.n1), *_xyz(t.n2), *_xyz(t.n3)] if kind == SMOOTH else [0.0] * 9
            )
        self.kind.append(kind)
        self.kinds.append(kind)
        self.row.append(row)
        self.xform.append(self.transform_row(inv))
        self.mat.append(self.material_row(shape.material, where))
        self.shadow.append(bool(getattr(shape, "casts_shadow", True)))
        self.shapes.append(shape)
        return self.kind.count - 1

    def unit(self, prim: int, tree: int, box: np.ndarray, ball: Any) -> None:
        self.unit_prim.append(prim)
        self.unit_tree.append(tree)
        self.unit_box.append(box)
        self.unit_ball.append(ball)

    # -- the walk

    def add(self, shape: Shape, parent_inv: Matrix, parent_fwd: Matrix, where: str) -> np.ndarray:
        """A world object or a group's child: leaves and CSG trees become units; returns
        its world-space box (6,), NaN when unbounded."""
        inv = _compose(_inverse(shape, where), parent_inv)
        fwd = _compose(parent_fwd, shape.transform)
        if isinstance(shape, Group) and unchanged(type(shape), Group, SHAPE_METHODS):
            return self.group(shape, inv, fwd, where)
        if isinstance(shape, CSG) and unchanged(type(shape), CSG, SHAPE_METHODS):
            lo = self.kind.count
            self.kinds = []
            root, box = self.csg(shape, inv, fwd, where)
            assert isinstance(root, Combine)
            slots = sum(SLOTS[k] for k in self.kinds)
            self.unit(-1, len(self.trees), box, _balls(box.reshape(1, 6))[0])
            self.trees.append(CsgTree(root, lo, self.kind.count, slots))
            return box
        kind = shape_kind(shape, where)
        p = self.prim(shape, kind, inv, where)
        box = self.box(shape, kind, fwd)
        ball = _sphere_ball(fwd) if kind == SPHERE else _balls(box.reshape(1, 6))[0]
        self.unit(p, -1, box, ball)
        return box

    def group(self, g: Group, inv: Matrix, fwd: Matrix, where: str) -> np.ndarray:
        """Chapter 14: a group's children, runs of mesh triangles packed at once."""
        children = g.children
        kinds = [
            MESH_KINDS.get(cls, -1) if _identity(m) else -1
            for cls, m in zip(map(type, children), map(_TRANSFORM, children), strict=True)
        ]
        boxes: list[np.ndarray] = []
        start = 0
        for k in range(len(children) + 1):
            if k < len(children) and kinds[k] >= 0 and kinds[k] == kinds[start]:
                continue
            if start < k and kinds[start] >= 0:
                boxes.append(self.triangles(children[start:k], kinds[start], inv, fwd, where))
                start = k
            if k < len(children) and kinds[k] < 0:
                child = children[k]
                boxes.append(self.add(child, inv, fwd, f"{where}.children[{k}] ({_label(child)})"))
                start = k + 1
        return _union(boxes)

    def triangles(
        self, run: list[Shape], kind: int, inv: Matrix, fwd: Matrix, where: str
    ) -> np.ndarray:
        """Chapter 15 at scale: triangles of one ``kind`` with no transform of their own,
        each a primitive and a unit, their rows built with NumPy; returns their box."""
        n = len(run)
        first = self.kind.count
        corners = np.fromiter(
            itertools.chain.from_iterable(map(_CORNERS, run)), dtype=np.float64, count=n * 18
        ).reshape(n, 18)
        self.tri.extend(np.concatenate([corners[:, 0:3], corners[:, 9:18]], axis=1))
        if kind == SMOOTH:
            normals = np.fromiter(
                itertools.chain.from_iterable(map(_NORMALS, run)), dtype=np.float64, count=n * 9
            ).reshape(n, 9)
        else:
            normals = np.zeros((n, 9))
        self.smooth.extend(normals)
        materials = list(map(_MATERIAL, run))
        ids = np.fromiter(map(id, materials), dtype=np.int64, count=n)
        _, firsts, which = np.unique(ids, return_index=True, return_inverse=True)
        rows = np.array(
            [self.material_row(materials[j], f"{where} (its triangle {j})") for j in firsts],
            dtype=np.float64,
        )
        self.mat.extend(rows[which.reshape(-1)])
        self.shadow.extend(np.fromiter(map(bool, map(_SHADOW, run)), dtype=np.float64, count=n))
        self.kind.extend(np.full(n, kind, dtype=np.float64))
        self.row.extend(np.arange(self.tri.count - n, self.tri.count, dtype=np.float64))
        self.xform.extend(np.full(n, self.transform_row(inv), dtype=np.float64))
        self.shapes.extend(run)
        boxes = _boxes(_apply(fwd, corners[:, 0:9].reshape(n, 3, 3)))
        self.unit_prim.extend(np.arange(first, first + n, dtype=np.float64))
        self.unit_tree.extend(np.full(n, -1.0))
        self.unit_box.extend(boxes)
        self.unit_ball.extend(_balls(boxes))
        return _union([boxes])

    def box(self, shape: Shape, kind: int, fwd: Matrix) -> np.ndarray:
        corners = _local_corners(shape, kind)
        if corners is None:
            return np.full(6, np.nan)
        return _boxes(_apply(fwd, corners)[None])[0]

    def csg(self, shape: Shape, inv: Matrix, fwd: Matrix, where: str) -> tuple[Node, np.ndarray]:
        """A CSG operand (inv and fwd include its own transform): its node and box."""
        if isinstance(shape, CSG) and unchanged(type(shape), CSG, SHAPE_METHODS):
            if shape.operation not in OPERATIONS:
                raise Unsupported(f"wavefront: {where} has an unknown operation")
            lo = self.kind.count
            left, left_box = self.operand(shape.left, inv, fwd, f"{where}.left")
            mid = self.kind.count
            right, right_box = self.operand(shape.right, inv, fwd, f"{where}.right")
            node = Combine(OPERATIONS[shape.operation], left, right, lo, mid, self.kind.count)
            return node, _union([left_box, right_box])
        if isinstance(shape, Group) and unchanged(type(shape), Group, SHAPE_METHODS):
            parts = [
                self.operand(child, inv, fwd, f"{where}.children[{k}]")
                for k, child in enumerate(shape.children)
            ]
            return Bunch(tuple(node for node, _ in parts)), _union([b for _, b in parts])
        kind = shape_kind(shape, where)
        return Leaf(self.prim(shape, kind, inv, where)), self.box(shape, kind, fwd)

    def operand(self, shape: Shape, parent_inv: Matrix, parent_fwd: Matrix, where: str) -> Any:
        inv = _compose(_inverse(shape, where), parent_inv)
        return self.csg(shape, inv, _compose(parent_fwd, shape.transform), where)


def _table(rows: list[list[float]], width: int) -> np.ndarray:
    if not rows:
        return np.zeros((0, width))
    return np.array(rows, dtype=np.float64).reshape(len(rows), width)


def pack(world: World, dtype: Any = np.float64, shading: bool = True) -> Scene:
    """Chapter 7: the objects and lights of ``world`` as tables in ``dtype``;
    ``shading=False``: its geometry only (no lights, materials or patterns: what
    ``intersect_world`` and ``is_shadowed`` need, whatever lights the world has)."""
    if not isinstance(world, World):
        raise Unsupported(f"wavefront: expected a World, got {type(world).__name__}")
    packer = _Packer(shading)
    for k, shape in enumerate(world.objects):
        packer.add(shape, identity_matrix, identity_matrix, f"world object {k} ({_label(shape)})")
    positions: list[list[float]] = []
    intensities: list[list[float]] = []
    for k, light in enumerate(world.lights if shading else ()):
        if type(light) is not PointLight:
            raise Unsupported(
                f"wavefront: light {k} of the world is {_a(type(light).__name__)}; the passes "
                "vectorize point lights only"
            )
        positions.append(_xyz(light.position))
        intensities.append(_rgb(light.intensity))
    mats = _table(packer.mat_rows, 28)
    boxes = packer.unit_box.array(np.float64)

    def f(a: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(a, dtype=dtype)

    def columns(a: np.ndarray) -> np.ndarray:  # one contiguous row per column
        return np.ascontiguousarray(a.T, dtype=dtype)

    def ints(column: Column) -> np.ndarray:
        return column.array(np.int64)

    reflective = mats[:, 7]
    transparency = mats[:, 8]
    return Scene(
        dtype=np.dtype(dtype),
        kind=ints(packer.kind),
        row=ints(packer.row),
        xform=ints(packer.xform),
        mat=ints(packer.mat),
        shadow=packer.shadow.array(bool),
        inv=columns(_table(packer.inv_rows, 12)),
        nrm=columns(_table(packer.nrm_rows, 9)),
        color=columns(mats[:, 0:3]),
        ambient=f(mats[:, 3]),
        diffuse=f(mats[:, 4]),
        specular=f(mats[:, 5]),
        shininess=f(mats[:, 6]),
        reflective=f(reflective),
        transparency=f(transparency),
        refractive=f(mats[:, 9]),
        pattern=np.array(packer.pattern_kinds, dtype=np.int64),
        pat_inv=columns(mats[:, 10:22]),
        pat_a=columns(mats[:, 22:25]),
        pat_b=columns(mats[:, 25:28]),
        caps=columns(packer.caps.array(np.float64)),
        tri=columns(packer.tri.array(np.float64)),
        smooth=columns(packer.smooth.array(np.float64)),
        unit_prim=ints(packer.unit_prim),
        unit_tree=ints(packer.unit_tree),
        unit_lo=boxes[:, 0:3].copy(),
        unit_hi=boxes[:, 3:6].copy(),
        unit_ball=columns(packer.unit_ball.array(np.float64)),
        trees=packer.trees,
        light_pos=f(_table(positions, 3)),
        light_int=f(_table(intensities, 3)),
        shapes=packer.shapes,
        opaque=not bool((transparency != 0).any()),
        mirrors=bool(((transparency != 0) | (reflective != 0)).any()),
    )
