"""What many rays meet, all at once (chapters 5, 7, 8, 11, 14, 16): the nearest hit, whether
a shadow ray is blocked, every intersection along a line.

A batch of rays is six values, origin x, y, z and direction x, y, z: arrays, except that
the origins may be scalars when every ray of the batch starts at one point (camera rays).

Each query tests the *direct* units against all its rays, one unit at a time with the
unit's parameters as scalars: an unbounded unit (a plane) exactly; a bounded one first
against a ball holding it (a few operations per ray), then exactly for the rays that come
near. A world with more than ``DIRECT_MAX`` bounded units puts them in a hierarchy
(``bvh``) instead, whose (ray, unit) pairs are tested a primitive at a time when few
primitives are concerned, else a kind at a time with the parameters gathered per pair.
A CSG tree (chapter 16) is evaluated for the rays that reach it: its leaves' intersection
lists concatenated and sorted (stably) at every group and CSG node, and filtered column by
column at every CSG node as ``filter_intersections`` walks them.

The nearest hit is the smallest t >= 0; ties go to the primitive that comes first in the
world (the reference's stable sort), then to the earlier entry of its own list.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from variants.wavefront import geometry as G
from variants.wavefront.bvh import Hierarchy, build
from variants.wavefront.scene import (
    CONE,
    CYLINDER,
    SMOOTH,
    SPHERE,
    TORUS,
    TRIANGLE,
    Bunch,
    Combine,
    CsgTree,
    Leaf,
    Node,
    Scene,
)

INF = np.inf
DIRECT_MAX = 16  # a world with this many bounded units or fewer gets no hierarchy
FEW_PRIMS = 16  # pairs concerning this many primitives or fewer are tested one at a time
NO_PRIM = np.iinfo(np.int64).max
SAMPLE = 64  # rays sampled to judge whether a unit's ball culls anything
WIDE_MIN = 4096  # a smaller batch culls with every ball (the sample would cost more)
WIDE = 0.75  # the share of the sample near a ball above which the ball is not used

Ray = tuple[Any, Any, Any, Any, Any, Any]
Three = tuple[Any, Any, Any]


@dataclass
class Index:
    """How a scene's units are reached: ``direct`` ones (in world order) tested against
    every ray, each with its ball (``ball``: x, y, z, radius², inf for none), the rest
    through ``hierarchy`` (None: none)."""

    scene: Scene
    direct: list[int]
    ball: list[tuple[float, float, float, float]]
    hierarchy: Hierarchy | None
    solid: list[bool]  # per direct unit: a sphere, which holds every point between its hits


def index(scene: Scene) -> Index:
    """The direct units and the hierarchy over the bounded ones of a big world."""
    bounded = ~np.isnan(scene.unit_lo).any(axis=1)
    units = np.flatnonzero(bounded)
    hierarchy = None
    direct = np.arange(scene.n_units)
    if len(units) > DIRECT_MAX:
        hierarchy = build(scene.unit_lo[units], scene.unit_hi[units], units, scene.dtype)
        direct = np.flatnonzero(~bounded)
    balls = []
    for unit in direct.tolist():
        x, y, z, r = (float(v) for v in scene.unit_ball[:, unit])
        # generous: the ball only decides which rays get the exact test
        r = r * 1.0001 + 1e-6 * (1 + abs(x) + abs(y) + abs(z))
        balls.append((x, y, z, r * r))
    solid = [
        bool(scene.unit_prim[unit] >= 0 and scene.kind[scene.unit_prim[unit]] == SPHERE)
        for unit in direct.tolist()
    ]
    return Index(scene, direct.tolist(), balls, hierarchy, solid)


# ------------------------------------------------------------------ one unit, or pairs


def split(ids: np.ndarray, count: int, few: int = FEW_PRIMS) -> list[tuple[int, Any]] | None:
    """(id, rows) for each id present among ``ids`` (0 .. count - 1), rows a slice when
    there is one id; None when there are more than ``few``."""
    if not len(ids):
        return []
    first = int(ids[0])
    if count == 1 or not (ids != first).any():
        return [(first, slice(None))]
    present = np.flatnonzero(np.bincount(ids, minlength=count))
    if len(present) > few:
        return None
    return [(int(i), np.flatnonzero(ids == i)) for i in present]


def params(scene: Scene, kind: int, prims: Any, normals: bool = False) -> Any:
    """A primitive's own parameters (scalars for one, arrays for many): what its
    intersection needs (cylinders and cones: minimum, maximum, closed; triangles: p1, e1,
    e2) or, with ``normals``, its normal (triangles: the face normal; smooth triangles:
    n1, n2, n3)."""
    row = scene.row[prims]
    if kind in (CYLINDER, CONE, TORUS):
        return scene.caps[:, row]
    if kind in (TRIANGLE, SMOOTH) and not normals:
        return scene.tri[0:9, row]
    if kind == TRIANGLE:
        return scene.tri[9:12, row]
    if kind == SMOOTH:
        return scene.smooth[:, row]
    return ()


def prim_slots(
    scene: Scene, prims: Any, kind: int, ray: Ray, eps: float
) -> tuple[list[Any], Any, Any]:
    """Chapter 9's ``intersect``: the intersection list (one t array per slot), u and v of
    primitives ``prims`` (one, or one per ray) of ``kind``."""
    m = scene.inv[:, scene.xform[prims]]
    return G.intersect(kind, m, params(scene, kind, prims), ray, eps)


def sub(ray: Ray, rows: Any) -> Ray:
    """The rays ``rows`` of a batch (shared origins stay scalars)."""
    return tuple(a[rows] if G.per_ray(a) else a for a in ray)


def size(ray: Ray) -> int:
    return len(ray[3])


def tree_list(scene: Scene, tree: CsgTree, ray: Ray, eps: float) -> tuple[Any, Any, Any, Any]:
    """Chapter 16: a CSG tree's intersections: (t, prim, u, v), 2-D, each row sorted by t
    with the entries the operations drop set to inf."""
    return _node(scene, tree.root, ray, eps)


def _node(scene: Scene, node: Node, ray: Ray, eps: float) -> tuple[Any, Any, Any, Any]:
    n = size(ray)
    if isinstance(node, Leaf):
        kind = int(scene.kind[node.prim])
        ts, u, v = prim_slots(scene, node.prim, kind, ray, eps)
        t = np.stack(ts, axis=1)
        prim = np.full(t.shape, node.prim, dtype=np.int64)
        if u is None:
            u = v = np.zeros(t.shape, dtype=t.dtype)
        else:
            u, v = u.reshape(n, 1), v.reshape(n, 1)
        return t, prim, u, v
    children = list(node.children) if isinstance(node, Bunch) else [node.left, node.right]
    if not children:
        empty = np.zeros((n, 0), dtype=ray[3].dtype)
        return empty, empty.astype(np.int64), empty, empty
    parts = [_node(scene, child, ray, eps) for child in children]
    t, prim, u, v = (np.concatenate([p[k] for p in parts], axis=1) for k in range(4))
    order = np.argsort(t, axis=1, kind="stable")
    t, prim, u, v = (np.take_along_axis(a, order, axis=1) for a in (t, prim, u, v))
    if isinstance(node, Combine):
        t = _filter(node, t, prim)
    return t, prim, u, v


def _filter(node: Combine, t: np.ndarray, prim: np.ndarray) -> np.ndarray:
    """Chapter 16's ``filter_intersections``, every row at once: walk the columns in order,
    tracking whether the ray is inside each operand."""
    t = t.copy()
    inside_left = np.zeros(len(t), dtype=bool)
    inside_right = np.zeros(len(t), dtype=bool)
    for j in range(t.shape[1]):
        present = t[:, j] < INF
        if not present.any():
            break  # sorted: nothing but empty entries from here on
        left = (prim[:, j] >= node.lo) & (prim[:, j] < node.mid)
        if node.op == 0:  # union
            allowed = (left & ~inside_right) | (~left & ~inside_left)
        elif node.op == 1:  # intersection
            allowed = (left & inside_right) | (~left & inside_left)
        else:  # difference
            allowed = (left & ~inside_right) | (~left & inside_left)
        t[present & ~allowed, j] = INF
        inside_left ^= present & left
        inside_right ^= present & ~left
    return t


@dataclass
class Lists:
    """Some rays' intersections with one unit: ``t``, a list of slot arrays (a primitive)
    or a 2-D array (a CSG tree); ``prim``, a scalar or 2-D; u, v (or None)."""

    t: Any
    prim: Any
    u: Any = None
    v: Any = None

    def table(self) -> tuple[np.ndarray, np.ndarray, Any, Any]:
        """(t, prim, u, v) as 2-D arrays, one column per slot."""
        t = self.t if isinstance(self.t, np.ndarray) else np.stack(self.t, axis=1)
        prim = self.prim if np.ndim(self.prim) != 1 else self.prim[:, None]
        prim = np.broadcast_to(prim, t.shape)
        if self.u is None:
            return t, prim, None, None
        u = self.u if self.u.ndim == 2 else self.u[:, None]
        v = self.v if self.v.ndim == 2 else self.v[:, None]
        return t, prim, np.broadcast_to(u, t.shape), np.broadcast_to(v, t.shape)

    def first(self) -> tuple[Any, Any, Any, Any, Any]:
        """Each ray's first entry with the least t >= 0: (t, slot, prim, u, v); inf where
        there is none."""
        if isinstance(self.t, np.ndarray):  # a CSG tree's list, sorted
            candidate = np.where(self.t >= 0, self.t, INF)
            slot = np.argmin(candidate, axis=1)
            pick = slot[:, None]
            t = np.take_along_axis(candidate, pick, axis=1)[:, 0]
            prim = np.take_along_axis(self.prim, pick, axis=1)[:, 0]
            u = np.take_along_axis(self.u, pick, axis=1)[:, 0]
            v = np.take_along_axis(self.v, pick, axis=1)[:, 0]
            return t, slot, prim, u, v
        t = np.where(self.t[0] >= 0, self.t[0], INF)
        slot = np.zeros(len(t), dtype=np.int64)
        for k, tk in enumerate(self.t[1:], start=1):
            closer = (tk >= 0) & (tk < t)
            np.copyto(t, tk, where=closer)
            slot[closer] = k
        return t, slot, self.prim, self.u, self.v

    def within(self, distance: Any, casts: np.ndarray) -> Any:
        """Has each ray an entry at 0 <= t < distance? A CSG tree's entries count when
        their primitive ``casts`` shadows; whether a primitive does is its caller's to ask."""
        if isinstance(self.t, np.ndarray):
            ok = (self.t >= 0) & (self.t < distance[:, None]) & casts[self.prim]
            return ok.any(axis=1)
        found = None
        for tk in self.t:
            ok = (tk >= 0) & (tk < distance)
            found = ok if found is None else found | ok
        return found


