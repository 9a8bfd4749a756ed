"""Packing a world into a ``Scene`` (chapters 5-16), from the tree ``variants.arrays.flatten``
makes of it (of a scene description, with no book shape built, or of the book's shapes):
each leaf a primitive row, each CSG shape a tree over its leaves (chapter 16), materials
and transforms shared by identity.

A run of triangles (an OBJ model's group, a group's run of the book's triangles) is packed
at once with NumPy (``_Packer.triangles``), so that a million triangles pack in a fraction
of a second.

Only what the vectorized passes know is packed: the kinds of ``scene.kinds`` but the test
shape, the reference's pattern, material and light classes, the sky. Anything else (a
texture map, a shape of another kind) is refused with an ``Unsupported`` error naming it,
never approximated; an area light is packed for the path integrator and refused by the
book's (``Scene.refuse_for_whitted``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from raytracer.lights import AreaLight, PointLight
from raytracer.materials import Material
from raytracer.matrices import Matrix
from raytracer.patterns import Pattern
from raytracer.world import World
from scene.pattern_kinds import NO_PATTERN, PatternKind, names, reference_pattern_kind
from variants.arrays import flatten as F
from variants.arrays.rows import normal_rows, rgb, rows3x4, stretch, xyz
from variants.wavefront.scene import (
    KIND_NAMES,
    MATERIAL_FIELDS,
    OPERATIONS,
    PATTERN_KINDS,
    SLOTS,
    SPHERE,
    Bunch,
    Combine,
    CsgTree,
    Leaf,
    Node,
    Scene,
    Unsupported,
)


def _a(name: str) -> str:
    """``name`` with its indefinite article."""
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _label(shape: object) -> str:
    return _a(type(shape).__name__)


def _refusal(error: F.FlattenError) -> Unsupported:
    """A flattening error in the passes' words."""
    if isinstance(error, F.UnknownShape):
        if error.changed is not None:
            return Unsupported(
                f"wavefront: {error.where} is {_a(type(error.shape).__name__)}, which changes "
                f"how {_a(error.changed.__name__)} intersects or computes normals; the passes "
                "only vectorize the reference's"
            )
        return _unknown(error.where, error.shape)
    return Unsupported(f"wavefront: {error}")


def _unknown(where: str, shape: object) -> Unsupported:
    known = ", ".join(KIND_NAMES)
    return Unsupported(
        f"wavefront: {where} is {_a(type(shape).__name__)}; the passes vectorize {known}, "
        "groups and CSG"
    )


