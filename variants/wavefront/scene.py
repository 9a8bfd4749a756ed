"""A world as the wavefront tracer reads it: tables (chapters 5-16).

Every leaf shape becomes a primitive (its index is its place in a depth-first walk of the
world, so comparing indices orders ties as the reference's stable sort does), with:

- ``kind`` (``SPHERE`` ... ``SMOOTH``) and ``row``, its row in its kind's own table
  (``caps`` for cylinders and cones, ``tri`` and ``smooth`` for triangles);
- ``xform``, its row in ``inv`` (world to object space, rows 0-2 of the inverse composed
  through its groups and CSG parents, chapter 14) and ``nrm`` (object to world space for
  normals: rows 0-2 of the inverse's transpose, 3x3);
- ``mat``, its row in the material tables (chapters 6, 10, 11), pattern included;
- ``shadow``: whether it casts a shadow.

Lights are tables in the world's order (``light_*``): a point light's position or an area
light's corner, its intensity, and an area light's cell edges and counts, which the path
integrator samples (one point over the whole light); the book's integrator refuses area
lights (``refuse_for_whitted``). ``emissive`` and ``sky`` are the path integrator's.

Shapes that share a transform chain (a mesh's triangles) share a row of ``inv``, shapes that
share a ``Material`` share its row. What a ray is tested against is a *unit*: a primitive
outside CSG, or a whole CSG tree (chapter 16, ``CsgTree``); a unit has a world-space box
unless it is unbounded (planes, open-ended cylinders and cones), and ``bvh`` arranges the
bounded ones.

``variants.wavefront.pack`` makes a ``Scene`` of a world.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from scene.kinds import BY_NAME, KINDS
from scene.pattern_kinds import PLAIN, pattern_kind
from variants.registry import RenderError

# primitive kinds: their numbers in the kind table (``scene.kinds``); every kind but the
# test shape renders
KIND_NAMES = tuple(kind.name for kind in KINDS if kind.renders)
SPHERE, PLANE, CUBE, CYLINDER, CONE, TORUS, TRIANGLE, SMOOTH = (
    BY_NAME[name].number
    for name in (
        "sphere", "plane", "cube", "cylinder", "cone", "torus", "triangle", "smooth_triangle"
    )
)  # fmt: skip

# pattern kinds: their numbers in the pattern table (``scene.pattern_kinds``); the passes
# vectorize chapter 10's, not the texture maps
PATTERN_KINDS = PLAIN
STRIPES, GRADIENT, RINGS, CHECKERS, TEST_PATTERN = (
    pattern_kind(name).number
    for name in ("stripe_pattern", "gradient_pattern", "ring_pattern", "checkers_pattern",
                 "test_pattern")
)  # fmt: skip

# CSG operations (chapter 16)
OPERATIONS = {"union": 0, "intersection": 1, "difference": 2}

# the Material fields the passes read; any other field must keep its default (``emissive``:
# the path integrator's, which the book's integrator ignores)
MATERIAL_FIELDS = frozenset(
    (
        "color", "ambient", "diffuse", "specular", "shininess", "reflective", "transparency",
        "refractive_index", "pattern", "emissive",
    )
)  # fmt: skip

BOX_PAD = 1e-9  # boxes grow by this much (relative, plus absolute) so rounding loses no hit


class Unsupported(RenderError, ValueError):
    """Something in the world the wavefront passes do not vectorize; the message names it.
    A ``ValueError`` for the book's API, a ``RenderError`` so that ``rtc render`` reports
    it in one line."""


@dataclass(frozen=True)
class Leaf:
    """A CSG tree's leaf: primitive ``prim``."""

    prim: int


@dataclass(frozen=True)
class Bunch:
    """A group inside a CSG tree (chapter 14): its children's intersections, sorted."""

    children: tuple[Node, ...]


@dataclass(frozen=True)
class Combine:
    """A CSG operation (chapter 16) of ``left`` (primitives ``lo`` to ``mid`` - 1) and
    ``right`` (``mid`` to ``hi`` - 1)."""

    op: int
    left: Node
    right: Node
    lo: int
    mid: int
    hi: int


Node = Leaf | Bunch | Combine


@dataclass(frozen=True)
class CsgTree:
    """A CSG shape at the top of a unit: its tree and its primitives ``lo`` to ``hi`` - 1."""

    root: Combine
    lo: int
    hi: int
    slots: int  # the most intersections its list can hold


SLOTS = tuple(kind.max_hits for kind in KINDS if kind.renders)
"""How many intersections a primitive of each kind can give (the cylinder's and the cone's:
two on the sides, one per cap)."""


@dataclass
class Scene:
    """The packed world (see the module's docstring); float tables in ``dtype``. Tables of
    several values per row (``inv``, ``nrm``, ``color``, ``pat_*``, ``caps``, ``tri``,
    ``smooth``) are stored a value at a time: ``inv[k, x]`` is value k of row x, so that
    gathering one value for many rays reads one contiguous array."""

    dtype: Any
    kind: np.ndarray
    row: np.ndarray
    xform: np.ndarray
    mat: np.ndarray
    shadow: np.ndarray
    inv: np.ndarray
    nrm: np.ndarray
    color: np.ndarray
    ambient: np.ndarray
    diffuse: np.ndarray
    specular: np.ndarray
    shininess: np.ndarray
    reflective: np.ndarray
    transparency: np.ndarray
    refractive: np.ndarray
    emissive: np.ndarray
    pattern: np.ndarray
    pat_inv: np.ndarray
    pat_a: np.ndarray
    pat_b: np.ndarray
    caps: np.ndarray  # a kind's parameters: cylinders, cones: minimum, maximum, closed (1.0 or
    # 0.0); tori: major radius, minor radius
    tri: np.ndarray  # triangles: p1, e1, e2, normal (12 values)
    smooth: np.ndarray  # smooth triangles, same rows as ``tri``: n1, n2, n3 (9 values)
    unit_prim: np.ndarray  # per unit: its primitive, or -1 for a CSG tree
    unit_tree: np.ndarray  # per unit: its CSG tree, or -1
    unit_lo: np.ndarray  # per unit: its world box (NaN rows: unbounded)
    unit_hi: np.ndarray
    unit_ball: np.ndarray  # per unit: a world-space ball holding it, (4, units): centre, radius
    trees: list[CsgTree]
    light_pos: np.ndarray
    light_int: np.ndarray
    light_edges: np.ndarray  # per light: an area light's uvec, vvec (a point light: zeros)
    light_steps: np.ndarray  # per light: an area light's usteps, vsteps (a point light: 0)
    sky: np.ndarray | None  # horizon and zenith colours, (2, 3) float64; None: no sky
    shapes: list[Any] = field(repr=False)  # the book's shape of each primitive, if any
    opaque: bool = True  # no material is transparent (n1/n2 never needed)
    mirrors: bool = False  # some material reflects or is transparent (secondary rays)

    @property
    def n_prims(self) -> int:
        return len(self.kind)

    @property
    def n_units(self) -> int:
        return len(self.unit_prim)

    def refuse_for_whitted(self) -> None:
        """``Unsupported`` if an area light is among the lights: the book's integrator in
        passes shades point lights only (the soft shadows chapter's cells are not
        vectorized)."""
        area = np.flatnonzero(self.light_steps[:, 0] > 0)
        if len(area):
            raise Unsupported(
                f"wavefront: light {int(area[0])} of the world is an AreaLight; the passes "
                "vectorize point lights only (area lights: path-traced, --integrator path)"
            )
