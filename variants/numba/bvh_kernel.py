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
child first, ``kernels_trace``); a leaf is a box item (``ITEM_C`` 0) followed by its units'
items, or just the unit's item when it holds one.
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

BINS = 16  # bins per axis (layout.BVH_BINS)
STACK = 256  # the most pending nodes (layout.BVH_STACK; the depth stays far below)
UNIT_WIDTH = 6  # per unit (float32): lo x, y, z, hi x, y, z; its centroid is their mean
STATS = 5  # nodes, leaves, box items, depth, items written (layout.BVH_STATS)
TRAVERSAL = 1.0  # the cost of a box test (``unit_cost``: a unit's test, in box tests)
WIDEST_ONLY = 256  # a node of more units bins only its widest axis (a third of the work)


@njit(cache=True, error_model="numpy")
def _area(lx, ly, lz, hx, hy, hz):
    """Half the surface area of a box (0 for an empty one)."""
    if hx < lx or hy < ly or hz < lz:
        return 0.0
    dx = hx - lx
    dy = hy - ly
    dz = hz - lz
    return dx * dy + dy * dz + dz * dx


@njit(cache=True, error_model="numpy")
def _centroid(units, u, axis):
    """The centre of the unit's box along ``axis``."""
    return (np.float64(units[u + axis]) + np.float64(units[u + 3 + axis])) * 0.5


@njit(cache=True, error_model="numpy")
def _bin_of(c, lo, scale):
    b = int((c - lo) * scale)
    if b < 0:
        return 0
    if b >= BINS:
        return BINS - 1
    return b