def unit_lists(scene: Scene, unit: int, ray: Ray, eps: float) -> Lists:
    """One unit's intersections with every ray of ``ray``."""
    p = int(scene.unit_prim[unit])
    if p < 0:
        return Lists(*tree_list(scene, scene.trees[int(scene.unit_tree[unit])], ray, eps))
    ts, u, v = prim_slots(scene, p, int(scene.kind[p]), ray, eps)
    return Lists(ts, p, u, v)


def _near_ball(ball: tuple[Any, Any, Any, Any], ray: Ray, dd: Any) -> np.ndarray:
    """Which rays come within the ball (x, y, z, radius²) on their lines: the squared
    distance from the centre to the line, |oc|² - (oc . d)² / |d|², at most radius²
    (computed in place on its own temporaries: the cull's cost is its memory traffic)."""
    x, y, z, r2 = ball
    ocx, ocy, ocz = x - ray[0], y - ray[1], z - ray[2]
    tca = ocx * ray[3]
    tca += ocy * ray[4]
    tca += ocz * ray[5]
    tca *= tca
    ocx *= ocx  # the origins' own arrays are never these: x - origin made them
    ocy *= ocy
    ocz *= ocz
    ocx += ocy
    ocx += ocz
    ocx -= r2
    return np.asarray(tca >= ocx * dd)


