"""Packing a world, a shape or a camera into the flat arrays the kernels read (``layout``).

A world is packed once per render, from the tree ``variants.arrays.flatten`` makes of it
(of a scene description, with no book shape built, or of the book's shapes for the book's
API): every leaf becomes one primitive row (``primitives``); CSG trees become a range of
rows plus their operations in post-order (chapter 16). How the items are arranged is the
``bvh`` option (``variants.numba.bvh``): by default the groups are flattened and a
bounding-volume hierarchy is built over the items with a box (``sah``); ``groups`` keeps
each group's box as an item the ray can skip (chapter 14); ``off`` none. Every light is
packed (one row each, ``lights``). A run of triangles is packed at once with NumPy: a
million triangles in a fraction of a second; in a render, compactly (``tg``, ``tn``: a row
per stretch of one material, an item per triangle).

Only what the kernels know is packed: the kinds of ``scene.kinds`` (the test shape for the
book's API only) and of ``scene.pattern_kinds``; anything else is refused with a
``PackError`` naming the object, never approximated.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from raytracer.camera import Camera
from raytracer.lights import Light
from raytracer.materials import Material
from raytracer.matrices import Matrix, identity_matrix
from raytracer.patterns import Pattern
from raytracer.shapes.shape import Shape
from raytracer.shapes.sphere import Sphere
from raytracer.sky import Sky
from raytracer.world import World
from variants.arrays import flatten as F
from variants.arrays.rows import rgb, rows3x4
from variants.numba import layout as L
from variants.numba.bvh import (
    BALLS_MAX,
    DEFAULT,
    SAH,
    STRUCTURES,
    Hierarchy,
    build_into,
    nodes_as,
    outward32,
    wide_nodes,
)
from variants.numba.errors import PackError, refusal
from variants.numba.lights import light_rows
from variants.numba.packed import Packed, PackedCamera, flat
from variants.numba.primitives import Rows, inverse
from variants.numba.textures import TextureTable

OPERATIONS = {"union": L.OP_UNION, "intersection": L.OP_INTERSECTION, "difference": L.OP_DIFFERENCE}


def _stack(parts: list[Any], width: int, dtype: Any) -> np.ndarray:
    """Rows (lists) and blocks (2-D arrays) as one table, in order. ``parts`` is emptied
    as it goes, so that a block is let go once copied (a mesh's blocks are large)."""
    rows = sum(len(p) if isinstance(p, np.ndarray) else 1 for p in parts)
    if len(parts) == 1 and isinstance(parts[0], np.ndarray) and parts[0].dtype == dtype:
        return parts.pop()
    table = np.empty((rows, width), dtype=dtype)
    at = 0
    parts.reverse()
    pending: list[Any] = []
    while parts or pending:
        part = parts.pop() if parts else None
        if pending and (part is None or isinstance(part, np.ndarray)):
            table[at : at + len(pending)] = np.array(pending, dtype=dtype).reshape(-1, width)
            at += len(pending)
            pending = []
        if isinstance(part, np.ndarray):
            table[at : at + len(part)] = part
            at += len(part)
        elif part is not None:
            pending.append(part)
    return table


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


def _box(bounds: np.ndarray) -> tuple[float, ...]:
    return NO_BOX if np.isnan(bounds).any() else tuple(float(v) for v in bounds)


class _Packer(Rows):
    """Collects rows and items while walking a flattened scene (``variants.arrays.flatten``),
    then builds the arrays.

    Rows and items are kept as single rows (lists) or as blocks (arrays: a run of
    triangles, packed at once); ``bounds`` holds, per item, a box item's box or a leaf
    item's world-space box (NaN: none)."""

    def __init__(
        self, dtype: Any, allow_test_shape: bool, structure: str = DEFAULT,
        every_box: bool = False, compact: bool = False,
    ) -> None:  # fmt: skip
        if structure not in STRUCTURES:
            raise ValueError(f"numba: unknown bvh structure {structure!r}: {STRUCTURES}")
        super().__init__(dtype, allow_test_shape)
        self.structure = structure
        self.every_box = every_box
        self.compact = compact  # runs of triangles as compact triangles (``tg``)
        self.items: list[Any] = []
        self.bounds: list[Any] = []
        self.n_items = 0
        self.csg: list[list[int]] = []
        self.cs_size = 1
        self.cs_prims = 1

    # -- rows of compact triangles, and their items

    def compact_triangles(self, run: F.Triangles) -> np.ndarray:
        """Chapter 15 at scale, compactly: the triangles' numbers in ``tg`` (and ``tn``),
        one row per stretch of them with one material and shadow (their transform, material
        and where they are), one ``I_TRI`` item each. Returns their box (6,)."""
        n = run.count
        tg, bounds = run.geometry()  # p1, e1, e2, normal: the layout of ``tg``
        first_t, first_n = self.n_tg, self.n_tn
        self.tg.append(tg)
        self.n_tg += n
        normals = run.normals()
        smooth = normals is not None
        if normals is not None:
            self.tn.append(normals.reshape(n, L.NTN))
            self.n_tn += n
        items = np.zeros((n, L.NITEM), dtype=np.int64)
        items[:, L.ITEM_TYPE] = L.I_TRI
        items[:, L.ITEM_B] = np.arange(first_t, first_t + n)
        key = run.material_of * 2 + run.shadow.astype(np.int64)
        cuts = [0, *(1 + np.flatnonzero(np.diff(key))).tolist(), n]
        for a, b in itertools.pairwise(cuts):
            material = run.materials[int(run.material_of[a])]
            f, i = self.row(run.kind.number, run.inv, f"{run.where} (its triangle {a})",
                            material, bool(run.shadow[a]))  # fmt: skip
            i[L.TRI_FIRST] = first_t + a
            i[L.TN_FIRST] = first_n + a if smooth else -1
            i[L.TRI_COUNT] = b - a
            items[a:b, L.ITEM_A] = self.n_rows
            self.rows_f.append(f)
            self.rows_i.append(i)
            self.shapes.append(run.sources[a] if run.sources is not None else None)
            self.n_rows += 1
        self.capacity += n * run.kind.max_hits
        self.items.append(items)
        self.bounds.append(bounds)
        self.n_items += n
        return F.union([bounds])

    def item(self, values: list[int], bounds: Any) -> int:
        """Append one item with its bounds (6 values, NaN: none); returns its index."""
        self.items.append(values)
        self.bounds.append(bounds)
        self.n_items += 1
        return len(self.items) - 1

    # -- trees

    def add(self, node: F.Node) -> np.ndarray:
        """Add a node (leaf, triangles, group or CSG) as items; returns its world box (6,),
        NaN when it is unbounded."""
        if isinstance(node, F.Group):
            return self.add_group(node)
        if isinstance(node, F.Csg):
            return self.add_csg(node)
        if isinstance(node, F.Triangles) and self.compact:
            return self.compact_triangles(node)
        if isinstance(node, F.Triangles):
            first_row = self.n_rows
            bounds = self.triangles(node)
            items = np.zeros((node.count, L.NITEM), dtype=np.int64)
            items[:, L.ITEM_TYPE] = L.I_PRIM
            items[:, L.ITEM_A] = np.arange(first_row, first_row + node.count)
            self.items.append(items)
            self.bounds.append(bounds)
            self.n_items += node.count
            return F.union([bounds])
        row, box = self.leaf_rows(node)
        self.item([L.I_PRIM, row, 0, 0, 0], _box(box))
        return box

    def open_box(self) -> tuple[int, int]:
        """A box item (``groups``), filled in by ``close_box``: (its index in ``items``,
        its item number); (-1, -1) when the structure has no group boxes."""
        if self.structure != "groups":
            return -1, -1
        return self.item([L.I_BOX, 0, 0, 0, 0], NO_BOX), self.n_items - 1

    def close_box(self, opened: tuple[int, int], box: np.ndarray) -> None:
        """Fill in the box item ``opened`` (skip to here); drop it when it is useless."""
        at, number = opened
        if at < 0:
            return
        inside = self.n_items - number - 1
        if np.isnan(box).any() or inside < (1 if self.every_box else 2):
            self.items[at] = [L.I_SKIP, 0, 0, 0, 0]
            return
        self.items[at][L.ITEM_A] = self.n_items
        self.bounds[at] = _box(box)

    def add_group(self, g: F.Group) -> np.ndarray:
        opened = self.open_box()
        box = F.union([self.add(child) for child in g.children])
        self.close_box(opened, box)
        return box

    def add_csg(self, c: F.Csg) -> np.ndarray:
        opened = self.open_box()
        item = self.item([L.I_CSG, len(self.csg), 0, self.n_rows, 0], NO_BOX)
        capacity_before = self.capacity
        box = self.csg_tree(c)
        self.items[item][L.ITEM_B] = len(self.csg)
        self.items[item][L.ITEM_D] = self.n_rows
        self.bounds[item] = _box(box)
        self.cs_size = max(self.cs_size, self.capacity - capacity_before)
        self.cs_prims = max(self.cs_prims, self.n_rows - self.items[item][L.ITEM_C])
        self.close_box(opened, box)
        return box

    def csg_tree(self, node: F.Node) -> np.ndarray:
        """A CSG operand's rows (and operations, post-order); returns its box."""
        if isinstance(node, F.Csg):
            if node.operation not in OPERATIONS:
                raise PackError(f"numba: {node.where} has an unknown operation {node.operation!r}")
            start = self.n_rows
            left = self.csg_tree(node.left)
            mid = self.n_rows
            right = self.csg_tree(node.right)
            self.csg.append([start, mid, self.n_rows, OPERATIONS[node.operation]])
            return F.union([left, right])
        if isinstance(node, F.Group):
            return F.union([self.csg_tree(child) for child in node.children])
        if isinstance(node, F.Triangles):
            return F.union([self.triangles(node)])
        return self.leaf_rows(node)[1]

    # -- result

    def build(self, lights: Sequence[Light], started: float | None = None) -> Packed:
        """The arrays: rows, items (the balls taken out, empty boxes dropped, and for
        ``sah`` the hierarchy built), boxes, CSG operations, the lights, the textures."""
        dtype = self.dtype
        pf = _stack(self.rows_f, L.NF, np.float64)
        pi = _stack(self.rows_i, L.NI, np.int64)
        items = _stack(self.items, L.NITEM, np.int32)
        bounds = _stack(self.bounds, L.NBOX, np.float64)
        # chapter 5: world spheres reached by a plain item (not in a CSG tree) leave the
        # items for the ball list (``sah``: while there are few of them), in item order
        prim = items[:, L.ITEM_TYPE] == L.I_PRIM
        ball = np.zeros(len(items), dtype=bool)
        ball[prim] = pi[items[prim, L.ITEM_A], L.WORLD_SPHERE] != 0
        if self.structure in SAH and ball.sum() >= BALLS_MAX:
            ball[:] = False
        ball_rows = items[ball, L.ITEM_A]
        items[ball, L.ITEM_TYPE] = L.I_SKIP
        items, bounds = _drop_skips(items, bounds)
        hierarchy = Hierarchy(self.structure)
        nodes = np.zeros((0, L.NNODE))
        if self.structure in SAH:
            given = [bounds]
            del bounds  # given away: _hierarchy lets it go as soon as it can
            with_nodes = self.compact and self.structure in ("sah", "sah4")
            items, boxes, nodes, hierarchy = _hierarchy(items, given, with_nodes)
        else:
            box = np.flatnonzero(items[:, L.ITEM_TYPE] == L.I_BOX)
            boxes = bounds[box].reshape(len(box), L.NBOX)
            items[box, L.ITEM_D] = np.arange(len(box))
            if self.structure == "groups":
                hierarchy = Hierarchy("groups", boxes=len(box))
        balls = np.zeros((L.NBALL, len(ball_rows)), dtype=dtype)
        balls[L.B_X : L.B_Z + 1] = pf[ball_rows, L.SPH_CENTER : L.SPH_CENTER + 3].T
        balls[L.B_R2] = pf[ball_rows, L.SPH_R2]
        balls[L.B_SHADOW] = pi[ball_rows, L.CASTS_SHADOW]
        balls[L.B_PRIM] = ball_rows
        csg = np.array(self.csg, dtype=np.int64).reshape(len(self.csg), L.NCSG)
        rows, sequences = light_rows(lights, dtype)
        tg = _stack(self.tg, L.NTG, np.float64).astype(dtype, copy=False)
        tn = _stack(self.tn, L.NTN, np.float64).astype(dtype, copy=False)
        seconds = time.perf_counter() - started if started is not None else 0.0
        wide = self.structure == "sah4" and len(nodes) > 0
        nodes = wide_nodes(nodes, dtype) if wide else nodes_as(nodes, dtype)
        boxes, nodes, at = _box_table(_outward(boxes, dtype), nodes)
        items[items[:, L.ITEM_TYPE] == L.I_NODES, L.ITEM_B] = at
        items[items[:, L.ITEM_TYPE] == L.I_NODES, L.ITEM_C] = L.WIDE if wide else 0
        return Packed(
            pf.astype(dtype, copy=False), pi, items, boxes, csg,
            rows, self.shapes, max(self.capacity, 1), self.cs_size,
            self.cs_prims, balls, hierarchy, seconds, textures=self.textures,
            light_values=sequences, tg=tg, tn=tn, nodes=nodes,
        )  # fmt: skip


def _box_table(boxes: np.ndarray, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """(boxes, nodes, where the nodes start) as views of one flat table, the nodes after
    the boxes (what the kernels take: ``Packed.box_table``), so that a render copies
    neither: the builder's own table (``bvh.build_into``), or a new one (float32)."""
    if not len(nodes):
        return boxes, nodes, 0
    table = boxes.base
    if table is None or table is not nodes.base or table.ndim != 1:
        table = np.empty(boxes.size + nodes.size, dtype=boxes.dtype)
        table[: boxes.size] = boxes.reshape(-1)
        table[boxes.size :] = nodes.reshape(-1)
        boxes = table[: boxes.size].reshape(boxes.shape)
        nodes = table[boxes.size :].reshape(nodes.shape)
    return boxes, nodes, (nodes.ctypes.data - table.ctypes.data) // table.itemsize


def _drop_skips(items: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The items without I_SKIP ones and without boxes left with nothing inside; a box's
    jump target moves to the first item kept at or after it."""
    kinds = items[:, L.ITEM_TYPE]
    if not ((kinds == L.I_SKIP) | (kinds == L.I_BOX)).any():
        return items, bounds
    leaf = (kinds == L.I_PRIM) | (kinds == L.I_CSG) | (kinds == L.I_TRI)
    leaves_before = np.concatenate([[0], np.cumsum(leaf)])
    box = np.flatnonzero(kinds == L.I_BOX)
    empty = leaves_before[items[box, L.ITEM_A]] - leaves_before[box + 1] == 0
    items[box[empty], L.ITEM_TYPE] = L.I_SKIP
    kept = items[:, L.ITEM_TYPE] != L.I_SKIP
    moved = np.concatenate([[0], np.cumsum(kept)])  # old index -> items kept before it
    box = np.flatnonzero(items[:, L.ITEM_TYPE] == L.I_BOX)
    items[box, L.ITEM_A] = moved[items[box, L.ITEM_A]]
    return items[kept], bounds[kept]


UNIT_CHUNK = 1 << 16  # units rounded to float32 at a time (no full-size float64 copy)


def _hierarchy(
    items: np.ndarray, given: list[np.ndarray], compact: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray, Hierarchy]:
    """``sah``: the unbounded items first, then the hierarchy over the others, written
    straight into the final table (items, boxes, compact nodes, what it is). ``given``:
    [the items' bounds], taken out of the list and let go once the units' float32 boxes
    are made from them; ``compact``: a hierarchy over compact triangles alone is also
    given as compact nodes, after an I_NODES item (``bvh.build_into``)."""
    bounds = given.pop()
    bounded = ~np.isnan(bounds).any(axis=1)
    outside = np.flatnonzero(~bounded)
    order = np.flatnonzero(bounded).astype(np.int64)
    n = len(order)
    if n < 2:
        ordered = np.concatenate([items[outside], items[order]])
        return (
            ordered,
            np.zeros((0, L.NBOX)),
            np.zeros((0, L.NNODE)),
            Hierarchy("sah", n, len(outside)),
        )
    units = np.empty((n, L.BVH_UNIT), dtype=np.float32)
    for at in range(0, n, UNIT_CHUNK):
        units[at : at + UNIT_CHUNK] = outward32(bounds[order[at : at + UNIT_CHUNK]])
    del bounds
    # a hierarchy over compact triangles only gets its compact nodes too (``I_NODES``)
    nodes_item = compact and bool((items[order, L.ITEM_TYPE] == L.I_TRI).all())
    base = len(outside) + nodes_item
    out = np.empty((base + 2 * n - 1, L.NITEM), dtype=np.int32)
    out[: len(outside)] = items[outside]
    count, boxes, nodes, hierarchy = build_into(items, units, order, out, base, nodes_item)
    if nodes_item:
        out[base - 1] = (L.I_NODES, count, 0, 0, 0)  # ITEM_B: set with the box table
    return out[:count], boxes, nodes, replace(hierarchy, outside=len(outside))


def _pack(
    nodes: Sequence[F.Node], lights: Sequence[Light], dtype: Any, allow_test_shape: bool,
    structure: str, every_box: bool = False, started: float | None = None,
    compact: bool = False,
) -> Packed:  # fmt: skip
    packer = _Packer(dtype, allow_test_shape, structure, every_box, compact)
    for node in nodes:
        packer.add(node)
    return packer.build(lights, started)


def _flattened(make: Any, *args: Any) -> Any:
    """``make(*args)`` (a ``flatten`` function), its errors in the kernels' words."""
    try:
        return make(*args)
    except F.FlattenError as error:
        raise refusal(error) from None


def pack_world(
    world: World,
    dtype: Any = np.float64,
    *,
    allow_test_shape: bool = False,
    structure: str = DEFAULT,
    compact: bool = False,
) -> Packed:
    """Chapter 7: every object of the book's ``world`` and its lights, packed; ``structure``:
    how the items are arranged (``bvh``); ``compact``: runs of triangles as compact
    triangles (a render's tables; the book's API wants a row per shape)."""
    if not isinstance(world, World):
        raise PackError(f"numba: expected a World, got {type(world).__name__}")
    started = time.perf_counter()
    nodes = _flattened(F.from_world, world)
    lights = list(world.lights)
    packed = _pack(
        nodes, lights, dtype, allow_test_shape, structure, started=started, compact=compact
    )
    packed.sky = pack_sky(world.sky, dtype)
    return packed


def pack_scene(scene: Any, dtype: Any = np.float64, *, structure: str = DEFAULT) -> Packed:
    """Chapter 7: a scene description (``scene.Scene``) packed straight from its entities
    and arrays, no book shape built."""
    started = time.perf_counter()
    nodes = _flattened(F.from_description, scene)
    lights = list(scene.lights)
    packed = _pack(nodes, lights, dtype, False, structure, started=started, compact=True)
    packed.sky = pack_sky(scene.sky, dtype)
    return packed


def pack_sky(s: Sky | None, dtype: Any = np.float64) -> np.ndarray:
    """Chapter 21 here (beyond the book): the sky's horizon and zenith colours (``layout``
    SKY_*); black all around without one, as ``raytracer.sky`` sees it."""
    table = np.zeros(L.NSKY, dtype=dtype)
    if s is not None:
        table[L.SKY_HORIZON : L.SKY_HORIZON + 3] = rgb(s.horizon)
        table[L.SKY_ZENITH : L.SKY_ZENITH + 3] = rgb(s.zenith)
    return table


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
    nodes = [
        _flattened(F.from_shape, s, identity_matrix, identity_matrix, _label(s), own_transform)
        for s in shapes
    ]
    return _pack(nodes, [], dtype, True, structure, every_box)


def world_inverse(shape: Shape) -> Matrix:
    """Chapter 14: world space to ``shape``'s object space, through all its parents."""
    where = _label(shape)
    inv = inverse(shape.transform, f"the transform of {where}")
    parent = shape.parent
    while parent is not None:
        what = f"the transform of {_label(parent)}, a parent of {where}"
        inv = F.compose(inv, inverse(parent.transform, what))
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
    if not leaf:
        target = Sphere(material=target.material)
    node = _flattened(F.from_shape, target, inv, identity_matrix, where, False)
    if isinstance(node, F.Leaf):
        m = material if material is not None else node.material
        packer.leaf_rows(dataclasses.replace(node, material=m), pattern, bound=False)
    elif isinstance(node, F.Triangles):
        if material is not None:
            node = dataclasses.replace(node, materials=[material])
        packer.triangles(node, pattern)
    else:
        raise PackError(f"numba: {where} has no surface of its own")
    built = packer.build([])
    return flat(built.pf), flat(built.pi)


def _label(shape: object) -> str:
    return f"a {type(shape).__name__}"


_CAMERA_INVERSES: dict[int, tuple[Any, Any]] = {}  # id -> (transform, its inverse)


def camera_inverse(m: Any) -> Any:
    """The reference's inverse of a camera transform, once per transform (a frame is
    prepared for every render, its camera's inverse a few hundred Python operations). A
    transform is immutable and kept beside its inverse: the same object has the same one."""
    found = _CAMERA_INVERSES.get(id(m))
    if found is not None and found[0] is m:
        return found[1]
    inv = inverse(m, "the camera transform")
    if len(_CAMERA_INVERSES) >= 16:
        _CAMERA_INVERSES.clear()
    _CAMERA_INVERSES[id(m)] = (m, inv)
    return inv


def pack_camera(c: Camera, dtype: Any = np.float64) -> PackedCamera:
    """The inverse view transform (the reference's), half extents and pixel size."""
    inv = camera_inverse(c.transform)
    row = [*rows3x4(inv), float(c.half_width), float(c.half_height), float(c.pixel_size)]
    return PackedCamera(np.array(row, dtype=dtype), int(c.hsize), int(c.vsize))
