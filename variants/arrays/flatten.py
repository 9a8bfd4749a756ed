"""A scene as the tracers that flatten it into tables see it (``numba``, ``wavefront``):
every leaf with its transform composed through its groups and CSG parents (chapter 14), its
material and shadow resolved, an OBJ model's triangles as arrays. Made from a scene
description (``scene.Scene``: nothing of the book's built, so a mesh is never an object per
triangle) or from the book's shapes (a ``World``, or shapes, for the book's API); the
packers of both tracers walk this tree and nothing else.

- ``Leaf``: one shape of a kind of ``scene.kinds`` other than the triangles;
- ``Triangles``: triangles of one kind (flat or smooth) with no transform of their own: an
  OBJ model's group, a group's run of them, or a single one; corners, edges and normals as
  arrays, each number what the reference's ``Triangle`` holds;
- ``Group`` (chapter 14) and ``Csg`` (chapter 16): what holds them.

Transforms are composed with the reference's matrices and its ``inverse`` (cofactor
expansion), so the packed tables start from the very numbers the reference uses; an
identity stays the identity (its computed inverse would hold -0.0). Only the reference's own
shape classes are flattened (or subclasses that keep their intersection and normal);
anything else is an ``UnknownShape``, which each tracer reports in its own words.
"""

from __future__ import annotations

import itertools
import operator
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from compiled.library import Recipe, load
from raytracer.matrices import Matrix, identity_matrix, inverse
from raytracer.shapes.csg import CSG
from raytracer.shapes.group import Group as BookGroup
from raytracer.shapes.shape import Shape
from raytracer.world import World
from scene.build import make_material
from scene.kinds import BY_NAME, SHAPE_METHODS, Kind, reference_kind, unchanged
from scene.shapes import GROUPS, ShapeSpec
from variants.arrays.rows import rows3x4

if TYPE_CHECKING:  # an OBJ model's arrays: imported by the loader for a scene that reads one
    from scene.obj_mesh import Mesh

BOX_PAD = 1e-9  # a world box grows by this much (relative, plus absolute): no hit is lost

Box = tuple[tuple[float, float, float], tuple[float, float, float]]


class FlattenError(ValueError):
    """A transform a flattening tracer cannot use; the message names the shape, without
    the tracer's name (each tracer adds its own)."""


class UnknownShape(FlattenError):
    """A shape of no kind the table knows (``changed``: the reference class whose
    intersection or normal it overrides, if it is a subclass of one)."""

    def __init__(self, where: str, shape: object, changed: type | None) -> None:
        super().__init__(f"{where} is a {type(shape).__name__}")
        self.where = where
        self.shape = shape
        self.changed = changed


@dataclass(eq=False)
class Leaf:
    """One shape: ``kind`` (not a triangle), its parameters by attribute, ``inv`` (world
    to object space) and ``fwd`` (object to world), its material and shadow; ``where``
    names it; ``source``: the book's shape it was made from, if any."""

    kind: Kind
    params: Mapping[str, Any]
    inv: Matrix
    fwd: Matrix
    material: Any
    shadow: bool
    where: str
    source: Shape | None = None

    def local_corners(self) -> np.ndarray | None:
        """The 8 corners of its box in object space (the kind's, ``scene.kinds``); None
        when it is unbounded."""
        box = self.kind.local_box(self.params)
        if box is None:
            return None
        (lx, ly, lz), (hx, hy, hz) = box
        corners = [(x, y, z) for x in (lx, hx) for y in (ly, hy) for z in (lz, hz)]
        return np.array(corners, dtype=np.float64)


