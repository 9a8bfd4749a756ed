"""The bounding-volume hierarchy's builder, compiled: a binned surface area heuristic over
boxes, written straight into the items and boxes tables the kernels traverse (``layout``).

This file is self-contained (numba's ``cache=True`` checks only the file a function is in,
so it imports no project module; ``tests/test_numba_bvh.py`` checks that its constants
match ``layout``'s). ``variants.numba.bvh`` calls it: through a small shared library built
from ``make_entry`` (as the render is, ``variants.numba.specialize``), so that a render
needs no numba; or through numba itself when no C compiler is found.

The build (Wald's binned SAH, with an explicit stack instead of recursion):

- a node covers a stretch [start, end) of the units (leaf items with their world-space
  boxes); its units' centroids are put into ``BINS`` bins along each axis, and the split
  between two bins with the least ``area(left) * count(left) + area(right) *
  count(right)`` is taken, unless a leaf of at most ``leaf_max`` units costs less (a box
  test counts ``TRAVERSAL`` units' tests);
- the units move in place (a partition), so each node's units stay contiguous;
- below ``sah_depth`` levels (a degenerate scene), and where every centroid is the same,
  the stretch is halved instead: the depth stays below ``sah_depth + log2(units) + 1``.

The tree is written depth first: a node is a box item whose ``ITEM_A`` is the item just
past its subtree (where a ray that misses the box goes on), ``ITEM_B`` the first item of
its second child and ``ITEM_C`` its split axis + 1 (for a ray that should visit the second
child first, ``kernels_hits``); a leaf is a box item (``ITEM_C`` 0) followed by its units'
items, or just the unit's item when it holds one.

A box is 6 floats, lo x, y, z, hi x, y, z: in ``fwork``, or a tuple while it grows (so that
it stays in registers); the loops run over the axes. Nothing is allocated (the C entry runs
without numba's runtime).
"""

from typing import Any

import numpy as np
from numba import cfunc, njit, types

# the same values as in ``layout`` (checked by the tests)
NITEM = 5
ITEM_TYPE = 0
ITEM_A = 1
ITEM_B = 2
ITEM_C = 3
ITEM_D = 4
I_BOX = 1
NBOX = 6
NODE_A = 6  # compact nodes (layout.NNODE columns): after the box, a leaf's first item or
NODE_C = 7  # an inner node's first child row; a leaf's count, an inner node's -2 - axis
NNODE = 8

BINS = 16  # bins per axis (layout.BVH_BINS)
STACK = 256  # the most pending nodes (layout.BVH_STACK; the depth stays far below)
UNIT_WIDTH = 6  # per unit (float32): lo x, y, z, hi x, y, z; its centroid is their mean
STATS = 5  # nodes, leaves, box items, depth, items written (layout.BVH_STATS)
TRAVERSAL = 1.0  # the cost of a box test (``unit_cost``: a unit's test, in box tests)
WIDEST_ONLY = 256  # a node of more units bins only its widest axis (a third of the work)

# work (ints): the pending nodes (start, end, depth, the parent box whose ITEM_B each is,
# its compact node's row), the open boxes (item, depth), the bins' counts (axis * BINS + b)
TASK = 5
TASKS = 0
OPENED = TASK * STACK
COUNTS = OPENED + 2 * STACK
WORK = COUNTS + 3 * BINS
# fwork (floats): the bins' boxes (axis * BINS + b), per boundary b the area and count
# right of it, the node's box, its centroids' box, each axis's bin scale (0: not binned)
BIN_BOXES = 0
RIGHT_AREA = 3 * BINS * 6
RIGHT_COUNT = RIGHT_AREA + BINS
NODE_BOX = RIGHT_COUNT + BINS
CENTRE_BOX = NODE_BOX + 6
SCALES = CENTRE_BOX + 6
FWORK = SCALES + 3

KERNEL: dict[str, Any] = {"cache": True, "error_model": "numpy"}
# the helpers are inlined into ``build`` by LLVM: called as functions, the build over a
# 138,000-triangle scene took a quarter longer (measured); inlined, a tenth less than the
# hand-unrolled build it replaced
HELPER: dict[str, Any] = {**KERNEL, "forceinline": True}


@njit(**HELPER)
def _empty(fwork, box):
    """The box at ``fwork[box]`` holds nothing (lo +inf, hi -inf)."""
    for a in range(3):
        fwork[box + a] = np.inf
        fwork[box + 3 + a] = -np.inf


EMPTY = (np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf)  # a box holding nothing


@njit(**HELPER)
def _box_at(fwork, at):
    """The box at ``fwork[at]`` as a tuple."""
    return (
        fwork[at], fwork[at + 1], fwork[at + 2], fwork[at + 3], fwork[at + 4], fwork[at + 5],
    )  # fmt: skip