def pattern_kind(pattern: object, where: str) -> PatternKind:
    """The kind of a material's pattern (``scene.pattern_kinds``); ``Unsupported`` for any
    other (a texture map, a pattern of patterns)."""
    kind = reference_pattern_kind(pattern, PATTERN_KINDS)
    if kind is not None:
        return kind
    raise Unsupported(
        f"wavefront: the pattern of {where} is {_a(type(pattern).__name__)}; the passes "
        f"vectorize {names(PATTERN_KINDS)}"
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


def _pattern_inverse(pattern: Pattern, where: str) -> Matrix:
    try:
        return F.inverse_affine(pattern.transform, f"the pattern transform of {where}")
    except F.FlattenError as error:
        raise _refusal(error) from None


def _balls(boxes: np.ndarray) -> np.ndarray:
    """Balls (n, 4: centre, radius) holding boxes (n, 6); radius inf for NaN boxes."""
    centre = (boxes[:, 0:3] + boxes[:, 3:6]) / 2
    radius = np.sqrt(((boxes[:, 3:6] - boxes[:, 0:3]) ** 2).sum(axis=1)) / 2
    radius = radius * (1 + 1e-6) + F.BOX_PAD * (1 + np.abs(centre).max(axis=1))
    balls = np.concatenate([centre, radius[:, None]], axis=1)
    balls[np.isnan(boxes).any(axis=1)] = (0.0, 0.0, 0.0, math.inf)
    return balls


def _sphere_ball(fwd: Matrix) -> list[float]:
    """The world-space ball holding the unit sphere moved by ``fwd``: its centre, and the
    most ``fwd`` can stretch a unit vector (Gershgorin's bound on AᵀA, exact for a rotation
    times a scale along the axes)."""
    centre = [float(fwd.rows[k][3]) for k in range(3)]
    radius = stretch(fwd) * (1 + 1e-6) + F.BOX_PAD * (1 + max(map(abs, centre)))
    if not (math.isfinite(radius) and all(map(math.isfinite, centre))):
        return [0.0, 0.0, 0.0, math.inf]
    return [*centre, radius]


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
    """Walks a flattened world (``variants.arrays.flatten``), collecting rows."""

    def __init__(self, shading: bool = True) -> None:
        self.shading = shading  # False: geometry only (materials and patterns not read)
        self.kind, self.row, self.xform, self.mat = Column(0), Column(0), Column(0), Column(0)
        self.shadow = Column(0)
        self.shapes: list[Any] = []
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
            self.inv_rows.append(rows3x4(inv))
            self.nrm_rows.append(normal_rows(inv))
            self.keep.append(inv)
        return found

    def material_row(self, m: Any, where: str) -> int:
        if not self.shading:
            return 0
        key = id(m)
        found = self.mat_ids.get(key)
        if found is not None:
            return found
        _check_material(m, where)
        values = [
            *rgb(m.color), float(m.ambient), float(m.diffuse), float(m.specular),
            float(m.shininess), float(m.reflective), float(m.transparency),
            float(m.refractive_index), *rgb(m.emissive),
        ]  # fmt: skip
        pattern = NO_PATTERN
        pat = [0.0] * 18
        if m.pattern is not None:
            kind = pattern_kind(m.pattern, where)
            pattern = kind.number
            pat[0:12] = rows3x4(_pattern_inverse(m.pattern, where))
            if kind.two_colors:
                pat[12:15] = rgb(m.pattern.a)
                pat[15:18] = rgb(m.pattern.b)
        found = self.mat_ids[key] = len(self.mat_rows)
        self.mat_rows.append(values + pat)
        self.pattern_kinds.append(pattern)
        self.keep.append(m)
        return found

    def prim(self, leaf: F.Leaf) -> int:
        """One primitive; returns its index."""
        kind = leaf.kind.number
        if not leaf.kind.renders:
            raise _unknown(leaf.where, leaf.source if leaf.source is not None else leaf.kind)
        row = 0
        if leaf.params:  # its parameters, in the kind table's order, as floats
            row = self.caps.count
            values = [float(v) for v in leaf.params.values()]
            self.caps.append((values + [0.0] * 3)[:3])
        self.kind.append(kind)
        self.kinds.append(kind)
        self.row.append(row)
        self.xform.append(self.transform_row(leaf.inv))
        self.mat.append(self.material_row(leaf.material, leaf.where))
        self.shadow.append(leaf.shadow)
        self.shapes.append(leaf.source)
        return self.kind.count - 1

    def unit(self, prim: int, tree: int, box: np.ndarray, ball: Any) -> None:
        self.unit_prim.append(prim)
        self.unit_tree.append(tree)
        self.unit_box.append(box)
        self.unit_ball.append(ball)

    # -- the walk

    def add(self, node: F.Node) -> np.ndarray:
        """A world object or a group's child: leaves and CSG trees become units; returns
        its world-space box (6,), NaN when unbounded."""
        if isinstance(node, F.Group):
            return F.union([self.add(child) for child in node.children])
        if isinstance(node, F.Csg):
            lo = self.kind.count
            self.kinds = []
            root, box = self.csg(node)
            assert isinstance(root, Combine)
            slots = sum(SLOTS[k] for k in self.kinds)
            self.unit(-1, len(self.trees), box, _balls(box.reshape(1, 6))[0])
            self.trees.append(CsgTree(root, lo, self.kind.count, slots))
            return box
        if isinstance(node, F.Triangles):
            first = self.kind.count
            boxes = self.triangles(node)
            n = node.count
            self.unit_prim.extend(np.arange(first, first + n, dtype=np.float64))
            self.unit_tree.extend(np.full(n, -1.0))
            self.unit_box.extend(boxes)
            self.unit_ball.extend(_balls(boxes))
            return F.union([boxes])
        p = self.prim(node)
        box = F.leaf_box(node)
        sphere = node.kind.number == SPHERE
        ball = _sphere_ball(node.fwd) if sphere else _balls(box.reshape(1, 6))[0]
        self.unit(p, -1, box, ball)
        return box

    def triangles(self, run: F.Triangles) -> np.ndarray:
        """Chapter 15 at scale: triangles of one kind, each a primitive, their rows built
        with NumPy; returns their world boxes (n, 6)."""
        n = run.count
        kind = run.kind.number
        tg, bounds = run.geometry()  # p1, e1, e2, normal: the layout of ``tri``
        self.tri.extend(tg)
        normals = run.normals()
        self.smooth.extend(normals.reshape(n, 9) if normals is not None else np.zeros((n, 9)))
        firsts = [int(np.argmax(run.material_of == j)) for j in range(len(run.materials))]
        rows = np.array(
            [
                self.material_row(m, f"{run.where} (its triangle {first})")
                for m, first in zip(run.materials, firsts, strict=True)
            ],
            dtype=np.float64,
        )
        self.mat.extend(rows[run.material_of])
        self.shadow.extend(run.shadow.astype(np.float64))
        self.kind.extend(np.full(n, kind, dtype=np.float64))
        self.kinds.extend([kind] * n)
        self.row.extend(np.arange(self.tri.count - n, self.tri.count, dtype=np.float64))
        self.xform.extend(np.full(n, self.transform_row(run.inv), dtype=np.float64))
        self.shapes.extend(run.sources if run.sources is not None else [None] * n)
        return bounds

    def csg(self, node: F.Node) -> tuple[Node, np.ndarray]:
        """A CSG operand: its node and box."""
        if isinstance(node, F.Csg):
            if node.operation not in OPERATIONS:
                raise Unsupported(f"wavefront: {node.where} has an unknown operation")
            lo = self.kind.count
            left, left_box = self.csg(node.left)
            mid = self.kind.count
            right, right_box = self.csg(node.right)
            combined = Combine(OPERATIONS[node.operation], left, right, lo, mid, self.kind.count)
            return combined, F.union([left_box, right_box])
        if isinstance(node, F.Group):
            parts = [self.csg(child) for child in node.children]
            return Bunch(tuple(n for n, _ in parts)), F.union([b for _, b in parts])
        if isinstance(node, F.Triangles):
            first = self.kind.count
            boxes = self.triangles(node)
            leaves = tuple(Leaf(p) for p in range(first, first + node.count))
            return (leaves[0] if len(leaves) == 1 else Bunch(leaves)), F.union([boxes])
        return Leaf(self.prim(node)), F.leaf_box(node)


MATERIAL_WIDTH = 31
"""A material's row: colour (3), ambient, diffuse, specular, shininess, reflective,
transparency, refractive index, emissive (3), the pattern's inverse (12) and colours (6)."""


def _table(rows: list[list[float]], width: int) -> np.ndarray:
    if not rows:
        return np.zeros((0, width))
    return np.array(rows, dtype=np.float64).reshape(len(rows), width)


def pack(world: World, dtype: Any = np.float64, shading: bool = True) -> Scene:
    """Chapter 7: the objects and lights of the book's ``world`` as tables in ``dtype``;
    ``shading=False``: its geometry only (no lights, materials or patterns: what
    ``intersect_world`` and ``is_shadowed`` need, whatever lights the world has)."""
    if not isinstance(world, World):
        raise Unsupported(f"wavefront: expected a World, got {type(world).__name__}")
    nodes = _flattened(F.from_world, world)
    return _tables(nodes, list(world.lights), world.sky, dtype, shading)


def pack_scene(scene: Any, dtype: Any = np.float64) -> Scene:
    """Chapter 7: a scene description (``scene.Scene``) as tables, straight from its
    entities and arrays: no book shape built."""
    nodes = _flattened(F.from_description, scene)
    return _tables(nodes, list(scene.lights), scene.sky, dtype, True)


def _flattened(make: Any, *args: Any) -> Any:
    try:
        return make(*args)
    except F.FlattenError as error:
        raise _refusal(error) from None


def _lights(lights: list[Any]) -> tuple[list[list[float]], ...]:
    """The lights' tables, in the world's order: a point light's position or an area
    light's corner, intensity, an area light's one-cell edges uvec and vvec (zeros for a
    point light) and its usteps and vsteps (0 for a point light)."""
    positions, intensities, edges, steps = [], [], [], []
    for k, light in enumerate(lights):
        if type(light) is AreaLight:
            positions.append(xyz(light.corner))
            edges.append(xyz(light.uvec) + xyz(light.vvec))
            steps.append([float(light.usteps), float(light.vsteps)])
        elif type(light) is PointLight:
            positions.append(xyz(light.position))
            edges.append([0.0] * 6)
            steps.append([0.0, 0.0])
        else:
            raise Unsupported(
                f"wavefront: light {k} of the world is {_a(type(light).__name__)}; the passes "
                "vectorize point lights and (path-traced) area lights only"
            )
        intensities.append(rgb(light.intensity))
    return positions, intensities, edges, steps


def _sky(sky: Any) -> np.ndarray | None:
    """The sky's horizon and zenith colours, (2, 3) float64; None: no sky."""
    if sky is None:
        return None
    return np.array([rgb(sky.horizon), rgb(sky.zenith)], dtype=np.float64)


def _tables(nodes: list[F.Node], lights: list[Any], sky: Any, dtype: Any, shading: bool) -> Scene:
    packer = _Packer(shading)
    for node in nodes:
        packer.add(node)
    positions, intensities, edges, steps = _lights(lights if shading else [])
    mats = _table(packer.mat_rows, MATERIAL_WIDTH)
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
        emissive=columns(mats[:, 10:13]),
        pattern=np.array(packer.pattern_kinds, dtype=np.int64),
        pat_inv=columns(mats[:, 13:25]),
        pat_a=columns(mats[:, 25:28]),
        pat_b=columns(mats[:, 28:31]),
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
        light_edges=f(_table(edges, 6)),
        light_steps=_table(steps, 2).astype(np.int64),
        sky=_sky(sky) if shading else None,
        shapes=packer.shapes,
        opaque=not bool((transparency != 0).any()),
        mirrors=bool(((transparency != 0) | (reflective != 0)).any()),
    )