@dataclass(eq=False)
class Triangles:
    """Triangles of one ``kind`` (``triangle`` or ``smooth_triangle``), ``count`` of them, in
    their parent's space (no transform of their own), from one of two sources: an OBJ
    model's arrays (``mesh`` and its ``rows``: nothing else is made until a packer asks),
    or the book's triangles' numbers (``given``: corners (n, 3, 3: p1, p2, p3), edges (n, 2,
    3: e1, e2), face normals (n, 3)); ``materials`` and ``shadow`` per triangle
    (``material_of``: an index into ``materials``); ``inv``, ``fwd``: their parent's;
    ``sources``: the book's triangles they were made from, if any."""

    kind: Kind
    count: int
    materials: list[Any]
    material_of: np.ndarray
    shadow: np.ndarray
    inv: Matrix
    fwd: Matrix
    where: str
    mesh: Mesh | None = None
    rows: slice = field(default_factory=lambda: slice(0))
    given: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None] | None = None
    sources: list[Shape] | None = None

    def corners(self) -> np.ndarray:
        """(n, 3, 3): each triangle's corners p1, p2, p3."""
        if self.mesh is not None:
            return self.mesh.corners(self.rows)
        assert self.given is not None
        return self.given[0]

    def normals(self) -> np.ndarray | None:
        """(n, 3, 3): a smooth triangle's corner normals n1, n2, n3; None for flat ones."""
        if not self.kind.smooth:
            return None
        if self.mesh is not None:
            assert self.mesh.corner_normals is not None
            return self.mesh.normals[self.mesh.corner_normals[self.rows]]
        assert self.given is not None
        return self.given[3]

    def geometry(self) -> tuple[np.ndarray, np.ndarray]:
        """(tg, bounds): each triangle's p1, e1, e2 and face normal (n, 12: the reference
        ``Triangle``'s numbers) and its world box (n, 6, NaN rows where not finite). An OBJ
        model's are computed by compiled code straight from its arrays, in one pass."""
        if self.mesh is not None:
            return mesh_geometry(self.mesh, self.rows, self.fwd)
        assert self.given is not None
        corners, edges, normal, _ = self.given
        n = self.count
        tg = np.concatenate([corners[:, 0], edges.reshape(n, 6), normal], axis=1)
        return tg, world_boxes(self.fwd, corners)


@dataclass(eq=False)
class Group:
    """Chapter 14: shapes whose transforms already hold the group's."""

    children: list[Node]
    where: str


@dataclass(eq=False)
class Csg:
    """Chapter 16: ``left`` ``operation`` ``right``."""

    operation: str
    left: Node
    right: Node
    where: str


Node = Leaf | Triangles | Group | Csg


# ---------------------------------------------------------------- transforms and boxes


def is_identity(m: Matrix) -> bool:
    return m is identity_matrix or m == identity_matrix


def affine(m: object, what: str) -> Matrix:
    """``m`` if it is a 4x4 affine matrix (bottom row 0 0 0 1), else a ``FlattenError``."""
    if not isinstance(m, Matrix) or m.size != 4:
        raise FlattenError(f"{what} is not a 4x4 matrix")
    if tuple(m.rows[3]) != (0.0, 0.0, 0.0, 1.0):
        raise FlattenError(
            f"{what} is not affine (its bottom row is {list(m.rows[3])}, not [0, 0, 0, 1]); "
            "only affine transforms are supported"
        )
    return m


def inverse_affine(
    m: object, what: str, known: Mapping[int, tuple[Any, Any]] | None = None
) -> Matrix:
    """The reference's inverse of an affine ``m`` (the identity's is itself); a
    ``FlattenError`` when it has none. ``known``: inverses already computed with the
    reference's ``inverse``, by the matrix's id, the matrix beside it (a scene's load)."""
    matrix = affine(m, what)
    if is_identity(matrix):
        return identity_matrix
    found = known.get(id(matrix)) if known else None
    if found is not None and found[0] is matrix:
        return found[1]
    try:
        return inverse(matrix)
    except ValueError:
        raise FlattenError(f"{what} is not invertible (determinant 0)") from None


def compose(a: Matrix, b: Matrix) -> Matrix:
    """``a * b``, skipping identities (a shape outside groups keeps its exact inverse)."""
    if is_identity(b):
        return a
    if is_identity(a):
        return b
    return a * b