@njit(**HELPER)
def _grown(box, fwork, at):
    """``box`` (lo x, y, z, hi x, y, z) grown to hold the box at ``fwork[at]``."""
    lx, ly, lz, hx, hy, hz = box
    return (
        min(lx, fwork[at]), min(ly, fwork[at + 1]), min(lz, fwork[at + 2]),
        max(hx, fwork[at + 3]), max(hy, fwork[at + 4]), max(hz, fwork[at + 5]),
    )  # fmt: skip


@njit(**HELPER)
def _holding(box, lx, ly, lz, hx, hy, hz):
    """``box`` grown to hold the box (lx, ly, lz, hx, hy, hz)."""
    bx, by, bz, cx, cy, cz = box
    return min(bx, lx), min(by, ly), min(bz, lz), max(cx, hx), max(cy, hy), max(cz, hz)


@njit(**HELPER)
def _grow_into(fwork, at, lx, ly, lz, hx, hy, hz):
    """The box at ``fwork[at]`` grows to hold the box (lx, ly, lz, hx, hy, hz)."""
    fwork[at] = min(fwork[at], lx)
    fwork[at + 1] = min(fwork[at + 1], ly)
    fwork[at + 2] = min(fwork[at + 2], lz)
    fwork[at + 3] = max(fwork[at + 3], hx)
    fwork[at + 4] = max(fwork[at + 4], hy)
    fwork[at + 5] = max(fwork[at + 5], hz)


@njit(**HELPER)
def _area(box):
    """Half the surface area of ``box`` (0 for an empty one)."""
    lx, ly, lz, hx, hy, hz = box
    if hx < lx or hy < ly or hz < lz:
        return 0.0
    dx = hx - lx
    dy = hy - ly
    dz = hz - lz
    return dx * dy + dy * dz + dz * dx


@njit(**HELPER)
def _centroid(units, u, axis):
    """The centre of the unit's box along ``axis``."""
    return (np.float64(units[u + axis]) + np.float64(units[u + 3 + axis])) * 0.5


@njit(**HELPER)
def _bin_of(c, lo, scale):
    b = int((c - lo) * scale)
    if b < 0:
        return 0
    if b >= BINS:
        return BINS - 1
    return b


@njit(**HELPER)
def _unit_box(units, u):
    """The unit's box (float32 in ``units``) as a tuple of float64."""
    return (
        np.float64(units[u]), np.float64(units[u + 1]), np.float64(units[u + 2]),
        np.float64(units[u + 3]), np.float64(units[u + 4]), np.float64(units[u + 5]),
    )  # fmt: skip


@njit(**HELPER)
def _extent(units, start, end, fwork):
    """The box of units [start, end) and the box of their centroids, into ``fwork`` (as
    tuples while they grow: in registers)."""
    box = centres = EMPTY
    for j in range(start, end):
        lx, ly, lz, hx, hy, hz = _unit_box(units, j * UNIT_WIDTH)
        cx, cy, cz = (lx + hx) * 0.5, (ly + hy) * 0.5, (lz + hz) * 0.5
        centres = _holding(centres, cx, cy, cz, cx, cy, cz)
        box = _holding(box, lx, ly, lz, hx, hy, hz)
    for c in range(6):
        fwork[NODE_BOX + c] = box[c]
        fwork[CENTRE_BOX + c] = centres[c]


@njit(**HELPER)
def _scales(m, fwork):
    """Each axis's bin scale (BINS over the centroids' spread; 0 where they do not spread,
    and for a node of more than ``WIDEST_ONLY`` units on every axis but the widest)."""
    widest = 0
    for a in range(3):
        width = fwork[CENTRE_BOX + 3 + a] - fwork[CENTRE_BOX + a]
        fwork[SCALES + a] = BINS / width if width > 0.0 else 0.0
        if width > fwork[CENTRE_BOX + 3 + widest] - fwork[CENTRE_BOX + widest]:
            widest = a
    if m > WIDEST_ONLY:
        for a in range(3):
            if a != widest:
                fwork[SCALES + a] = 0.0


@njit(**HELPER)
def _bin(units, start, end, work, fwork):
    """The units' counts and boxes per bin, along every axis with a scale."""
    for k in range(3 * BINS):
        work[COUNTS + k] = 0
        _empty(fwork, BIN_BOXES + k * 6)
    for j in range(start, end):
        u = j * UNIT_WIDTH
        lx, ly, lz, hx, hy, hz = _unit_box(units, u)
        for a in range(3):
            scale = fwork[SCALES + a]
            if scale == 0.0:
                continue
            k = a * BINS + _bin_of(_centroid(units, u, a), fwork[CENTRE_BOX + a], scale)
            work[COUNTS + k] += 1
            _grow_into(fwork, BIN_BOXES + k * 6, lx, ly, lz, hx, hy, hz)


