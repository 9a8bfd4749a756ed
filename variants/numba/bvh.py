"""The bounding-volume hierarchy (the bonus chapter "Bounding boxes and hierarchies", done
as renderers do it): how a packed world's items are arranged for the rays.

The variant's ``bvh`` option picks one of the structures (``STRUCTURES``):

- ``sah`` (the default): the world's groups are flattened (their transforms are already
  composed into each primitive), every leaf item (a primitive, or a whole CSG tree) with a
  world-space box becomes a unit, and a hierarchy is built over the units by the binned
  surface area heuristic (``bvh_kernel``, compiled), once per render, when the world is
  packed. Items without a box (planes, open cylinders and cones, CSG trees holding them)
  stay outside the tree and come first, so that a hit on them (a floor) can already cut
  the tree's boxes short. When the world has few spheres with a similarity transform they
  stay the ``balls``, tested all at once (``layout``); from ``BALLS_MAX`` on they join the
  hierarchy;
- ``sah-items``: the same hierarchy walked only as items (the kernels' loop below), also
  over compact triangles, where ``sah`` gives a hierarchy of compact triangles alone its
  compact nodes too (written by the builder): a node's two children side by side, tested
  together, the one first along the ray on the node's split axis taken first (by the sign
  of the ray's direction: ordered by the two entry distances instead, the walk took a
  fifth longer, a branch the processor cannot predict) and the other dropped when it
  comes back beyond the nearest hit so far;
- ``sah4``: ``sah`` whose compact nodes are collapsed into wide ones (``wide_nodes``): a
  node adopts its children's children, so a wide node is two levels of the tree, its four
  children's boxes (a row of four per side) tested at once by vector instructions, those
  the ray enters taken nearest first (the mesh row's render in 0.81x the time of the
  compact nodes', six-knots.yml's with its shadow rays in 0.87x). The order comes from
  compare-and-swap branches on the four (entry, link) pairs: sorted without a branch
  (integer keys, the link in their low bits) the render took 1.04x the compact nodes'
  time, as the next node then waits for every test where a predicted branch lets the
  processor start on it; ordered by the tree's split axes for the ray's octant, 1.10x;
  float32 boxes (half the bytes, a conversion per side) took 1.02-1.05x float64's time;
- ``groups``: the scene's own group tree: a group's box skips its children (chapter 14);
- ``off``: no boxes at all: every ray visits every item.

The kernels traverse all three with the same loop and no recursion (``kernels_hits``): a
box the ray misses, or meets only beyond the nearest hit so far, sends it past the box's
contents; the hit ray visits an inner node's second child first when it travels down the
node's split axis.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from compiled.library import Compiled, Recipe, load
from variants.numba import layout as L

STRUCTURES = ("sah", "sah4", "sah-items", "groups", "off")
SAH = ("sah", "sah4", "sah-items")  # the structures built by the heuristic
DEFAULT = "sah"
LEAF_MAX = 4  # the most units in a leaf
UNIT_COST = 1.0  # a unit's test against a box test, for the heuristic (a primitive is first
# tested against its bounding sphere, about as fast as a box; 2.0 measured no faster)
BALLS_MAX = 32  # from this many world spheres on, they join the hierarchy (``sah``)

BVH_BUILDER = Recipe(
    name="build_bvh",
    module="variants.numba.bvh_kernel",
    function="build",
    parameters=(
        ("int64_t", "n"), ("float *", "units"), ("int64_t *", "order"),
        ("int32_t *", "uitems"), ("int32_t *", "items"), ("double *", "boxes"),
        ("int64_t", "base"), ("int64_t *", "work"), ("double *", "fwork"),
        ("int64_t", "leaf_max"), ("int64_t", "sah_depth"), ("double", "unit_cost"),
        ("int64_t *", "stats"), ("double *", "nodes"), ("int64_t *", "links"),
        ("int64_t", "with_nodes"),
    ),
    what="the hierarchy builder",
)  # fmt: skip


def load_bvh_builder() -> Compiled:
    """The hierarchy's builder (``bvh_kernel.build``): from its shared library (built first
    if missing), else numba's ``njit`` function with its disk cache. Once per process."""
    return load(BVH_BUILDER)