def apply(m: Matrix, points: np.ndarray) -> np.ndarray:
    """``m`` applied to points (..., 3), term by term as Python adds them (no matrix
    product, which would also wake BLAS threads beside the render's)."""
    r = m.rows
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    out = np.empty(points.shape, dtype=np.float64)
    for k in range(3):
        out[..., k] = r[k][0] * x + r[k][1] * y + r[k][2] * z + r[k][3]
    return out


def world_boxes(fwd: Matrix, points: np.ndarray) -> np.ndarray:
    """Padded world-space boxes (n, 6: lo, hi) of object-space points (n, k, 3) moved by
    ``fwd``; NaN rows where a value is not finite."""
    moved = apply(fwd, points)
    lo, hi = moved[:, 0], moved[:, 0]
    for k in range(1, moved.shape[1]):  # explicit: numpy reduces a short axis slowly
        lo, hi = np.minimum(lo, moved[:, k]), np.maximum(hi, moved[:, k])
    pad = BOX_PAD * (1.0 + np.abs(lo) + np.abs(hi))
    boxes = np.concatenate([lo - pad, hi + pad], axis=1)
    boxes[~np.isfinite(boxes).all(axis=1)] = np.nan
    return boxes


def leaf_box(leaf: Leaf) -> np.ndarray:
    """A leaf's world box (6,), NaN when it is unbounded."""
    corners = leaf.local_corners()
    if corners is None:
        return np.full(6, np.nan)
    return world_boxes(leaf.fwd, corners[None])[0]


def union(boxes: Sequence[np.ndarray]) -> np.ndarray:
    """The box (6,) around boxes (each (6,) or (n, 6)); NaN if any is unbounded or none."""
    if not boxes:
        return np.full(6, np.nan)
    every = np.concatenate([np.asarray(b).reshape(-1, 6) for b in boxes])
    if not len(every) or np.isnan(every).any():
        return np.full(6, np.nan)
    return np.concatenate([every[:, 0:3].min(axis=0), every[:, 3:6].max(axis=0)])


# ------------------------------------------------------------------------ the triangles


MESH_PACKER = Recipe(
    name="pack_mesh",
    module="variants.arrays.mesh_kernel",
    function="pack_mesh",
    parameters=(
        ("int64_t", "n"), ("double *", "positions"), ("int32_t *", "tri"), ("double *", "fwd"),
        ("double *", "tg"), ("double *", "bounds"), ("double", "pad"),
    ),
    what="the mesh packer",
)  # fmt: skip


def mesh_geometry(mesh: Mesh, rows: slice, fwd: Matrix) -> tuple[np.ndarray, np.ndarray]:
    """``Triangles.geometry`` of an OBJ model's triangles ``rows`` (``mesh_kernel``): the
    numbers ``face_normals`` and ``world_boxes`` give, term by term."""
    tri = np.ascontiguousarray(mesh.triangles[rows], dtype=np.int32)
    n = len(tri)
    tg = np.empty((n, 12), dtype=np.float64)
    bounds = np.empty((n, 6), dtype=np.float64)
    if n:
        positions = np.ascontiguousarray(mesh.positions, dtype=np.float64)
        m = np.array(rows3x4(fwd), dtype=np.float64)
        load(MESH_PACKER).function(n, positions, tri, m, tg, bounds, BOX_PAD)
    return tg, bounds


_CORNERS = operator.attrgetter(
    *[f"{corner}.{axis}" for corner in ("p1", "p2", "p3", "e1", "e2", "normal") for axis in "xyz"]
)
_NORMALS = operator.attrgetter(*[f"{n}.{axis}" for n in ("n1", "n2", "n3") for axis in "xyz"])