@njit(**HELPER)
def _best_split(work, fwork):
    """(axis, the first bin of the right side, its cost): the boundary with the least
    ``area(left) * count(left) + area(right) * count(right)`` (axis -1: none). A sweep's
    box is a tuple, so that it stays in registers."""
    best = np.inf
    axis = -1
    split = -1
    for a in range(3):
        if fwork[SCALES + a] == 0.0:
            continue
        # right to left: the area and count right of each boundary b (bins b ...)
        box = EMPTY
        count = 0
        for b in range(BINS - 1, 0, -1):
            k = a * BINS + b
            count += work[COUNTS + k]
            box = _grown(box, fwork, BIN_BOXES + k * 6)
            fwork[RIGHT_AREA + b] = _area(box)
            fwork[RIGHT_COUNT + b] = count
        # left to right: the cost of each boundary
        box = EMPTY
        count = 0
        for b in range(1, BINS):
            k = a * BINS + b - 1
            count += work[COUNTS + k]
            box = _grown(box, fwork, BIN_BOXES + k * 6)
            right = fwork[RIGHT_COUNT + b]
            if count == 0 or right == 0.0:
                continue
            cost = _area(box) * count + fwork[RIGHT_AREA + b] * right
            if cost < best:
                best = cost
                axis = a
                split = b
    return axis, split, best


@njit(**HELPER)
def _split(units, start, end, depth, work, fwork, leaf_max, sah_depth, unit_cost):
    """(axis, split) for units [start, end): the binned heuristic's best boundary, or axis
    -1 where a leaf costs less, where no boundary separates them, or from ``sah_depth``
    on. A leaf costs m tests; a split one box test and its children's, each in
    proportion to its area."""
    m = end - start
    if m <= 1 or depth >= sah_depth:
        return -1, -1
    _scales(m, fwork)
    _bin(units, start, end, work, fwork)
    axis, split, best = _best_split(work, fwork)
    if axis >= 0 and m <= leaf_max:
        area = _area(_box_at(fwork, NODE_BOX))
        if area > 0.0 and TRAVERSAL + unit_cost * best / area >= unit_cost * m:
            return -1, -1
    return axis, split


@njit(**HELPER)
def _partition(units, order, start, end, axis, split, fwork):
    """The units whose centroid falls below bin ``split`` along ``axis`` first, in place;
    returns where the others start."""
    low = fwork[CENTRE_BOX + axis]
    scale = BINS / (fwork[CENTRE_BOX + 3 + axis] - low)
    i = start
    k = end - 1
    while i <= k:
        if _bin_of(_centroid(units, i * UNIT_WIDTH, axis), low, scale) < split:
            i += 1
        else:
            for c in range(UNIT_WIDTH):
                swap = units[i * UNIT_WIDTH + c]
                units[i * UNIT_WIDTH + c] = units[k * UNIT_WIDTH + c]
                units[k * UNIT_WIDTH + c] = swap
            unit = order[i]
            order[i] = order[k]
            order[k] = unit
            k -= 1
    return i


@njit(**HELPER)
def _box_item(items, pos, after, second, axis, boxes, box_items, fwork):
    """Item ``pos``: a box (the node's, from ``fwork``) named ``box_items`` in ``boxes``."""
    items[pos * NITEM + ITEM_TYPE] = I_BOX
    items[pos * NITEM + ITEM_A] = after
    items[pos * NITEM + ITEM_B] = second
    items[pos * NITEM + ITEM_C] = axis
    items[pos * NITEM + ITEM_D] = box_items
    for c in range(NBOX):
        boxes[box_items * NBOX + c] = fwork[NODE_BOX + c]


@njit(**HELPER)
def _push(work, tasks, start, end, depth, parent, row):
    t = TASKS + TASK * tasks
    work[t] = start
    work[t + 1] = end
    work[t + 2] = depth
    work[t + 3] = parent
    work[t + 4] = row
    return tasks + 1


@njit(**HELPER)
def _node(nodes, links, row, first, code, fwork):
    """Compact node ``row``: the node's box (from ``fwork``), then ``first`` and ``code``
    as integers (``links``: the same table as int64: integer bits in the float slots,
    which the kernels read without a conversion)."""
    at = row * NNODE
    for c in range(NBOX):
        nodes[at + c] = fwork[NODE_BOX + c]
    links[at + NODE_A] = first
    links[at + NODE_C] = code