def _wide(idx: Index, ray: Ray) -> list[bool]:
    """For each direct unit: does nearly every ray come near its ball (``WIDE`` of a sample
    of ``SAMPLE`` rays, all balls at once)? Then the cull costs more than it saves: the unit
    is tested against every ray (the answers are the same: a ray the ball would cull misses
    the unit). An unbounded unit always; none in a batch under ``WIDE_MIN`` rays."""
    n = size(ray)
    if n < WIDE_MIN:
        return [ball[3] == INF for ball in idx.ball]
    some = sub(ray, slice(None, None, n // SAMPLE))
    dd = some[3] * some[3] + some[4] * some[4] + some[5] * some[5]
    x, y, z, r2 = (np.array(column)[:, None] for column in zip(*idx.ball, strict=True))
    near = _near_ball((x, y, z, r2), some, dd)
    wide: list[bool] = (np.count_nonzero(near, axis=1) >= WIDE * near.shape[1]).tolist()
    return wide


def culled(
    idx: Index, ray: Ray, skip: Any = None, inside: Three | None = None
) -> Iterator[tuple[int, Any]]:
    """(unit, rows) for every direct unit (in world order) that some ray may meet: the
    rays that come near its ball (all, a slice, for an unbounded or a wide one, ``_wide``).
    ``skip(unit)``: leave a unit out. ``inside``: a point per ray; a solid unit (a sphere)
    is asked only of the rays whose point lies in its ball (a sphere can hold a point
    between its intersections only then)."""
    dd = None
    everyone = slice(None)
    if not idx.direct:
        return
    wide = _wide(idx, ray) if inside is None else [ball[3] == INF for ball in idx.ball]
    for unit, ball, whole, solid in zip(idx.direct, idx.ball, wide, idx.solid, strict=True):
        if skip is not None and skip(unit):
            continue
        if inside is not None and solid and not whole:
            x, y, z, r2 = ball
            px, py, pz = inside[0] - x, inside[1] - y, inside[2] - z
            rows = np.flatnonzero(px * px + py * py + pz * pz <= r2)
            if len(rows):
                yield unit, rows
            continue
        if whole:
            yield unit, everyone
            continue
        if dd is None:
            dd = ray[3] * ray[3] + ray[4] * ray[4] + ray[5] * ray[5]
        rows = np.flatnonzero(_near_ball(ball, ray, dd))
        if len(rows):
            yield unit, rows


def direct_lists(
    idx: Index, ray: Ray, eps: float, skip: Any = None, inside: Three | None = None
) -> Iterator[tuple[Any, Lists]]:
    """(rows, lists) for every direct unit (in world order): the rays that may meet it
    (all: a slice) and their intersections with it. ``skip(unit)``: leave a unit out;
    ``inside``: see ``culled``."""
    scene = idx.scene
    for unit, rows in culled(idx, ray, skip, inside):
        yield rows, unit_lists(scene, unit, ray if isinstance(rows, slice) else sub(ray, rows), eps)


def pair_lists(
    idx: Index, rays: np.ndarray, units: np.ndarray, ray: Ray, eps: float
) -> Iterator[tuple[np.ndarray, Lists]]:
    """For (ray, unit) pairs: (pairs, lists) per batch of pairs of one primitive, one kind
    (parameters gathered per pair) or one CSG tree."""
    scene = idx.scene
    few = split(units, scene.n_units)
    if few is not None:
        for unit, pairs in few:
            some = np.arange(len(units))[pairs] if isinstance(pairs, slice) else pairs
            yield some, unit_lists(scene, unit, sub(ray, rays[some]), eps)
        return
    prims = scene.unit_prim[units]
    kinds = np.where(prims >= 0, scene.kind[np.maximum(prims, 0)], -1)
    for kind in np.flatnonzero(np.bincount(kinds + 1)) - 1:
        pairs = np.flatnonzero(kinds == kind)
        if kind < 0:
            trees = scene.unit_tree[units[pairs]]
            for tree in np.unique(trees).tolist():
                some = pairs[trees == tree]
                t, prim, u, v = tree_list(scene, scene.trees[tree], sub(ray, rays[some]), eps)
                yield some, Lists(t, prim, u, v)
            continue
        p = prims[pairs]
        ts, u, v = prim_slots(scene, p, int(kind), sub(ray, rays[pairs]), eps)
        yield pairs, Lists(ts, p, u, v)


def inverse_direction(ray: Ray) -> tuple[Any, Any, Any]:
    """1 / direction, a zero component replaced by the smallest normal number of its sign
    (so that a slab test never computes 0 * inf)."""
    out = []
    for d in ray[3:]:
        tiny = np.finfo(d.dtype).tiny
        out.append(np.divide(1, np.where(d == 0, np.copysign(tiny, d), d)))
    return out[0], out[1], out[2]


# ------------------------------------------------------------------------------ queries

PAIRS_PER_RAY = 8
"""A (ray, node) pair of the hierarchy's walk becomes up to ``bvh.LEAF`` (ray, unit) pairs,
each costing several times a ray's share of the batch's arrays while it is tested: the
walk takes ``cap`` / ``PAIRS_PER_RAY`` pairs at a time."""


def pair_cap(cap: int) -> int:
    return max(64, cap // PAIRS_PER_RAY)


@dataclass
class Nearest:
    """The nearest hit of every ray: t (inf: none), prim (-1: none), slot (its place in
    the primitive's or CSG tree's list), u and v (triangles)."""

    t: np.ndarray
    prim: np.ndarray
    slot: np.ndarray
    u: np.ndarray
    v: np.ndarray

    def take(self, rows: Any) -> Nearest:
        return Nearest(self.t[rows], self.prim[rows], self.slot[rows], self.u[rows], self.v[rows])


def nearest(idx: Index, ray: Ray, eps: float, cap: int) -> Nearest:
    """Chapters 5 and 7 (``intersect_world``, then ``hit``): the nearest hit of each ray."""
    n = size(ray)
    dtype = ray[3].dtype
    best = Nearest(
        np.full(n, INF, dtype=dtype),
        np.full(n, NO_PRIM, dtype=np.int64),
        np.zeros(n, dtype=np.int64),
        np.zeros(n, dtype=dtype),
        np.zeros(n, dtype=dtype),
    )
    # direct units come in world order: a later one wins only by a smaller t
    for rows, lists in direct_lists(idx, ray, eps):
        t, slot, prim, u, v = lists.first()
        if isinstance(rows, slice):
            closer = t < best.t
            np.copyto(best.t, t, where=closer)
            np.copyto(best.prim, prim, where=closer)
            np.copyto(best.slot, slot, where=closer)
            if u is not None:
                np.copyto(best.u, u, where=closer)
                np.copyto(best.v, v, where=closer)
            continue
        closer = t < best.t[rows]
        won = rows[closer]
        best.t[won] = t[closer]
        best.prim[won] = prim[closer] if G.per_ray(prim) else prim
        best.slot[won] = slot[closer]
        if u is not None:
            best.u[won] = u[closer]
            best.v[won] = v[closer]
    if idx.hierarchy is not None:
        for rays, units in idx.hierarchy.pairs(
            ray[:3], inverse_direction(ray), best.t, pair_cap(cap)
        ):
            for pairs, lists in pair_lists(idx, rays, units, ray, eps):
                _improve(best, rays[pairs], *lists.first())
    best.prim[best.prim == NO_PRIM] = -1
    return best


def _improve(best: Nearest, r: Any, t: Any, slot: Any, prim: Any, u: Any, v: Any) -> None:
    """Keep the pairs' hits that beat the best so far (a smaller t, or the same t on an
    earlier primitive); a ray may appear in several pairs."""
    prim = np.broadcast_to(prim, t.shape)
    bt = best.t[r]
    keep = (t < bt) | ((t == bt) & (t < INF) & (prim < best.prim[r]))
    if not keep.any():
        return
    r, t, slot, prim = r[keep], t[keep], slot[keep], prim[keep]
    order = np.lexsort((prim, t, r))
    first = np.ones(len(order), dtype=bool)
    first[1:] = r[order][1:] != r[order][:-1]
    pick = order[first]
    won = r[pick]
    best.t[won] = t[pick]
    best.prim[won] = prim[pick]
    best.slot[won] = slot[pick]
    if u is not None:
        best.u[won] = u[keep][pick]
        best.v[won] = v[keep][pick]


def blocked(idx: Index, ray: Ray, distance: np.ndarray, eps: float, cap: int) -> np.ndarray:
    """Chapter 8 (``is_shadowed``): does a shadow-casting primitive meet each ray at
    0 <= t < distance? A ray found blocked is tested no further."""
    scene = idx.scene
    shadow = scene.shadow
    n = size(ray)
    hit = np.zeros(n, dtype=bool)

    def no_shadow(unit: int) -> bool:
        p = int(scene.unit_prim[unit])
        if p >= 0:
            return not shadow[p]
        tree = scene.trees[int(scene.unit_tree[unit])]
        return not shadow[tree.lo : tree.hi].any()

    for unit, rows in culled(idx, ray, no_shadow):
        if hit.any():  # a ray found blocked is tested no further
            rows = np.flatnonzero(~hit) if isinstance(rows, slice) else rows[~hit[rows]]
            if not len(rows):
                continue
        whole = isinstance(rows, slice)
        lists = unit_lists(scene, unit, ray if whole else sub(ray, rows), eps)
        found = lists.within(distance if whole else distance[rows], shadow)
        hit[np.flatnonzero(found) if whole else rows[found]] = True
        if hit.all():
            return hit
    if idx.hierarchy is not None:
        live = np.flatnonzero(~hit)
        ray, distance = sub(ray, live), distance[live]
        limit = distance.copy()
        for rays, units in idx.hierarchy.pairs(
            ray[:3], inverse_direction(ray), limit, pair_cap(cap)
        ):
            open_ = limit[rays] > -INF
            rays, units = rays[open_], units[open_]
            for pairs, lists in pair_lists(idx, rays, units, ray, eps):
                r = rays[pairs]
                found = lists.within(distance[r], shadow)
                if not isinstance(lists.t, np.ndarray):  # a primitive's: does it cast one?
                    found = found & shadow[lists.prim]
                limit[r[found]] = -INF
        hit[live[limit == -INF]] = True
    return hit


@dataclass
class Records:
    """Every intersection along the rays' lines: ray, prim, slot, t, u, v (1-D, unordered)."""

    ray: np.ndarray
    prim: np.ndarray
    slot: np.ndarray
    t: np.ndarray
    u: np.ndarray
    v: np.ndarray


def records(idx: Index, ray: Ray, eps: float, cap: int, upto: Any = None) -> Records:
    """Chapter 7's ``intersect_world`` (negative t included, as its list has them), for
    chapter 11's n1 and n2 and for the book's ``intersect_world``; ``upto``: only the
    intersections at t <= upto[ray]."""
    n = size(ray)
    parts: list[tuple[Any, ...]] = []

    def add(r: np.ndarray, lists: Lists) -> None:
        t, prim, u, v = lists.table()
        rows, slot = np.nonzero(t < INF if upto is None else t <= upto[r][:, None])
        zeros = np.zeros(len(rows), dtype=t.dtype)
        parts.append(
            (
                r[rows], prim[rows, slot], slot, t[rows, slot],
                zeros if u is None else u[rows, slot], zeros if v is None else v[rows, slot],
            )
        )  # fmt: skip

    everyone = np.arange(n)
    for rows, lists in direct_lists(idx, ray, eps):
        add(everyone[rows], lists)
    if idx.hierarchy is not None:
        limit = np.full(n, INF)
        inverse = inverse_direction(ray)
        for rays, units in idx.hierarchy.pairs(
            ray[:3], inverse, limit, pair_cap(cap), whole_line=True
        ):
            for pairs, lists in pair_lists(idx, rays, units, ray, eps):
                add(rays[pairs], lists)
    if not parts:
        z = np.zeros(0, dtype=np.int64)
        f = np.zeros(0, dtype=ray[3].dtype)
        return Records(z, z, z, f, f, f)
    columns = [np.concatenate([p[k] for p in parts]) for k in range(6)]
    return Records(*columns)