def book_triangles(run: list[Shape], kind: Kind, inv: Matrix, fwd: Matrix, where: str) -> Triangles:
    """``Triangles`` holding the numbers of the book's triangles ``run`` (all of ``kind``,
    no transform of their own), read at once."""
    n = len(run)
    values = np.fromiter(
        itertools.chain.from_iterable(map(_CORNERS, run)), dtype=np.float64, count=n * 18
    ).reshape(n, 18)
    normals = None
    if kind.smooth:
        normals = np.fromiter(
            itertools.chain.from_iterable(map(_NORMALS, run)), dtype=np.float64, count=n * 9
        ).reshape(n, 3, 3)
    materials: dict[int, int] = {}
    listed: list[Any] = []
    material_of = np.empty(n, dtype=np.int64)
    for k, shape in enumerate(run):
        m = shape.material
        found = materials.get(id(m))
        if found is None:
            found = materials[id(m)] = len(listed)
            listed.append(m)
        material_of[k] = found
    shadow = np.fromiter((bool(s.casts_shadow) for s in run), dtype=bool, count=n)
    given = (
        values[:, 0:9].reshape(n, 3, 3), values[:, 9:15].reshape(n, 2, 3), values[:, 15:18],
        normals,
    )  # fmt: skip
    return Triangles(
        kind, n, listed, material_of, shadow, inv, fwd, where, given=given, sources=list(run)
    )


# ------------------------------------------------------------------- from the book's shapes


def _label(shape: object) -> str:
    name = type(shape).__name__
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _triangle_kind(shape: Shape) -> Kind | None:
    """The kind of a book triangle packed with others: exactly the reference's classes."""
    for name in ("smooth_triangle", "triangle"):
        if type(shape) is BY_NAME[name].reference:
            return BY_NAME[name]
    return None


def from_shape(shape: Shape, parent_inv: Matrix, parent_fwd: Matrix, where: str,
               own: bool = True) -> Node:  # fmt: skip
    """The node of one book shape under a parent (``own=False``: without the shape's own
    transform, as ``local_intersect`` sees it)."""
    if own:
        what = f"the transform of {where}"
        inv = compose(inverse_affine(shape.transform, what), parent_inv)
        fwd = compose(parent_fwd, shape.transform)
    else:
        inv, fwd = parent_inv, parent_fwd
    if isinstance(shape, BookGroup) and unchanged(type(shape), BookGroup, SHAPE_METHODS):
        return Group(_children(shape.children, inv, fwd, where), where)
    if isinstance(shape, CSG) and unchanged(type(shape), CSG, SHAPE_METHODS):
        left = from_shape(shape.left, inv, fwd, f"{where}.left")
        right = from_shape(shape.right, inv, fwd, f"{where}.right")
        return Csg(shape.operation, left, right, where)
    kind, changed = reference_kind(shape)
    if kind is None:
        raise UnknownShape(where, shape, changed)
    if kind.corners:
        return book_triangles([shape], kind, inv, fwd, where)
    params = {p.attribute: getattr(shape, p.attribute) for p in kind.parameters}
    shadow = bool(getattr(shape, "casts_shadow", True))
    return Leaf(kind, params, inv, fwd, shape.material, shadow, where, shape)


def _children(children: list[Shape], inv: Matrix, fwd: Matrix, where: str) -> list[Node]:
    """A group's children: runs of plain triangles of one class with no transform of their
    own (a mesh) as one ``Triangles`` each, read at once; any other child on its own."""
    nodes: list[Node] = []
    kinds = [_triangle_kind(child) if is_identity(child.transform) else None for child in children]
    start = 0
    for k in range(len(children) + 1):
        if k < len(children) and kinds[k] is not None and kinds[k] == kinds[start]:
            continue
        run_kind = kinds[start] if start < k else None
        if run_kind is not None:
            nodes.append(book_triangles(children[start:k], run_kind, inv, fwd, where))
            start = k
        if k < len(children) and kinds[k] is None:
            child = children[k]
            nodes.append(from_shape(child, inv, fwd, f"{where}.children[{k}] ({_label(child)})"))
            start = k + 1
    return nodes


def from_world(world: World) -> list[Node]:
    """Chapter 7: every object of a book world."""
    return [
        from_shape(s, identity_matrix, identity_matrix, f"world object {k} ({_label(s)})")
        for k, s in enumerate(world.objects)
    ]


