"""A bounding-volume hierarchy over the bounded units, walked by whole passes of rays (the
bonus chapter "Bounding boxes and hierarchies", done the wavefront way).

``build`` sorts the units along a Morton curve and pairs leaves of ``LEAF`` of them level
by level (a linear BVH). ``Hierarchy.pairs`` walks it for many rays at once without
recursion: a work list of (ray, node) pairs, level by level; one vectorized slab test per
level drops the pairs whose ray misses the node's box (or meets it only beyond the ray's
``limit``, which the caller may lower between two steps: the nearest hit so far, a shadow
ray's distance to the light); a leaf's pairs become (ray, unit) pairs for the caller to
test; an inner node's become pairs with both children. A level with more pairs than
``cap`` is cut into pieces, the last piece walked to its leaves first, so the work list
stays bounded.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from variants.wavefront.geometry import per_ray

LEAF = 4  # the most units in a leaf


@dataclass
class Hierarchy:
    """Nodes 0 .. n-1 (0: the root): box ``lo``/``hi`` (3, n), children ``left``/``right``
    (-1 for a leaf), a leaf's units ``order[start : start + count]``."""

    lo: np.ndarray
    hi: np.ndarray
    left: np.ndarray
    right: np.ndarray
    start: np.ndarray
    count: np.ndarray
    order: np.ndarray

    @property
    def nodes(self) -> int:
        return len(self.left)

    @property
    def leaves(self) -> int:
        return int((self.left < 0).sum())

    def depth(self) -> int:
        """The number of levels."""
        level = np.zeros(self.nodes, dtype=np.int64)
        for n in range(self.nodes):  # children come after their parent
            if self.left[n] >= 0:
                level[self.left[n]] = level[self.right[n]] = level[n] + 1
        return int(level.max()) + 1 if self.nodes else 0

    def pairs(
        self,
        origin: tuple[Any, Any, Any],
        inverse: tuple[Any, Any, Any],
        limit: np.ndarray,
        cap: int,
        whole_line: bool = False,
    ) -> Iterator[tuple[np.ndarray, np.ndarray]]:
        """(rays, units): for every ray (index into ``origin``'s arrays) the units of every
        leaf whose box it meets between t = 0 (``whole_line``: -inf) and ``limit[ray]``
        (read afresh at every level, so lowering it prunes what is left). ``inverse``: 1 /
        direction, with zero components replaced by a tiny number of their sign."""
        n = len(limit)
        stack = [(np.arange(n), np.zeros(n, dtype=np.int64))]
        while stack:
            rays, nodes = stack.pop()
            enter = None
            leave = None
            for k in range(3):
                o = origin[k][rays] if per_ray(origin[k]) else origin[k]
                inv = inverse[k][rays]
                t1 = (self.lo[k][nodes] - o) * inv
                t2 = (self.hi[k][nodes] - o) * inv
                near, far = np.minimum(t1, t2), np.maximum(t1, t2)
                enter = near if enter is None else np.maximum(enter, near)
                leave = far if leave is None else np.minimum(leave, far)
            assert enter is not None and leave is not None
            if whole_line:
                keep = enter <= leave
            else:
                keep = (leave >= np.maximum(enter, 0)) & (enter <= limit[rays])
            rays, nodes = rays[keep], nodes[keep]
            leaf = self.left[nodes] < 0
            if leaf.any():
                yield self._expand(rays[leaf], nodes[leaf])
            inner = ~leaf
            if inner.any():
                rays, nodes = rays[inner], nodes[inner]
                rays = np.concatenate([rays, rays])
                nodes = np.concatenate([self.left[nodes], self.right[nodes]])
                pieces = -(-len(rays) // cap)
                stack.extend(
                    zip(np.array_split(rays, pieces), np.array_split(nodes, pieces), strict=True)
                )

    def _expand(self, rays: np.ndarray, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        counts = self.count[nodes]
        total = int(counts.sum())
        first = np.repeat(self.start[nodes] - (np.cumsum(counts) - counts), counts)
        return np.repeat(rays, counts), self.order[first + np.arange(total)]


def _spread(v: np.ndarray) -> np.ndarray:
    """The low 21 bits of ``v`` (uint64) moved to every third bit."""
    v = v & np.uint64(0x1FFFFF)
    for shift, mask in (
        (32, 0x1F00000000FFFF), (16, 0x1F0000FF0000FF), (8, 0x100F00F00F00F00F),
        (4, 0x10C30C30C30C30C3), (2, 0x1249249249249249),
    ):  # fmt: skip
        v = (v | (v << np.uint64(shift))) & np.uint64(mask)
    return v


def morton(points: np.ndarray) -> np.ndarray:
    """Morton codes (uint64) of points (n, 3): 21 bits per axis over their bounding box."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    scale = np.where(hi > lo, (2**21 - 1) / np.where(hi > lo, hi - lo, 1), 0)
    q = ((points - lo) * scale).astype(np.uint64)
    return (
        _spread(q[:, 0]) | (_spread(q[:, 1]) << np.uint64(1)) | (_spread(q[:, 2]) << np.uint64(2))
    )


def build(lo: np.ndarray, hi: np.ndarray, units: np.ndarray, dtype: Any) -> Hierarchy:
    """The hierarchy over ``units`` (their boxes ``lo``, ``hi``: (n, 3) float64): the
    units sorted along a Morton curve through their box centres, cut into leaves of
    ``LEAF`` consecutive units, and the leaves paired level by level up to the root (a
    linear BVH: a few NumPy calls per level, however many units). Boxes stored in
    ``dtype``, rounded outwards."""
    n = len(units)
    order = np.argsort(morton((lo + hi) / 2), kind="stable")
    lo, hi, units = lo[order], hi[order], units[order]
    starts = np.arange(0, n, LEAF)
    counts = np.diff(np.append(starts, n))
    # nodes in the order they are made (leaves first, the root last), renumbered at the end
    node_lo = [np.minimum.reduceat(lo, starts, axis=0)]
    node_hi = [np.maximum.reduceat(hi, starts, axis=0)]
    left = [np.full(len(starts), -1)]
    right = [np.full(len(starts), -1)]
    made = len(starts)
    level = np.arange(made)
    while len(level) > 1:
        pairs = len(level) // 2
        a, b = level[0 : 2 * pairs : 2], level[1 : 2 * pairs : 2]
        all_lo, all_hi = np.concatenate(node_lo), np.concatenate(node_hi)
        node_lo.append(np.minimum(all_lo[a], all_lo[b]))
        node_hi.append(np.maximum(all_hi[a], all_hi[b]))
        left.append(a)
        right.append(b)
        parents = np.arange(made, made + pairs)
        made += pairs
        level = np.concatenate([parents, level[2 * pairs :]])  # an odd one out waits a level
    # renumber: the root first, every parent before its children
    total = made
    left_all, right_all = np.concatenate(left), np.concatenate(right)
    new = total - 1 - np.arange(total)
    inner = left_all >= 0
    left_new = np.where(inner, new[np.maximum(left_all, 0)], -1)[::-1]
    right_new = np.where(inner, new[np.maximum(right_all, 0)], -1)[::-1]
    start = np.zeros(total, dtype=np.int64)
    count = np.zeros(total, dtype=np.int64)
    start[: len(starts)], count[: len(starts)] = starts, counts
    return Hierarchy(
        lo=_outward(np.concatenate(node_lo)[::-1].T, dtype, -np.inf),
        hi=_outward(np.concatenate(node_hi)[::-1].T, dtype, np.inf),
        left=np.ascontiguousarray(left_new),
        right=np.ascontiguousarray(right_new),
        start=np.ascontiguousarray(start[::-1]),
        count=np.ascontiguousarray(count[::-1]),
        order=units,
    )


def _outward(values: np.ndarray, dtype: Any, towards: float) -> np.ndarray:
    """``values`` in ``dtype``, each rounded away from the box (towards ``towards``)."""
    rounded = np.ascontiguousarray(values, dtype=dtype)
    if rounded.dtype != values.dtype:
        moved = (rounded < values) if towards > 0 else (rounded > values)
        rounded[moved] = np.nextafter(rounded[moved], np.array(towards, dtype=dtype))
    return rounded