@njit(cache=True, error_model="numpy")
def build(n, units, order, uitems, items, boxes, base, work, fwork, leaf_max, sah_depth,
          unit_cost, stats):  # fmt: skip
    """Build the hierarchy over ``n`` units; returns the number of items written.

    units: n x UNIT_WIDTH float32 boxes (flat; reordered in place); order: each unit's item
    in ``uitems`` (n ints, reordered with them); uitems: the items the units stand for
    (NITEM int32 each); items: the table written from row ``base`` on (int32; a tree over n
    units has at most 2 n - 1 items: a leaf of one unit is its item alone, any other node a
    box item); boxes: one row per box item written (at most n - 1), whose ITEM_D names it;
    work: 6 STACK + 3 BINS ints; fwork: 3 BINS x 6 + 2 BINS floats; leaf_max: the most
    units in a leaf; sah_depth: the depth from which stretches are halved; unit_cost: a
    unit's test in box tests; stats: STATS ints written (nodes, leaves, box items, depth,
    items)."""
    task = 0  # work[task + 4 k ...]: start, end, depth, the parent box whose ITEM_B it is
    opened = 4 * STACK  # work[opened + 2 k ...]: an open box item and its depth
    counts = 6 * STACK  # work[counts + axis * BINS + b]
    bin_box = 0  # fwork[bin_box + (axis * BINS + b) * 6 ...]
    right_area = 3 * BINS * 6  # fwork[right_area + b]: the area right of boundary b
    right_count = right_area + BINS  # (as a float)
    nodes = 0
    leaves = 0
    box_items = 0
    deepest = 0
    pos = base
    tasks = 0
    n_open = 0
    if n > 0:
        work[task] = 0
        work[task + 1] = n
        work[task + 2] = 0
        work[task + 3] = -1
        tasks = 1
    while tasks > 0:
        tasks -= 1
        t = task + 4 * tasks
        start = work[t]
        end = work[t + 1]
        depth = work[t + 2]
        parent = work[t + 3]
        # every open box at this depth or deeper ends here
        while n_open > 0 and work[opened + 2 * (n_open - 1) + 1] >= depth:
            n_open -= 1
            items[work[opened + 2 * n_open] * NITEM + ITEM_A] = pos
        if parent >= 0:
            items[parent * NITEM + ITEM_B] = pos
        nodes += 1
        if depth > deepest:
            deepest = depth
        m = end - start
        # the node's box and its centroids' box
        lx = np.inf
        ly = np.inf
        lz = np.inf
        hx = -np.inf
        hy = -np.inf
        hz = -np.inf
        clx = np.inf
        cly = np.inf
        clz = np.inf
        chx = -np.inf
        chy = -np.inf
        chz = -np.inf
        for j in range(start, end):
            u = j * UNIT_WIDTH
            ulx = np.float64(units[u])
            uly = np.float64(units[u + 1])
            ulz = np.float64(units[u + 2])
            uhx = np.float64(units[u + 3])
            uhy = np.float64(units[u + 4])
            uhz = np.float64(units[u + 5])
            cx = (ulx + uhx) * 0.5
            cy = (uly + uhy) * 0.5
            cz = (ulz + uhz) * 0.5
            clx = min(clx, cx)
            cly = min(cly, cy)
            clz = min(clz, cz)
            chx = max(chx, cx)
            chy = max(chy, cy)
            chz = max(chz, cz)
            lx = min(lx, ulx)
            ly = min(ly, uly)
            lz = min(lz, ulz)
            hx = max(hx, uhx)
            hy = max(hy, uhy)
            hz = max(hz, uhz)
        split = -1  # the first bin of the right side
        axis = -1
        if m > 1 and depth < sah_depth:
            # bin the centroids along every axis at once
            for k in range(3 * BINS):
                work[counts + k] = 0
                f = bin_box + k * 6
                fwork[f] = np.inf
                fwork[f + 1] = np.inf
                fwork[f + 2] = np.inf
                fwork[f + 3] = -np.inf
                fwork[f + 4] = -np.inf
                fwork[f + 5] = -np.inf
            s0 = BINS / (chx - clx) if chx > clx else 0.0
            s1 = BINS / (chy - cly) if chy > cly else 0.0
            s2 = BINS / (chz - clz) if chz > clz else 0.0
            if m > WIDEST_ONLY:
                # a large node: only the axis its centroids spread widest along
                wx = chx - clx
                wy = chy - cly
                wz = chz - clz
                if wx >= wy and wx >= wz:
                    s1 = 0.0
                    s2 = 0.0
                elif wy >= wz:
                    s0 = 0.0
                    s2 = 0.0
                else:
                    s0 = 0.0
                    s1 = 0.0
            for j in range(start, end):
                u = j * UNIT_WIDTH
                ulx = np.float64(units[u])
                uly = np.float64(units[u + 1])
                ulz = np.float64(units[u + 2])
                uhx = np.float64(units[u + 3])
                uhy = np.float64(units[u + 4])
                uhz = np.float64(units[u + 5])
                for a in range(3):
                    scale = s0 if a == 0 else (s1 if a == 1 else s2)
                    if scale == 0.0:
                        continue
                    low = clx if a == 0 else (cly if a == 1 else clz)
                    c = _centroid(units, u, a)
                    k = a * BINS + _bin_of(c, low, scale)
                    work[counts + k] += 1
                    f = bin_box + k * 6
                    fwork[f] = min(fwork[f], ulx)
                    fwork[f + 1] = min(fwork[f + 1], uly)
                    fwork[f + 2] = min(fwork[f + 2], ulz)
                    fwork[f + 3] = max(fwork[f + 3], uhx)
                    fwork[f + 4] = max(fwork[f + 4], uhy)
                    fwork[f + 5] = max(fwork[f + 5], uhz)
            best = np.inf
            for a in range(3):
                scale = s0 if a == 0 else (s1 if a == 1 else s2)
                if scale == 0.0:
                    continue
                # right to left: the area and count right of each boundary b (bins b ...)
                rlx = np.inf
                rly = np.inf
                rlz = np.inf
                rhx = -np.inf
                rhy = -np.inf
                rhz = -np.inf
                count = 0
                for b in range(BINS - 1, 0, -1):
                    k = a * BINS + b
                    f = bin_box + k * 6
                    count += work[counts + k]
                    rlx = min(rlx, fwork[f])
                    rly = min(rly, fwork[f + 1])
                    rlz = min(rlz, fwork[f + 2])
                    rhx = max(rhx, fwork[f + 3])
                    rhy = max(rhy, fwork[f + 4])
                    rhz = max(rhz, fwork[f + 5])
                    fwork[right_area + b] = _area(rlx, rly, rlz, rhx, rhy, rhz)
                    fwork[right_count + b] = count
                # left to right: the cost of each boundary
                llx = np.inf
                lly = np.inf
                llz = np.inf
                lhx = -np.inf
                lhy = -np.inf
                lhz = -np.inf
                count = 0
                for b in range(1, BINS):
                    k = a * BINS + b - 1
                    f = bin_box + k * 6
                    count += work[counts + k]
                    llx = min(llx, fwork[f])
                    lly = min(lly, fwork[f + 1])
                    llz = min(llz, fwork[f + 2])
                    lhx = max(lhx, fwork[f + 3])
                    lhy = max(lhy, fwork[f + 4])
                    lhz = max(lhz, fwork[f + 5])
                    right = fwork[right_count + b]
                    if count == 0 or right == 0.0:
                        continue
                    cost = _area(llx, lly, llz, lhx, lhy, lhz) * count + (
                        fwork[right_area + b] * right
                    )
                    if cost < best:
                        best = cost
                        axis = a
                        split = b
            if axis >= 0:
                area = _area(lx, ly, lz, hx, hy, hz)
                # a leaf costs m tests; a split one box test and its children's, each in
                # proportion to its area
                if (
                    m <= leaf_max
                    and area > 0.0
                    and (TRAVERSAL + unit_cost * best / area >= unit_cost * m)
                ):
                    axis = -1
        halve = axis < 0 and m > leaf_max  # no split found, or too deep: halve the stretch
        if axis < 0 and not halve:
            # a leaf: a box (when it holds more than one unit), then the units' items
            leaves += 1
            if m > 1:
                items[pos * NITEM + ITEM_TYPE] = I_BOX
                items[pos * NITEM + ITEM_A] = pos + 1 + m
                items[pos * NITEM + ITEM_B] = 0
                items[pos * NITEM + ITEM_C] = 0
                items[pos * NITEM + ITEM_D] = box_items
                _write_box(boxes, box_items, lx, ly, lz, hx, hy, hz)
                box_items += 1
                pos += 1
            for j in range(start, end):
                unit = order[j]
                for c in range(NITEM):
                    items[pos * NITEM + c] = uitems[unit * NITEM + c]
                pos += 1
            continue
        mid = start + m // 2
        if not halve:
            # partition: the units whose centroid falls below bin ``split`` first
            low = clx if axis == 0 else (cly if axis == 1 else clz)
            high = chx if axis == 0 else (chy if axis == 1 else chz)
            scale = BINS / (high - low)
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
            mid = i
        # an inner node: its box, open until its subtree is written
        items[pos * NITEM + ITEM_TYPE] = I_BOX
        items[pos * NITEM + ITEM_A] = 0
        items[pos * NITEM + ITEM_B] = 0
        items[pos * NITEM + ITEM_C] = axis + 1 if not halve else 0
        items[pos * NITEM + ITEM_D] = box_items
        _write_box(boxes, box_items, lx, ly, lz, hx, hy, hz)
        box_items += 1
        if n_open >= STACK or tasks + 2 > STACK:
            return -1  # cannot happen: the depth is bounded (see above)
        work[opened + 2 * n_open] = pos
        work[opened + 2 * n_open + 1] = depth
        n_open += 1
        # the second child first on the stack, so the first is written first
        t = task + 4 * tasks
        work[t] = mid
        work[t + 1] = end
        work[t + 2] = depth + 1
        work[t + 3] = pos
        work[t + 4] = start
        work[t + 5] = mid
        work[t + 6] = depth + 1
        work[t + 7] = -1
        tasks += 2
        pos += 1
    while n_open > 0:
        n_open -= 1
        items[work[opened + 2 * n_open] * NITEM + ITEM_A] = pos
    stats[0] = nodes
    stats[1] = leaves
    stats[2] = box_items
    stats[3] = deepest
    stats[4] = pos
    return pos


@njit(cache=True, error_model="numpy")
def _write_box(boxes, pos, lx, ly, lz, hx, hy, hz):
    m = pos * NBOX
    boxes[m] = lx
    boxes[m + 1] = ly
    boxes[m + 2] = lz
    boxes[m + 3] = hx
    boxes[m + 4] = hy
    boxes[m + 5] = hz


def make_entry(cache):
    """``build`` as a C function over raw pointers (numba's ``cfunc``): ``int64 f(int64 n,
    float *units, int64 *order, int32 *uitems, int32 *items, double *boxes, int64 base,
    int64 *work, double *fwork, int64 leaf_max, int64 sah_depth, double unit_cost, int64
    *stats)``; ``cache``: numba's disk cache."""
    fp = types.CPointer(types.float64)
    ip = types.CPointer(types.int64)
    i32p = types.CPointer(types.int32)
    i64 = types.int64
    signature = types.int64(
        i64, types.CPointer(types.float32), ip, i32p, i32p, fp, i64, ip, fp, i64, i64,
        types.float64, ip,
    )  # fmt: skip
    flags: dict[str, Any] = {"_nrt": False, "error_model": "numpy"}
    return cfunc(signature, cache=cache, **flags)(build.py_func)
