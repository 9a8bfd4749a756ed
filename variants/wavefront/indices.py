"""n1 and n2 at many hits at once (chapter 11's ``containers``, without a sorted list).

An object is one of the book's containers at a hit when an odd number of its intersections
come before the hit in the ray's sorted list (negative t included: the list has them; a
tie in t goes to the earlier primitive, then to the earlier entry of one primitive's
list); the containers are ordered by their latest such intersection. So for each hit it is
enough to know whether the hit's own object is a container (and its latest entry) and
which other container was entered last:

- n1: the last container's index (the hit's own object's, when it is the last), else 1;
- n2: the hit's own index when its object was not a container (the ray enters it), else
  the last other container's (the ray leaves it), else 1.

A world without a hierarchy is tallied unit by unit over the rays that come near it
(``_by_units``); with one, from every intersection along the rays (``hits.records``,
grouped by a sort: ``_by_records``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from variants.wavefront.geometry import per_ray
from variants.wavefront.hits import INF, Index, Nearest, Ray, direct_lists, records, sub


@dataclass
class Containers:
    """Per hit: is its own object a container (``inside``) and its latest entry before
    the hit (``own_t``, ``own_slot``); the last other container entered (``other``: its
    primitive, -1 none; ``other_t``, ``other_slot``)."""

    inside: np.ndarray
    own_t: np.ndarray
    own_slot: np.ndarray
    other: np.ndarray
    other_t: np.ndarray
    other_slot: np.ndarray

    @classmethod
    def empty(cls, n: int, dtype: Any) -> Containers:
        return cls(
            np.zeros(n, dtype=bool), np.full(n, -INF, dtype=dtype), np.full(n, -1),
            np.full(n, -1), np.full(n, -INF, dtype=dtype), np.full(n, -1),
        )  # fmt: skip

    def enter(self, hit: Nearest, r: np.ndarray, prim: Any, t: Any, slot: Any) -> None:
        """Containers found: rays ``r`` are inside ``prim`` (one per ray, or one for all),
        whose latest entry before the hit is (t, slot)."""
        prim = np.broadcast_to(prim, r.shape)
        own = prim == hit.prim[r]
        self.inside[r[own]] = True
        self.own_t[r[own]] = t[own]
        self.own_slot[r[own]] = slot[own]
        r, prim, t, slot = r[~own], prim[~own], t[~own], slot[~own]
        ot, op = self.other_t[r], self.other[r]
        later = (t > ot) | (
            (t == ot) & ((prim > op) | ((prim == op) & (slot > self.other_slot[r])))
        )
        r = r[later]
        self.other[r], self.other_t[r], self.other_slot[r] = prim[later], t[later], slot[later]


def _before(hit: Nearest, r: Any, t: Any, prim: Any, slot: Any) -> Any:
    """Does the intersection (t, prim, slot) of ray r come before its hit in the sorted
    list? (The hit's own entry does not.)"""
    th, ph, lh = hit.t[r], hit.prim[r], hit.slot[r]
    return np.where(
        prim == ph,
        (slot != lh) & ((t < th) | ((t == th) & (slot < lh))),
        (t < th) | ((t == th) & (prim < ph)),
    )


def _by_units(idx: Index, ray: Ray, hit: Nearest, eps: float, found: Containers) -> None:
    """Every direct unit, over the rays that come near it: for each of its primitives,
    how many of its intersections come before the hit, and the latest of them."""
    n = len(hit.t)
    everyone = np.arange(n)
    # a sphere is a container only where it holds the hit point: its ball culls by it
    point = (ray[0] + ray[3] * hit.t, ray[1] + ray[4] * hit.t, ray[2] + ray[5] * hit.t)
    for rows, lists in direct_lists(idx, ray, eps, inside=point):
        r = everyone[rows]
        t, prim, _, _ = lists.table()
        slot = np.broadcast_to(np.arange(t.shape[1]), t.shape)
        before = (t < INF) & _before(hit, r[:, None], t, prim, slot)
        prims = np.unique(prim).tolist() if per_ray(lists.prim) else [int(lists.prim)]
        for p in prims:
            mine = before if len(prims) == 1 else before & (prim == p)
            odd = mine.sum(axis=1) % 2 == 1
            if not odd.any():
                continue
            mine, tt = mine[odd], t[odd]
            latest_t = np.where(mine, tt, -INF).max(axis=1)
            latest = mine & (tt == latest_t[:, None])
            latest_slot = np.where(latest, slot[odd], -1).max(axis=1)
            found.enter(hit, r[odd], p, latest_t, latest_slot)


def _by_records(
    idx: Index, ray: Ray, hit: Nearest, eps: float, cap: int, found: Containers
) -> None:
    """Every intersection along the rays up to their hits, grouped by (ray, primitive)."""
    rec = records(idx, ray, eps, cap, upto=hit.t)
    keep = _before(hit, rec.ray, rec.t, rec.prim, rec.slot)
    r, p, t, slot = rec.ray[keep], rec.prim[keep], rec.t[keep], rec.slot[keep]
    order = np.lexsort((slot, t, p, r))  # by (ray, prim), the latest last
    r, p, t, slot = r[order], p[order], t[order], slot[order]
    last = np.ones(len(r), dtype=bool)
    last[:-1] = (r[1:] != r[:-1]) | (p[1:] != p[:-1])
    start = np.ones(len(r), dtype=bool)
    start[1:] = last[:-1]
    position = np.arange(len(r))
    count = position - np.maximum.accumulate(np.where(start, position, 0)) + 1
    container = last & (count % 2 == 1)  # each ray's (ray, prim) pairs are distinct here
    r, p, t, slot = r[container], p[container], t[container], slot[container]
    order = np.lexsort((slot, p, t, r))  # so that the latest other container comes last
    found.enter(hit, r[order], p[order], t[order], slot[order])


def refractive_indices(
    idx: Index, ray: Ray, hit: Nearest, eps: float, cap: int
) -> tuple[np.ndarray, np.ndarray]:
    """Chapter 11: (n1, n2) at each hit of ``ray``'s rays (see the module)."""
    scene = idx.scene
    n = len(hit.t)
    found = Containers.empty(n, hit.t.dtype)
    if idx.hierarchy is None:
        _by_units(idx, ray, hit, eps, found)
    else:
        _by_records(idx, ray, hit, eps, cap, found)
    one = np.ones(n, dtype=hit.t.dtype)
    has_other = found.other >= 0
    outside = np.where(has_other, scene.refractive[scene.mat[np.maximum(found.other, 0)]], one)
    own = scene.refractive[scene.mat[hit.prim]]
    later = has_other & (
        (found.other_t > found.own_t)
        | ((found.other_t == found.own_t) & (found.other > hit.prim))
        | (
            (found.other_t == found.own_t)
            & (found.other == hit.prim)
            & (found.other_slot > found.own_slot)
        )
    )
    n1 = np.where(found.inside, np.where(later, outside, own), outside)
    n2 = np.where(found.inside, outside, own)
    return n1, n2


RECORDS_PER_RAY = 16
"""n1 and n2 need every intersection along a ray: in a world with a hierarchy they are
found for ``cap`` / ``RECORDS_PER_RAY`` rays at a time, so that their lists stay within the
pass's budget. Without one, ``_by_units`` holds one unit's few slots per ray at a time, less
than a ray of the pass takes: all the hits go at once (each part costs every unit's whole
round of NumPy calls, Python time that holds the GIL)."""


def indices_in_parts(idx: Index, ray: Ray, hit: Nearest, eps: float, cap: int) -> tuple[Any, Any]:
    """``refractive_indices`` a part of the rays at a time (``RECORDS_PER_RAY``)."""
    n = len(hit.t)
    step = max(1, cap // RECORDS_PER_RAY) if idx.hierarchy is not None else max(1, cap)
    if n <= step:
        return refractive_indices(idx, ray, hit, eps, cap)
    parts = [
        refractive_indices(
            idx, sub(ray, slice(k, k + step)), hit.take(slice(k, k + step)), eps, cap
        )
        for k in range(0, n, step)
    ]
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])