# ------------------------------------------------------------- from a scene description


@dataclass(eq=False)  # a flattening's state: compared by identity
class _Described:
    """The state of flattening one description: its API, the inverses its load computed
    with the reference's ``inverse`` (``Scene.inverses``), and the materials made so far
    (one value per material the file gives, and one default)."""

    api: Mapping[str, Any]
    inverses: Mapping[int, tuple[Any, Any]]
    made: dict[int, Any] = field(default_factory=dict)
    default: Any = None

    def material(self, properties: dict[str, Any] | None) -> Any:
        if properties is None:
            if self.default is None:
                self.default = self.api["material"]()
            return self.default
        found = self.made.get(id(properties))
        if found is None:
            found = self.made[id(properties)] = make_material(self.api, properties)
        return found


def from_description(scene: Any) -> list[Node]:
    """Chapter 7: every shape of a scene description (``scene.Scene``), nothing built."""
    same = scene.api.get("inverse") is inverse  # the load inverted with the reference's
    state = _Described(scene.api, getattr(scene, "inverses", {}) if same else {})
    return [
        _from_spec(state, spec, identity_matrix, identity_matrix, None, True)
        for spec in scene.objects
    ]


def _from_spec(
    state: _Described, spec: ShapeSpec, parent_inv: Matrix, parent_fwd: Matrix,
    material: dict[str, Any] | None, shadow: bool,
) -> Node:  # fmt: skip
    where = spec.label
    if spec.transform is None:
        inv, fwd = parent_inv, parent_fwd
    else:
        what = f"the transform of {where}"
        inv = compose(inverse_affine(spec.transform, what, state.inverses), parent_inv)
        fwd = compose(parent_fwd, spec.transform)
    material = spec.material if spec.material is not None else material
    shadow = spec.shadow if spec.shadow is not None else shadow
    if spec.kind in GROUPS:
        return Group(
            [_from_spec(state, c, inv, fwd, material, shadow) for c in spec.children], where
        )
    if spec.kind == "csg":
        assert spec.left is not None and spec.right is not None and spec.operation is not None
        left = _from_spec(state, spec.left, inv, fwd, material, shadow)
        right = _from_spec(state, spec.right, inv, fwd, material, shadow)
        return Csg(spec.operation, left, right, where)
    if spec.kind == "obj":
        return _model(state, spec, inv, fwd, material, shadow)
    kind = BY_NAME[spec.kind]
    return Leaf(kind, kind.values(spec.params), inv, fwd, state.material(material), shadow, where)


def _model(
    state: _Described, spec: ShapeSpec, inv: Matrix, fwd: Matrix,
    material: dict[str, Any] | None, shadow: bool,
) -> Node:  # fmt: skip
    """Chapter 15: an OBJ model as ``obj_to_group`` makes it, a group per OBJ group, each
    a run of flat or smooth triangles (``Triangles``) from the mesh's arrays."""
    mesh = spec.mesh
    assert mesh is not None, "an OBJ model is read when it is added"
    made = state.material(material)
    smooth = mesh.smooth()
    parts: list[Node] = []
    start = 0
    for name, count in mesh.groups:
        where = f"{spec.label} (OBJ group {name or 'default'})"
        runs: list[Node] = []
        stop = start + count
        # runs of one kind (flat or smooth), in order
        cuts = [start, *(start + 1 + np.flatnonzero(np.diff(smooth[start:stop]))).tolist(), stop]
        for cut, end in itertools.pairwise(cuts):
            if cut == end:
                continue
            kind = BY_NAME["smooth_triangle" if smooth[cut] else "triangle"]
            n = end - cut
            run = Triangles(
                kind, n, [made], np.zeros(n, dtype=np.int64), np.full(n, shadow), inv, fwd,
                where, mesh=mesh, rows=slice(cut, end),
            )  # fmt: skip
            runs.append(run)
        parts.append(Group(runs, where))
        start = stop
    return Group(parts, spec.label)