@dataclass(frozen=True)
class Hierarchy:
    """How a packed world's items are arranged: ``structure`` (``STRUCTURES``); for
    ``sah``: the units in the tree, the items outside it, the tree's nodes, leaves and
    box items, its depth and the seconds its build took."""

    structure: str
    units: int = 0
    outside: int = 0
    nodes: int = 0
    leaves: int = 0
    boxes: int = 0
    depth: int = 0
    seconds: float = 0.0

    def describe(self) -> str:
        """One line for ``explain``."""
        if self.structure == "off":
            return "bvh: off (every ray visits every item)"
        if self.structure == "groups":
            return f"bvh: the scene's own groups ({self.boxes:,} group boxes)"
        outside = (
            f"; {self.outside:,} unbounded item{'' if self.outside == 1 else 's'} outside it"
            if self.outside
            else ""
        )
        if self.nodes == 0:
            return f"bvh: SAH, nothing to build over ({self.units} bounded){outside}"
        return (
            f"bvh: SAH over {self.units:,} primitives, {self.nodes:,} nodes ({self.leaves:,} "
            f"leaves), depth {self.depth}, built in {self.seconds:.3g} s{outside}"
        )


def outward32(boxes: np.ndarray) -> np.ndarray:
    """Boxes (lo x, y, z, hi x, y, z) as float32, rounded outwards (never smaller)."""
    rounded = boxes.astype(np.float32)
    lo, hi = rounded[:, 0:3], rounded[:, 3:6]
    low = lo.astype(np.float64) > boxes[:, 0:3]
    high = hi.astype(np.float64) < boxes[:, 3:6]
    lo[low] = np.nextafter(lo[low], np.float32(-np.inf))
    hi[high] = np.nextafter(hi[high], np.float32(np.inf))
    return rounded


def node_links(nodes: np.ndarray) -> np.ndarray:
    """The compact nodes' links (``NODE_A``, ``NODE_C``) as int64: integers stored as the
    bits of their float slots (the builder writes them so: the kernels read them without
    a conversion, ``int_bits``, which was on the walk's path from a node to its children)."""
    return nodes.view(_bits(nodes.dtype))[:, L.NODE_A : L.NODE_C + 1].astype(np.int64)


def nodes_as(nodes: np.ndarray, dtype: Any) -> np.ndarray:
    """The compact nodes in float type ``dtype`` (the boxes converted, the links kept as
    integers of the new width: ``node_links``)."""
    if np.dtype(dtype) == nodes.dtype:
        return nodes
    converted = nodes.astype(dtype)
    converted.view(_bits(converted.dtype))[:, L.NODE_A : L.NODE_C + 1] = node_links(nodes)
    return converted


def wide_nodes(nodes: np.ndarray, dtype: Any) -> np.ndarray:
    """The compact nodes (float64, the builder's) collapsed into wide ones (``layout``:
    ``NWIDE`` values of type ``dtype`` each), the root in row 0: an inner node at an even
    depth adopts its children's children (an inner child's two, a leaf child itself), so a
    wide node is two levels of the tree and the walk's stack holds at most 3 entries per
    wide level."""
    links = node_links(nodes)
    first, code = links[:, 0], links[:, 1]
    inner = code < 0
    depth = np.zeros(len(nodes), dtype=np.int64)
    level = np.zeros(1, dtype=np.int64)
    while len(level):
        level = level[inner[level]]
        depth[first[level]] = depth[first[level] + 1] = depth[level] + 1
        level = np.concatenate([first[level], first[level] + 1])
    rows = np.flatnonzero(inner & (depth % 2 == 0))
    if not inner[0]:
        rows = np.zeros(1, dtype=np.int64)
        slots = np.array([[0, -1, -1, -1]])
    else:
        c0, c1 = first[rows], first[rows] + 1
        slots = np.stack([
            np.where(inner[c0], first[c0], c0), np.where(inner[c0], first[c0] + 1, -1),
            np.where(inner[c1], first[c1], c1), np.where(inner[c1], first[c1] + 1, -1),
        ], axis=1)  # fmt: skip
    row_of = np.full(len(nodes), -1, dtype=np.int64)
    row_of[rows] = np.arange(len(rows))
    wide = np.zeros((len(rows), L.NWIDE), dtype=dtype)
    used = slots >= 0
    at = np.where(used, slots, 0)
    for c in range(L.NBOX):
        empty = np.inf if c < 3 else -np.inf
        wide[:, c * L.WIDE : (c + 1) * L.WIDE] = np.where(used, nodes[at, c], empty)
    leaf = -1 - (first[at] * 8 + code[at])
    link = np.where(used, np.where(inner[at], row_of[at], leaf), 0)
    if used.any() and (np.where(used & inner[at], row_of[at], 0) < 0).any():
        raise RuntimeError("numba: a wide node's child is not a wide node (a bug)")
    if (link >= 2**31).any() or (link < -(2**31)).any():
        raise RuntimeError("numba: too many triangles for a wide node's int32 links")
    at32 = L.W_LINK * wide.itemsize // 4
    wide.view(np.int32)[:, at32 : at32 + L.WIDE] = link
    return wide


