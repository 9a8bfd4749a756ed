"""The numba variant's bounding-volume hierarchy (``variants.numba.bvh``): the same pictures
with ``bvh=sah`` (the default), ``bvh=groups`` and ``bvh=off``, and as ``naive`` draws them;
the hierarchy's invariants; the fast packing of meshes; worlds with nothing to build over.

The three structures change which items a ray visits and in what order, never which hit
it keeps (a tie goes to the earlier primitive), nor a shadow: their pictures are compared
for equality, bit for bit; against ``naive`` with ``test_numba``'s float64 tolerance.
"""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from reference_pixels import lattice, naive_at, picture_at

from raytracer.camera import RenderSettings
from raytracer.materials import material
from raytracer.matrices import Matrix
from scene import load_scene
from variants.arrays import flatten
from variants.numba import bvh, bvh_kernel
from variants.numba import layout as L
from variants.numba import pack as numba_pack
from variants.numba.bvh import BALLS_MAX, build_tree
from variants.numba.features import analyse
from variants.numba.pack import pack_world, world_inverse
from variants.numba.packed import Packed
from variants.registry import VariantError, load_variant

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes"
FLOAT64_WORST = 1e-6  # as in test_numba
ONE_STEP = 1.0 / 255.0
STRUCTURES = ("numba", "numba[bvh=sah4]", "numba[bvh=groups]", "numba[bvh=off]")


def _icosahedron(api: Any, smooth: bool, splits: int = 1) -> Any:
    """A unit icosphere of triangles (smooth: with the corner normals) in a group."""
    t = (1 + math.sqrt(5)) / 2
    raw = [
        (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
        (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1),
    ]  # fmt: skip
    verts = [tuple(c / math.sqrt(sum(v * v for v in p)) for c in p) for p in raw]
    faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
        (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
        (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1),
    ]  # fmt: skip
    for _ in range(splits):
        split = []
        for a, b, c in faces:
            mids = []
            for i, j in ((a, b), (b, c), (c, a)):
                m = [(verts[i][k] + verts[j][k]) / 2 for k in range(3)]
                length = math.sqrt(sum(v * v for v in m))
                verts.append(tuple(v / length for v in m))
                mids.append(len(verts) - 1)
            ab, bc, ca = mids
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    g = api["group"]()
    for a, b, c in faces:
        p = [api["point"](*verts[k]) for k in (a, b, c)]
        if smooth:
            n = [api["vector"](*verts[k]) for k in (a, b, c)]
            api["add_child"](g, api["smooth_triangle"](*p, *n))
        else:
            api["add_child"](g, api["triangle"](*p))
    return g


def mixed(api: Any, spheres: int = 6) -> tuple[Any, Any]:
    """Groups in groups, a CSG shape inside a group, planes, flat and smooth triangles, balls
    and ellipsoids, a cylinder, a reflective floor, a glass sphere, shadows; 24x18."""
    c = api["color"]
    floor = api["plane"]()
    floor.material = material(color=c(0.9, 0.9, 0.8), reflective=0.2, specular=0)
    wall = api["plane"]()
    api["set_transform"](wall, api["translation"](0, 0, 8) * api["rotation_x"](math.pi / 2))
    outer = api["group"]()
    api["set_transform"](outer, api["translation"](0.3, 0, 0.5) * api["rotation_y"](0.4))
    flat = _icosahedron(api, smooth=False)
    api["set_transform"](flat, api["translation"](-1.2, 0.8, 0) * api["scaling"](0.7, 0.7, 0.7))
    for child in flat.children:
        child.material = material(color=c(0.9, 0.4, 0.2))
    smooth = _icosahedron(api, smooth=True)
    api["set_transform"](smooth, api["translation"](1.1, 0.9, -0.4) * api["scaling"](0.8, 0.8, 0.8))
    for child in smooth.children:
        child.material = material(color=c(0.2, 0.5, 0.9), specular=0.8, shininess=120)
    inner = api["group"]()
    api["add_child"](inner, flat)
    api["add_child"](inner, smooth)
    api["add_child"](outer, inner)
    left = api["cube"]()
    right = api["sphere"]()
    api["set_transform"](right, api["scaling"](1.3, 1.3, 1.3))
    carved = api["csg"]("difference", left, right)
    api["set_transform"](carved, api["translation"](0, 0.5, -1.6) * api["scaling"](0.4, 0.4, 0.4))
    for shape in (left, right):
        shape.material = material(color=c(0.3, 0.8, 0.4))
    api["add_child"](outer, carved)
    cyl = api["cylinder"]()
    cyl.minimum, cyl.maximum, cyl.closed = 0.0, 1.0, True
    api["set_transform"](cyl, api["translation"](2.2, 0, 1) * api["scaling"](0.3, 1, 0.3))
    api["add_child"](outer, cyl)
    balls = api["group"]()
    for k in range(spheres):
        s = api["sphere"]()
        x, z = -2.5 + 5.0 * (k % 8) / 7, -2.6 + 0.5 * (k // 8)
        scale = api["scaling"](0.15, 0.15, 0.15) if k % 5 else api["scaling"](0.12, 0.2, 0.12)
        api["set_transform"](s, api["translation"](x, 0.2, z) * scale)
        s.material = material(color=c(0.1 * (k % 10), 0.6, 1 - 0.1 * (k % 10)))
        api["add_child"](balls, s)
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](-0.2, 0.5, -2.2) * api["scaling"](0.4, 0.4, 0.4))
    w = api["world"]()
    w.objects.extend([floor, wall, outer, balls, glass])
    w.light = api["point_light"](api["point"](-4, 7, -6), c(1, 1, 1))
    view = api["view_transform"](
        api["point"](0, 2.2, -6), api["point"](0, 0.6, 0), api["vector"](0, 1, 0)
    )
    return replace(api["camera"](24, 18, math.pi / 3), transform=view), w