@njit(cache=True, error_model="numpy")
def build(n, units, order, uitems, items, boxes, base, work, fwork, leaf_max, sah_depth,
          unit_cost, stats, nodes, links, with_nodes):  # fmt: skip
    """Build the hierarchy over ``n`` units; returns the number of items written.

    units: n x UNIT_WIDTH float32 boxes (flat; reordered in place); order: each unit's item
    in ``uitems`` (n ints, reordered with them); uitems: the items the units stand for
    (NITEM int32 each); items: the table written from row ``base`` on (int32; a tree over n
    units has at most 2 n - 1 items: a leaf of one unit is its item alone, any other node a
    box item); boxes: one row per box item written (at most n - 1), whose ITEM_D names it;
    work: ``WORK`` ints; fwork: ``FWORK`` floats (see above); leaf_max: the most units in a leaf;
    sah_depth: the depth from which stretches are halved; unit_cost: a unit's test in box
    tests; stats: STATS ints written (nodes, leaves, box items, depth, items); nodes:
    with_nodes != 0: the tree as compact nodes too (NNODE floats each, at most 2 n - 1;
    ``bvh.build_into``), the root in row 0, each inner node's two children side by side;
    links: ``nodes`` as int64 (``_node``)."""
    count = leaves = box_items = deepest = n_open = tasks = 0
    rows = 1  # compact nodes given a row
    pos = base
    if n > 0:
        tasks = _push(work, tasks, 0, n, 0, -1, 0)
    while tasks > 0:
        tasks -= 1
        t = TASKS + TASK * tasks
        start, end, depth, parent = work[t], work[t + 1], work[t + 2], work[t + 3]
        row = work[t + 4]
        # every open box at this depth or deeper ends here
        while n_open > 0 and work[OPENED + 2 * (n_open - 1) + 1] >= depth:
            n_open -= 1
            items[work[OPENED + 2 * n_open] * NITEM + ITEM_A] = pos
        if parent >= 0:
            items[parent * NITEM + ITEM_B] = pos
        count += 1
        deepest = max(deepest, depth)
        m = end - start
        _extent(units, start, end, fwork)
        axis, split = _split(units, start, end, depth, work, fwork, leaf_max, sah_depth,
                             unit_cost)  # fmt: skip
        if axis < 0 and m <= leaf_max:
            # a leaf: a box (when it holds more than one unit), then the units' items
            leaves += 1
            if with_nodes != 0:
                _node(nodes, links, row, pos + 1 if m > 1 else pos, m, fwork)
            if m > 1:
                _box_item(items, pos, pos + 1 + m, 0, 0, boxes, box_items, fwork)
                box_items += 1
                pos += 1
            for j in range(start, end):
                for c in range(NITEM):
                    items[pos * NITEM + c] = uitems[order[j] * NITEM + c]
                pos += 1
            continue
        # an inner node: its box, open until its subtree is written; no split found, or
        # too deep: the stretch is halved
        mid = start + m // 2
        if axis >= 0:
            mid = _partition(units, order, start, end, axis, split, fwork)
        _box_item(items, pos, 0, 0, axis + 1, boxes, box_items, fwork)
        box_items += 1
        if with_nodes != 0:
            _node(nodes, links, row, rows, -2 - axis, fwork)
        if n_open >= STACK or tasks + 2 > STACK:
            return -1  # cannot happen: the depth is bounded (see above)
        work[OPENED + 2 * n_open] = pos
        work[OPENED + 2 * n_open + 1] = depth
        n_open += 1
        # the second child first on the stack, so the first is written first
        tasks = _push(work, tasks, mid, end, depth + 1, pos, rows + 1)
        tasks = _push(work, tasks, start, mid, depth + 1, -1, rows)
        rows += 2
        pos += 1
    while n_open > 0:
        n_open -= 1
        items[work[OPENED + 2 * n_open] * NITEM + ITEM_A] = pos
    stats[0] = count
    stats[1] = leaves
    stats[2] = box_items
    stats[3] = deepest
    stats[4] = pos
    return pos


def make_entry(cache):
    """``build`` as a C function over raw pointers (numba's ``cfunc``): ``int64 f(int64 n,
    float *units, int64 *order, int32 *uitems, int32 *items, double *boxes, int64 base,
    int64 *work, double *fwork, int64 leaf_max, int64 sah_depth, double unit_cost, int64
    *stats, double *nodes, int64 *links, int64 with_nodes)``; ``cache``: numba's disk cache."""
    fp = types.CPointer(types.float64)
    ip = types.CPointer(types.int64)
    i32p = types.CPointer(types.int32)
    i64 = types.int64
    signature = types.int64(
        i64, types.CPointer(types.float32), ip, i32p, i32p, fp, i64, ip, fp, i64, i64,
        types.float64, ip, fp, ip, i64,
    )  # fmt: skip
    flags: dict[str, Any] = {"_nrt": False, "error_model": "numpy"}
    return cfunc(signature, cache=cache, **flags)(build.py_func)