def _bits(dtype: np.dtype) -> type:
    return np.int64 if dtype.itemsize == 8 else np.int32


def build_into(
    items: np.ndarray,
    units: np.ndarray,
    order: np.ndarray,
    out: np.ndarray,
    base: int,
    with_nodes: bool = False,
) -> tuple[int, np.ndarray, np.ndarray, Hierarchy]:
    """The hierarchy over n units written into ``out`` (int32, NITEM columns) from row
    ``base`` on (room for 2 n - 1 rows there). ``units``: their world boxes (n x 6 float32,
    rounded outwards; reordered); ``order``: the row of ``items`` each unit stands for (n
    ints; reordered); ``with_nodes``: the tree as compact nodes too (``layout``: the root
    in row 0, a node's two children side by side; a row per node of the tree), in the same
    flat table as the boxes, after them. Returns (rows of ``out`` used, the box items'
    boxes: one row each, named by their ITEM_D, the compact nodes (none without
    ``with_nodes``), what was built)."""
    n = len(units)
    started = time.perf_counter()
    # one table (not zeroed: every row kept is written): the boxes, then the nodes
    rows = 2 * n - 1 if with_nodes else 0
    table = np.empty(max(n, 1) * L.NBOX + rows * L.NNODE, dtype=np.float64)
    boxes = table[: max(n, 1) * L.NBOX].reshape(-1, L.NBOX)
    nodes = table[boxes.size :].reshape(-1, L.NNODE)
    work = np.zeros(L.BVH_WORK, dtype=np.int64)
    fwork = np.zeros(L.BVH_FWORK, dtype=np.float64)
    stats = np.zeros(L.BVH_STATS, dtype=np.int64)
    # below sah_depth the heuristic decides; from there on stretches are halved, so the
    # depth stays within BVH_DEPTH (the kernels' range stack)
    sah_depth = L.BVH_DEPTH - math.ceil(math.log2(max(n, 2))) - 2
    count = load_bvh_builder().function(
        n, units.reshape(-1), order, items.reshape(-1), out.reshape(-1), boxes.reshape(-1),
        base, work, fwork, LEAF_MAX, sah_depth, UNIT_COST, stats, table[boxes.size :],
        table[boxes.size :].view(np.int64), int(with_nodes),
    )  # fmt: skip
    if count < 0 or stats[3] >= L.BVH_DEPTH:
        raise RuntimeError(f"numba: the hierarchy over {n} units went too deep (a bug)")
    seconds = time.perf_counter() - started
    nodes_count, leaves, box_items, depth, _ = (int(v) for v in stats)
    hierarchy = Hierarchy("sah", n, 0, nodes_count, leaves, box_items, depth, seconds)
    return int(count), boxes[:box_items], nodes[: nodes_count if with_nodes else 0], hierarchy


def build_tree(
    unit_items: np.ndarray, unit_boxes: np.ndarray
) -> tuple[np.ndarray, np.ndarray, Hierarchy]:
    """The hierarchy over units (``unit_items``: n x NITEM, ``unit_boxes``: n x 6 world-space
    boxes, finite): its items (int32) and box rows (``build_into``) and what it is."""
    n = len(unit_items)
    items = np.ascontiguousarray(unit_items, dtype=np.int32)
    out = np.zeros((max(2 * n - 1, 1), L.NITEM), dtype=np.int32)
    count, boxes, _, hierarchy = build_into(
        items, outward32(unit_boxes), np.arange(n, dtype=np.int64), out, 0
    )
    return out[:count], boxes, hierarchy