def many_balls(api: Any) -> tuple[Any, Any]:
    """``mixed`` with enough spheres (one in five an ellipsoid) that they join the
    hierarchy instead of the balls."""
    return mixed(api, spheres=BALLS_MAX * 5 // 4 + 8)


def _render(name: str, build: Any) -> np.ndarray:
    variant = load_variant(name)
    camera, world = build(variant.api)
    image = variant.api["render"](camera, world, RenderSettings())
    pixel_at = variant.api["pixel_at"]
    rows = [
        [(p.red, p.green, p.blue) for p in (pixel_at(image, x, y) for x in range(image.width))]
        for y in range(image.height)
    ]
    return np.array(rows, dtype=np.float64)


_NAIVE: dict[str, np.ndarray] = {}


@pytest.mark.parametrize("build", [mixed, many_balls], ids=["mixed", "many-balls"])
def test_every_structure_draws_the_same_picture_as_naive(build: Any) -> None:
    """The three structures' whole pictures bit for bit; naive's (about 0.07 CPU s a pixel
    here) at a quarter of the pixels, every other one of every other row
    (tests/reference_pixels.py), against numba's there."""
    pictures = {name: _render(name, build) for name in STRUCTURES}
    height, width = pictures["numba"].shape[:2]
    pixels = lattice(width, height)
    if build.__name__ not in _NAIVE:
        _NAIVE[build.__name__] = naive_at(build, RenderSettings(), pixels)
    expected = np.clip(_NAIVE[build.__name__], 0, 1)
    distinct = {tuple(np.round(p, 3)) for p in expected}
    assert len(distinct) > 20, "the scene should not be blank"
    for name in STRUCTURES[1:]:
        assert np.array_equal(pictures[name], pictures["numba"]), f"{name} differs from sah"
    difference = np.abs(np.clip(picture_at(pictures["numba"], pixels), 0, 1) - expected)
    worst = float(difference.max())
    print(f"{build.__name__}: max difference from naive {worst:.3g}")
    assert worst <= FLOAT64_WORST
    assert int((difference.max(axis=1) > ONE_STEP).sum()) == 0


def test_the_scenes_use_what_they_should() -> None:
    """``mixed`` keeps its spheres as balls and builds a hierarchy over the rest; with
    ``BALLS_MAX`` spheres or more they are in the hierarchy; ``groups`` keeps group boxes;
    ``off`` has no box at all."""
    api = load_variant("naive").api
    _, w = mixed(api)
    packed = pack_world(w)
    assert packed.balls.shape[1] > 0
    assert packed.hierarchy.structure == "sah" and packed.hierarchy.nodes > 10
    assert packed.hierarchy.outside == 2  # the floor and the wall
    assert "HAS_BOXES" in analyse(packed).flags
    _, crowded = many_balls(api)
    assert pack_world(crowded).balls.shape[1] == 0
    assert pack_world(crowded, structure="groups").balls.shape[1] > BALLS_MAX
    grouped = pack_world(w, structure="groups")
    assert grouped.hierarchy.structure == "groups" and grouped.hierarchy.boxes > 0
    off = pack_world(w, structure="off")
    assert L.I_BOX not in set(off.items[:, L.ITEM_TYPE].tolist())
    assert "HAS_BOXES" not in analyse(off).flags


# -------------------------------------------------------------------- the invariants


def _world_box(shape: Any) -> np.ndarray:
    """A leaf shape's world-space box from its corners (through every parent): a
    triangle's three, any other shape's box's eight (the reference's ``local_bounds``)."""
    if hasattr(shape, "p1"):
        points = [(p.x, p.y, p.z) for p in (shape.p1, shape.p2, shape.p3)]
    else:
        box = shape.local_bounds()
        lo, hi = box.min, box.max
        points = [(x, y, z) for x in (lo.x, hi.x) for y in (lo.y, hi.y) for z in (lo.z, hi.z)]
    assert all(math.isfinite(v) for p in points for v in p)
    inv = np.array(world_inverse(shape).rows, dtype=np.float64)
    fwd = np.linalg.inv(inv)
    corners = np.array([fwd @ np.array([*p, 1.0]) for p in points])[:, :3]
    return np.concatenate([corners.min(axis=0), corners.max(axis=0)])


def _triangle_of(packed: Packed, k: int, first: Any) -> Any:
    """The book's triangle k places after ``first`` in its parent group (a run of compact
    triangles holds its parent's children in order)."""
    siblings = first.parent.children
    return siblings[siblings.index(first) + k]


def _contains(outer: np.ndarray, inner: np.ndarray) -> bool:
    slack = 1e-9 * (1 + np.abs(inner).max())
    return bool((outer[:3] <= inner[:3] + slack).all() and (outer[3:] >= inner[3:] - slack).all())


def _check_hierarchy(packed: Packed) -> None:
    """Every primitive once; boxes hold what they skip; jumps point past their subtree;
    an inner node's second child starts where its first ends; the depth stays within
    ``BVH_DEPTH``."""
    items, boxes = packed.items, packed.boxes
    n = len(items)
    seen: list[int] = [int(r) for r in packed.balls[L.B_PRIM]]
    triangles: list[int] = []  # compact ones
    for item in items:
        if item[L.ITEM_TYPE] == L.I_PRIM:
            seen.append(int(item[L.ITEM_A]))
        elif item[L.ITEM_TYPE] == L.I_CSG:
            seen.extend(range(int(item[L.ITEM_C]), int(item[L.ITEM_D])))
        elif item[L.ITEM_TYPE] == L.I_TRI:
            triangles.append(int(item[L.ITEM_B]))
            first, count = packed.pi[item[L.ITEM_A], [L.TRI_FIRST, L.TRI_COUNT]]
            assert first <= item[L.ITEM_B] < first + count, "a triangle of its run"
    runs = packed.pi[:, L.TRI_FIRST] >= 0
    expected = np.flatnonzero(~runs).tolist()
    assert sorted(seen) == expected, "every primitive exactly once"
    assert sorted(triangles) == list(range(len(packed.tg))), "every triangle exactly once"
    assert len(boxes) == int((items[:, L.ITEM_TYPE] == L.I_BOX).sum())
    box_of = {i: int(items[i, L.ITEM_D]) for i in range(n) if items[i, L.ITEM_TYPE] == L.I_BOX}
    assert sorted(box_of.values()) == list(range(len(boxes))), "a box row per box item"

    def end_of(i: int) -> int:  # one past item i's subtree
        return int(items[i, L.ITEM_A]) if items[i, L.ITEM_TYPE] == L.I_BOX else i + 1

    depth = [0] * n
    for i in range(n):
        if items[i, L.ITEM_TYPE] != L.I_BOX:
            continue
        skip = end_of(i)
        assert i + 2 <= skip <= n, f"box {i} skips to {skip}"
        j = i + 1
        children = []
        while j < skip:  # the subtree is a sequence of whole subtrees
            children.append(j)
            depth[j] = depth[i] + 1
            assert end_of(j) <= skip, f"item {j} runs past its parent {i}"
            j = end_of(j)
        assert j == skip
        outer = boxes[box_of[i]]
        for j in range(i + 1, skip):
            if items[j, L.ITEM_TYPE] == L.I_BOX:
                assert _contains(outer, boxes[box_of[j]]), f"box {i} does not hold box {j}"
            elif items[j, L.ITEM_TYPE] in (L.I_PRIM, L.I_TRI):
                shape = packed.shapes[int(items[j, L.ITEM_A])]
                if items[j, L.ITEM_TYPE] == L.I_TRI:  # the run's first triangle's shape:
                    first = packed.pi[items[j, L.ITEM_A], L.TRI_FIRST]
                    shape = _triangle_of(packed, int(items[j, L.ITEM_B]) - int(first), shape)
                assert _contains(outer, _world_box(shape)), f"box {i} misses item {j}"
        if items[i, L.ITEM_C] > 0:  # an inner node of the hierarchy: two children
            assert len(children) == 2
            assert int(items[i, L.ITEM_B]) == children[1]
            assert 1 <= items[i, L.ITEM_C] <= 3
    assert max(depth, default=0) < L.BVH_DEPTH


def test_the_hierarchy_of_a_mixed_world_keeps_its_invariants() -> None:
    api = load_variant("naive").api
    for build in (mixed, many_balls):
        _, w = build(api)
        for structure in ("sah", "groups", "off"):
            _check_hierarchy(pack_world(w, structure=structure))
            _check_hierarchy(pack_world(w, structure=structure, compact=True))


def test_a_mesh_hierarchy_keeps_its_invariants_and_reports_itself() -> None:
    api = load_variant("naive").api
    mesh = _icosahedron(api, smooth=True, splits=3)  # 1,280 triangles
    api["set_transform"](mesh, api["translation"](1, 2, 3) * api["rotation_z"](0.3))
    w = api["world"]()
    w.objects.append(mesh)
    packed = pack_world(w)
    _check_hierarchy(packed)
    _check_hierarchy(pack_world(w, compact=True))
    h = packed.hierarchy
    assert (h.units, h.outside) == (1280, 0)
    assert h.nodes >= 2 * 1280 / bvh.LEAF_MAX - 1
    assert h.leaves <= 1280 and h.nodes == 2 * h.leaves - 1  # a binary tree
    assert 10 <= h.depth < L.BVH_DEPTH
    assert h.seconds >= 0 and packed.seconds >= h.seconds
    line = h.describe()
    assert line.startswith("bvh: SAH over 1,280 primitives, ") and " nodes " in line
    assert "built in" in line


def test_degenerate_units_still_give_a_shallow_tree() -> None:
    """5,000 units with the same box (no split separates them): stretches are halved."""
    n = 5000
    unit_items = np.zeros((n, L.NITEM), dtype=np.int32)
    unit_items[:, L.ITEM_A] = np.arange(n)
    unit_boxes = np.tile([0.0, 0.0, 0.0, 1.0, 1.0, 1.0], (n, 1))
    items, boxes, h = build_tree(unit_items, unit_boxes)
    prims = items[items[:, L.ITEM_TYPE] == L.I_PRIM, L.ITEM_A]
    assert sorted(prims.tolist()) == list(range(n))
    assert h.depth < L.BVH_DEPTH
    assert h.depth <= math.ceil(math.log2(n)) + 1
    assert len(boxes) == (items[:, L.ITEM_TYPE] == L.I_BOX).sum()
    assert (boxes == [0, 0, 0, 1, 1, 1]).all()


def test_the_builder_constants_are_the_layout_ones() -> None:
    """``bvh_kernel`` keeps its own copies (numba's cache sees only its own file)."""
    assert bvh_kernel.NITEM == L.NITEM and bvh_kernel.NBOX == L.NBOX
    assert (bvh_kernel.ITEM_TYPE, bvh_kernel.ITEM_A, bvh_kernel.ITEM_B) == (
        L.ITEM_TYPE, L.ITEM_A, L.ITEM_B,
    )  # fmt: skip
    assert (bvh_kernel.ITEM_C, bvh_kernel.ITEM_D, bvh_kernel.I_BOX) == (
        L.ITEM_C, L.ITEM_D, L.I_BOX,
    )  # fmt: skip
    assert bvh_kernel.BINS == L.BVH_BINS and bvh_kernel.STACK == L.BVH_STACK
    assert bvh_kernel.UNIT_WIDTH == L.BVH_UNIT and bvh_kernel.STATS == L.BVH_STATS
    assert bvh_kernel.WORK == L.BVH_WORK and bvh_kernel.FWORK == L.BVH_FWORK
    assert (bvh_kernel.NODE_A, bvh_kernel.NODE_C, bvh_kernel.NNODE) == (L.NODE_A, L.NODE_C, L.NNODE)
    assert L.MIN_SCRATCH >= 2 * L.BVH_DEPTH  # the hit ray's range stack


# ------------------------------------------------------------ packing meshes at scale


def test_a_mesh_packs_to_the_same_rows_one_at_a_time_and_at_once(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The fast path for a group's triangles makes the rows ``leaf_row`` makes (the
    bounding sphere up to rounding), in the same order, with the same world boxes."""
    api = load_variant("naive").api
    w = api["world"]()
    for smooth in (False, True):
        mesh = _icosahedron(api, smooth=smooth, splits=1)
        api["set_transform"](mesh, api["translation"](2, 0, 1) * api["scaling"](1, 2, 1))
        mesh.children[3].material = material(color=api["color"](1, 0, 0))
        mesh.children[5].casts_shadow = False
        api["set_transform"](mesh.children[7], api["translation"](0, 0.1, 0))  # not plain
        w.objects.append(mesh)
    fast = pack_world(w, structure="off")
    monkeypatch.setattr(flatten, "_triangle_kind", lambda shape: None)  # every one alone
    slow = pack_world(w, structure="off")
    assert [id(s) for s in fast.shapes] == [id(s) for s in slow.shapes]
    assert np.array_equal(fast.pi, slow.pi)
    assert np.array_equal(fast.items, slow.items)
    bound = slice(L.BOUND, L.BOUND + 4)
    columns = [c for c in range(L.NF) if not bound.start <= c < bound.stop]
    assert np.array_equal(fast.pf[:, columns], slow.pf[:, columns])
    assert np.allclose(fast.pf[:, bound], slow.pf[:, bound], rtol=1e-12, atol=1e-12)
    assert fast.pi[3, L.CASTS_SHADOW] == 1 and fast.pi[5, L.CASTS_SHADOW] == 0
    assert fast.pf[3, L.COLOR + 1] == 0.0 and fast.pf[4, L.COLOR + 1] == 1.0


def test_float32_boxes_are_rounded_outwards() -> None:
    boxes = np.array([[0.1, -0.3, 1 / 3, 0.7, 1e-3, 2 / 3]], dtype=np.float64)
    rounded = numba_pack._outward(boxes, np.float32)
    assert rounded.dtype == np.float32
    assert (rounded[:, :3].astype(np.float64) <= boxes[:, :3]).all()
    assert (rounded[:, 3:].astype(np.float64) >= boxes[:, 3:]).all()


# ------------------------------------------------- nothing to build over, ties, options


@pytest.mark.parametrize("name", STRUCTURES)
def test_an_empty_world_and_a_world_of_planes(name: str) -> None:
    variant = load_variant(name)
    api = variant.api
    camera = replace(api["camera"](6, 4, math.pi / 3), transform=api["view_transform"](
        api["point"](0, 1, -5), api["point"](0, 0, 0), api["vector"](0, 1, 0)
    ))  # fmt: skip
    empty = api["world"]()
    empty.light = api["point_light"](api["point"](0, 5, -5), api["color"](1, 1, 1))
    image = api["render"](camera, empty, RenderSettings())
    assert all(
        api["pixel_at"](image, x, y) == api["color"](0, 0, 0) for x in range(6) for y in range(4)
    )
    planes = api["world"]()
    planes.light = empty.light
    for k in range(3):
        p = api["plane"]()
        api["set_transform"](p, api["translation"](0, -1 - k, 0))
        p.material = material(color=api["color"](0.2 * (k + 1), 0.5, 0.5))
        planes.objects.append(p)
    packed = pack_world(planes, structure=variant.tracer.options.bvh)
    assert len(packed.items) == 3 and L.I_BOX not in packed.items[:, L.ITEM_TYPE]
    assert packed.hierarchy.nodes == 0
    seen = _render_world(variant, camera, planes)
    naive = _render_world(load_variant("naive"), camera, planes)
    assert np.abs(seen - naive).max() <= FLOAT64_WORST
    assert seen[3, 0, 0] == pytest.approx(naive[3, 0, 0]) and seen[3, 0, 0] > 0


def _render_world(variant: Any, camera: Any, w: Any) -> np.ndarray:
    image = variant.api["render"](camera, w, RenderSettings())
    at = variant.api["pixel_at"]
    return np.array(
        [[(lambda p: (p.red, p.green, p.blue))(at(image, x, y)) for x in range(image.width)]
         for y in range(image.height)]
    )  # fmt: skip


def test_a_tie_goes_to_the_earlier_object_in_any_order() -> None:
    """Two identical ellipsoids (one transform, so every t is the same) in a hierarchy:
    the hit is the first in the world's order, as in the reference's stable sort, whatever
    order the hierarchy visits them in."""
    for reverse in (False, True):
        results = {}
        for name in ("naive", *STRUCTURES):
            api = load_variant(name).api
            shapes = []
            for k in range(6):
                s = api["sphere"]()
                api["set_transform"](s, api["translation"](0, 0, k % 2) * api["scaling"](1, 2, 1))
                s.material = material(
                    color=api["color"](k / 5, 0, 1), ambient=1, diffuse=0, specular=0
                )
                shapes.append(s)
            w = api["world"]()
            w.objects.extend(reversed(shapes) if reverse else shapes)
            w.light = api["point_light"](api["point"](0, 0, -10), api["color"](1, 1, 1))
            c = api["color_at"](w, api["ray"](api["point"](0, 0, -5), api["vector"](0, 0, 1)))
            results[name] = (c.red, c.green, c.blue)
        assert len(set(results.values())) == 1, results
        assert results["naive"][0] == pytest.approx(0.8 if reverse else 0.0)


def test_the_option_is_named_and_checked() -> None:
    assert load_variant("numba[bvh=off]").name == "numba[bvh=off]"
    assert load_variant("numba[bvh=groups,threads=1]").name == "numba[bvh=groups,threads=1]"
    assert load_variant("numba[bvh=sah]").name == "numba"
    expected = "bvh='octree' must be one of sah, sah4, sah-items, groups, off"
    with pytest.raises(VariantError, match=expected):
        load_variant("numba[bvh=octree]")


def test_explain_says_how_the_items_are_arranged() -> None:
    api = load_variant("naive").api
    _, w = mixed(api)
    for name, expected in (
        ("numba", "bvh: SAH over "),
        ("numba[bvh=groups]", "bvh: the scene's own groups"),
        ("numba[bvh=off]", "bvh: off (every ray visits every item)"),
    ):
        printed = load_variant(name).tracer.explain(w)
        assert expected in printed, printed
        assert "packed in " in printed


def test_the_book_api_answers_alike_through_every_structure() -> None:
    """``intersect_world`` and ``intersect`` on a group list the same intersections."""
    found = {}
    for name in ("naive", *STRUCTURES):
        api = load_variant(name).api
        _, w = mixed(api)
        r = api["ray"](api["point"](-0.8, 0.8, -5), api["vector"](0, 0, 1))
        xs = api["intersect_world"](w, r)
        group_xs = api["intersect"](w.objects[2], r)
        found[name] = ([round(i.t, 9) for i in xs], [round(i.t, 9) for i in group_xs])
    assert len(found["naive"][0]) >= 4 and found["naive"][1]
    for name in STRUCTURES:
        assert found[name] == found["naive"], name


def test_the_matrix_helpers_agree() -> None:
    """``flatten.apply`` adds its terms as Python adds them, one point at a time."""
    m = Matrix([[1.5, 0.2, -0.3, 4.0], [0.1, 2.0, 0.7, -1.0], [0.0, -0.4, 0.9, 0.5], [0, 0, 0, 1]])
    points = np.array([[[0.1, 0.2, 0.3], [1.0, -2.0, 3.5], [1e3, 1e-3, -7.0]]])
    got = flatten.apply(m, points)
    r = m.rows
    for k in range(3):
        x, y, z = (float(v) for v in points[0, k])
        expected = tuple(r[j][0] * x + r[j][1] * y + r[j][2] * z + r[j][3] for j in range(3))
        assert tuple(got[0, k]) == expected


# ------------------------------------------------------------- where the builder comes from

MESH_IN_A_FRESH_PROCESS = (
    "import sys\n"
    "from scene import load_scene\n"
    "from variants.registry import load_variant\n"
    "from compiled import library\n"
    "v = load_variant('numba')\n"
    "s = load_scene('scenes/mesh.yml', v.api).resized(16, 10)\n"
    "from raytracer.camera import RenderSettings\n"
    "frame = v.tracer.prepare(s.camera, v.world_for(s), RenderSettings())\n"
    "print('numba' in sys.modules, frame.packed.hierarchy.nodes,"
    " [b.origin for b in library._loaded.values()])\n"
)


def test_a_mesh_render_needs_no_numba_once_the_builder_is_built() -> None:
    """The hierarchy's builder is a shared library too: a fresh process packs a mesh scene,
    builds its hierarchy and loads its render without importing numba."""
    numba = load_variant("numba")  # the libraries exist once this process did the same
    scene = load_scene(SCENES / "mesh.yml", numba.api).resized(16, 10)
    numba.tracer.prepare(scene.camera, numba.world_for(scene), RenderSettings())
    done = subprocess.run(
        [sys.executable, "-c", MESH_IN_A_FRESH_PROCESS], cwd=ROOT, capture_output=True,
        text=True,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    imported, nodes, origins = done.stdout.split(" ", 2)
    assert imported == "False", done.stdout
    assert int(nodes) > 10
    assert "shared library" in origins


def test_without_a_c_compiler_the_builder_runs_in_numba(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """Where the builder cannot be linked (CC=/bin/false), numba runs the same function,
    and builds the same tree."""
    rng = np.random.default_rng(3)
    centres = rng.uniform(-10, 10, (300, 3))
    unit_boxes = np.concatenate([centres - 0.2, centres + 0.3], axis=1)
    unit_items = np.zeros((300, L.NITEM), dtype=np.int64)
    unit_items[:, L.ITEM_A] = np.arange(300)
    linked = build_tree(unit_items, unit_boxes)
    assert "shared library" in bvh.load_bvh_builder().origin
    monkeypatch.setenv("CC", "/bin/false")
    monkeypatch.setenv("RTC_NUMBA_KERNELS", str(tmp_path))
    builder = bvh.load_bvh_builder()
    assert "numba with its disk cache" in builder.origin and "could not link" in builder.origin
    assert not list(tmp_path.glob("*.so"))
    fallback = build_tree(unit_items, unit_boxes)
    assert np.array_equal(fallback[0], linked[0]) and np.array_equal(fallback[1], linked[1])
    assert fallback[2].nodes == linked[2].nodes > 100


def test_the_box_test_without_slab_checks_answers_as_the_slab_test() -> None:
    """``box_hit`` (one branch, for rays parallel to no axis) against ``box_range`` (the slab
    test with its checks) on random boxes and rays, among them rays along an axis and
    origins on a box's faces, where 0 * inf would arise."""
    from numba import njit

    from variants.numba.kernels_geometry import box_hit, box_range

    @njit(error_model="numpy")  # 1 / 0 is inf, as in the kernels
    def both(boxes, rays, thi):
        out = np.zeros((len(rays), 2), np.bool_)
        for k in range(len(rays)):
            ox, oy, oz, dx, dy, dz = rays[k]
            ix, iy, iz = 1.0 / dx, 1.0 / dy, 1.0 / dz
            parallel = abs(ix) == np.inf or abs(iy) == np.inf or abs(iz) == np.inf
            out[k, 0] = box_hit(boxes, k % 50, ox, oy, oz, ix, iy, iz, thi, parallel)
            out[k, 1] = box_range(boxes, k % 50, ox, oy, oz, ix, iy, iz, 0.0, thi)
        return out

    rng = np.random.default_rng(36)
    low = rng.uniform(-2, 1, (50, 3))
    boxes = np.concatenate([low, low + rng.uniform(0.01, 2, (50, 3))], axis=1).ravel()
    rays = np.concatenate([rng.uniform(-3, 3, (4000, 3)), rng.normal(size=(4000, 3))], axis=1)
    rays[::7, 3 + rng.integers(0, 3)] = 0.0  # along a plane of two axes
    rays[::11, 3:5] = 0.0  # along the z axis
    faces = np.arange(0, 4000, 13)
    rays[faces, 0] = boxes.reshape(50, 6)[faces % 50, 0]  # starting on a box's face
    for thi in (np.inf, 2.5):
        answers = both(boxes, rays, thi)
        assert (answers[:, 0] == answers[:, 1]).all()
        assert 0 < answers[:, 0].sum() < len(rays)  # both answers occur


# ---------------------------------------------- compact nodes (a hierarchy of triangles)


def _two_meshes(api: Any) -> tuple[Any, Any]:
    """Two icospheres of compact triangles (one smooth) over a floor, the one casting a
    shadow on the other: a hierarchy of triangles alone, the floor outside it."""
    c = api["color"]
    near = _icosahedron(api, smooth=False, splits=2)
    api["set_transform"](near, api["translation"](-0.6, 1.2, -0.8) * api["scaling"](0.5, 0.5, 0.5))
    far = _icosahedron(api, smooth=True, splits=3)
    api["set_transform"](far, api["translation"](0.5, 0.6, 0.6) * api["rotation_y"](0.4))
    for child in near.children:
        child.material = material(color=c(0.9, 0.4, 0.2), specular=0.6)
    floor = api["plane"]()
    w = api["world"]()
    w.objects.extend([floor, near, far])
    w.light = api["point_light"](api["point"](-5, 8, -6), c(1, 1, 1))
    view = api["view_transform"](
        api["point"](0, 1.8, -5), api["point"](0, 0.7, 0), api["vector"](0, 1, 0)
    )
    return replace(api["camera"](40, 30, math.pi / 3), transform=view), w


def _node_boxes(packed: Packed) -> np.ndarray:
    return packed.nodes[:, : L.NBOX].astype(np.float64)


def _check_nodes(packed: Packed) -> None:
    """The I_NODES item and its compact nodes: the root in row 0, an inner node's two
    children side by side in rows of their own, inside its box; a leaf's triangles (its
    I_TRI items) inside its box; every triangle item of the hierarchy in one leaf."""
    items, nodes = packed.items, packed.nodes
    (at,) = np.flatnonzero(items[:, L.ITEM_TYPE] == L.I_NODES)
    start = int(items[at, L.ITEM_B])  # where the nodes are in the kernels' box table
    table = packed.box_table()
    assert start >= packed.boxes.size, "the nodes follow the boxes"
    assert table[start : start + nodes.size].tobytes() == nodes.tobytes()  # (links: bits)
    end = int(items[at, L.ITEM_A])
    boxes = _node_boxes(packed)
    reached: list[int] = []
    children: list[int] = []
    links = bvh.node_links(nodes)
    for row in range(len(nodes)):
        first, code = int(links[row, 0]), int(links[row, 1])
        outer = boxes[row]
        if code < 0:
            assert code >= -4 and first % 2 == 1 and first + 1 < len(nodes)
            children += [first, first + 1]
            for child in (first, first + 1):
                assert _contains(outer, boxes[child]), f"node {row} does not hold {child}"
            continue
        reached += _leaf_triangles(packed, items, outer, first, code, at, end, f"leaf {row}")
    assert sorted(children) == list(range(1, len(nodes))), "every node a child once"
    triangles = [k for k in range(at, end) if items[k, L.ITEM_TYPE] == L.I_TRI]
    assert sorted(reached) == triangles, "every triangle in one leaf"


def _leaf_triangles(
    packed: Any, items: Any, box: Any, first: int, count: int, at: Any, end: Any, leaf: str
) -> list[int]:
    """A leaf's items ``first`` .. ``first + count - 1``: within the hierarchy's items (after
    its own, before ``end``), compact triangles all, each inside ``box``; their indices."""
    assert count > 0 and at < first and first + count <= end
    for k in range(first, first + count):
        assert items[k, L.ITEM_TYPE] == L.I_TRI
        shape = packed.shapes[int(items[k, L.ITEM_A])]
        run_first = packed.pi[items[k, L.ITEM_A], L.TRI_FIRST]
        shape = _triangle_of(packed, int(items[k, L.ITEM_B]) - int(run_first), shape)
        assert _contains(box, _world_box(shape)), f"{leaf} misses item {k}"
    return list(range(first, first + count))


def test_compact_nodes_keep_their_invariants() -> None:
    api = load_variant("naive").api
    _, w = _two_meshes(api)
    wide = pack_world(w, compact=True)
    _check_nodes(wide)
    assert len(wide.nodes) == wide.hierarchy.nodes  # every node of the tree, leaves too
    assert "HAS_NODES" in analyse(wide).flags  # the kernel gets the nodes' walks
    table = wide.box_table()  # what the kernels take: the boxes, then the nodes
    assert np.shares_memory(table, wide.nodes) and np.shares_memory(table, wide.boxes)
    narrow = pack_world(w, np.float32, compact=True)
    _check_nodes(narrow)
    assert narrow.nodes.dtype == np.float32
    # float32 boxes hold the float64 ones (the builder's boxes are float32 values already)
    assert (narrow.nodes[:, :3].astype(np.float64) <= wide.nodes[:, :3]).all()
    assert (narrow.nodes[:, 3:6].astype(np.float64) >= wide.nodes[:, 3:6]).all()
    assert np.array_equal(bvh.node_links(narrow.nodes), bvh.node_links(wide.nodes))
    # the links are integer bits in their float slots, not float values (no link is 0)
    for packed in (wide, narrow):
        links = bvh.node_links(packed.nodes).astype(packed.nodes.dtype)
        assert (packed.nodes[:, L.NODE_A : L.NODE_C + 1] != links).all()
    # the items' walk and the book's API never see them; sah-items builds none
    items_only = pack_world(w, structure="sah-items", compact=True)
    assert L.I_NODES not in set(items_only.items[:, L.ITEM_TYPE].tolist())
    assert len(items_only.nodes) == 0
    assert "HAS_NODES" not in analyse(items_only).flags  # ... and its kernel none
    assert len(pack_world(w).nodes) == 0  # the book's API: a row per triangle
    mixed_world = pack_world(mixed(api)[1], compact=True)  # not triangles alone: no nodes
    assert len(mixed_world.nodes) == 0
    assert "HAS_NODES" not in analyse(mixed_world).flags


def test_compact_nodes_draw_the_same_picture_as_the_items_walk() -> None:
    api = load_variant("naive").api
    camera, w = _two_meshes(api)
    pictures = {}
    for name in ("numba[threads=1]", "numba[bvh=sah-items,threads=1]", "numba[bvh=off,threads=1]"):
        image = load_variant(name).tracer.render(camera, w, RenderSettings())
        pictures[name] = np.asarray(image.array, dtype=np.float64)
    ours = pictures["numba[threads=1]"]
    assert len({tuple(np.round(p, 3)) for p in ours.reshape(-1, 3)}) > 50, "not blank"
    for name, picture in pictures.items():
        assert np.array_equal(picture, ours), f"{name} differs from the compact nodes'"


def test_a_broken_node_table_fails_the_checks_and_the_picture() -> None:
    api = load_variant("naive").api
    camera, w = _two_meshes(api)
    tracer = load_variant("numba[threads=1]").tracer
    right = np.asarray(tracer.render(camera, w, RenderSettings()).array)
    shrunk = pack_world(w, compact=True)
    leaf = int(np.flatnonzero(bvh.node_links(shrunk.nodes)[:, 1] > 0)[0])
    shrunk.nodes[leaf, 3:6] = shrunk.nodes[leaf, 0:3]  # a leaf's box made a point
    with pytest.raises(AssertionError, match="misses item"):
        _check_nodes(shrunk)
    lost = pack_world(w, compact=True)
    codes = lost.nodes.view(np.int64)[:, L.NODE_C]  # the links: integer bits (``bvh.node_links``)
    codes[codes > 0] = 1  # leaves keep one triangle
    with pytest.raises(AssertionError, match="every triangle in one leaf"):
        _check_nodes(lost)
    for broken in (shrunk, lost):
        picture = np.asarray(tracer.render(camera, broken, RenderSettings()).array)
        assert not np.array_equal(picture, right)


# ------------------------------------------------- wide nodes (``bvh=sah4``, ``layout``)


def _wide_parts(packed: Packed) -> tuple[np.ndarray, np.ndarray]:
    """The wide nodes' boxes (float64: node, side, child) and links (node, child)."""
    nodes = packed.nodes
    boxes = nodes[:, : L.W_LINK].astype(np.float64).reshape(-1, L.NBOX, L.WIDE)
    per = nodes.itemsize // 4  # int32 links per value
    links = nodes.view(np.int32)[:, L.W_LINK * per : L.W_LINK * per + L.WIDE]
    return boxes, links.astype(np.int64)


def _check_wide(packed: Packed) -> None:
    """The I_NODES item (ITEM_C: WIDE) and its wide nodes: the root in row 0, every other
    node a child of one node, inside that child's box; a leaf child's triangles inside
    its box; an empty slot's box holding nothing; every triangle item in one leaf."""
    items = packed.items
    (at,) = np.flatnonzero(items[:, L.ITEM_TYPE] == L.I_NODES)
    assert items[at, L.ITEM_C] == L.WIDE
    start = int(items[at, L.ITEM_B])
    table = packed.box_table()
    assert start >= packed.boxes.size, "the nodes follow the boxes"
    assert table[start : start + packed.nodes.size].tobytes() == packed.nodes.tobytes()
    end = int(items[at, L.ITEM_A])
    boxes, links = _wide_parts(packed)
    reached: list[int] = []
    children: list[int] = []
    for row in range(len(boxes)):
        for j in range(L.WIDE):
            box = np.concatenate([boxes[row, 0:3, j], boxes[row, 3:6, j]])
            link = int(links[row, j])
            if (box[:3] == np.inf).all() and (box[3:] == -np.inf).all():
                assert link == 0, f"node {row}: an empty slot with a link"
                continue
            assert (box[:3] <= box[3:]).all(), f"node {row}: child {j}'s box holds nothing"
            if link >= 0:
                assert 0 < link < len(boxes)
                children.append(link)
                inner = boxes[link]
                used = inner[0] != np.inf
                lo, hi = inner[0:3, used].min(axis=1), inner[3:6, used].max(axis=1)
                assert _contains(box, np.concatenate([lo, hi])), f"node {row} misses {link}"
                continue
            first, count = (-1 - link) >> 3, (-1 - link) & 7
            reached += _leaf_triangles(packed, items, box, first, count, at, end, f"leaf of {row}")
    assert sorted(children) == list(range(1, len(boxes))), "every node a child once"
    triangles = [k for k in range(at, end) if items[k, L.ITEM_TYPE] == L.I_TRI]
    assert sorted(reached) == triangles, "every triangle in one leaf"


def test_wide_nodes_keep_their_invariants() -> None:
    api = load_variant("naive").api
    _, w = _two_meshes(api)
    wide = pack_world(w, structure="sah4", compact=True)
    _check_wide(wide)
    assert "HAS_NODES" in analyse(wide).flags
    assert np.shares_memory(wide.box_table(), wide.nodes)
    # a wide node is two levels of the binary tree: about a third as many nodes
    binary = pack_world(w, compact=True)
    inner = int((bvh.node_links(binary.nodes)[:, 1] < 0).sum())
    assert inner // 2 <= len(wide.nodes) < inner
    narrow = pack_world(w, np.float32, structure="sah4", compact=True)
    _check_wide(narrow)
    assert narrow.nodes.dtype == np.float32
    # the same boxes (float32 values already) and links in either type
    assert np.array_equal(_wide_parts(narrow)[0], _wide_parts(wide)[0])
    assert np.array_equal(_wide_parts(narrow)[1], _wide_parts(wide)[1])
    assert len(pack_world(w, structure="sah4").nodes) == 0  # the book's API: none


def test_a_tree_of_one_leaf_is_one_wide_node() -> None:
    tiny = np.zeros((1, L.NNODE))
    tiny[0, :6] = (0, 0, 0, 1, 1, 1)
    tiny.view(np.int64)[0, L.NODE_A : L.NODE_C + 1] = (7, 3)  # a leaf of 3 triangles
    (node,) = bvh.wide_nodes(tiny, np.float64)
    links = node.view(np.int32)[2 * L.W_LINK : 2 * L.W_LINK + L.WIDE]
    assert links.tolist() == [-1 - (7 * 8 + 3), 0, 0, 0]
    assert node[0 : L.W_LINK : L.WIDE].tolist() == [0, 0, 0, 1, 1, 1]
    assert (node[1 : 3 * L.WIDE : L.WIDE] == np.inf).all()


def _axis_camera(api: Any) -> Any:
    """A camera whose middle pixel's ray runs along the z axis, and whose middle column's
    and row's rays are parallel to a plane of two axes: the walks' parallel tests."""
    view = api["view_transform"](
        api["point"](0, 0.8, -5), api["point"](0, 0.8, 0), api["vector"](0, 1, 0)
    )
    return replace(api["camera"](41, 31, math.pi / 3), transform=view)


@pytest.mark.parametrize("float32", [False, True], ids=["float64", "float32"])
def test_wide_nodes_draw_the_same_picture_as_the_compact_nodes(
    float32: bool, request: pytest.FixtureRequest
) -> None:
    if float32:  # a kernel of the meshes' features (the gate's generic float32 kernel has no
        request.getfixturevalue("specialized_kernels")  # compact nodes: it would build another)
    api = load_variant("naive").api
    camera, w = _two_meshes(api)
    extra = ",float32" if float32 else ""
    for view in (camera, _axis_camera(api)):
        pictures = [
            np.asarray(load_variant(f"numba[{bvh_option}threads=1{extra}]").tracer.render(
                view, w, RenderSettings()).array, dtype=np.float64)
            for bvh_option in ("", "bvh=sah4,")
        ]  # fmt: skip
        assert len({tuple(np.round(p, 3)) for p in pictures[0].reshape(-1, 3)}) > 50
        assert np.array_equal(pictures[1], pictures[0])


def test_a_broken_wide_table_fails_the_checks_and_the_picture() -> None:
    api = load_variant("naive").api
    camera, w = _two_meshes(api)
    tracer = load_variant("numba[bvh=sah4,threads=1]").tracer
    right = np.asarray(tracer.render(camera, w, RenderSettings()).array)
    shrunk = pack_world(w, structure="sah4", compact=True)
    _, links = _wide_parts(shrunk)
    row, j = (int(v) for v in np.argwhere(links < 0)[0])
    for side in range(3):  # a leaf's box made a point
        shrunk.nodes[row, (3 + side) * L.WIDE + j] = shrunk.nodes[row, side * L.WIDE + j]
    with pytest.raises(AssertionError, match="misses item"):
        _check_wide(shrunk)
    lost = pack_world(w, structure="sah4", compact=True)
    ints = lost.nodes.view(np.int32)[:, 2 * L.W_LINK : 2 * L.W_LINK + L.WIDE]
    leaves = ints < 0
    ints[leaves] = -1 - (((-1 - ints[leaves]) >> 3) * 8 + 1)  # leaves keep one triangle
    with pytest.raises(AssertionError, match="every triangle in one leaf"):
        _check_wide(lost)
    for broken in (shrunk, lost):
        picture = np.asarray(tracer.render(camera, broken, RenderSettings()).array)
        assert not np.array_equal(picture, right)
