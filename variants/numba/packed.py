"""A world or shape packed for the kernels (``layout``): the tables and what they came
from, and the camera as the kernels read it (chapter 7). ``pack`` makes them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from raytracer.shapes.shape import Shape
from variants.numba import layout as L
from variants.numba.bvh import Hierarchy
from variants.numba.textures import TextureTable


@dataclass(eq=False)  # arrays: compared by identity, as an array cannot say "equal"
class Packed:
    """A packed world or shape: the arrays (see ``layout``) and what they came from.

    shapes: the leaf shape of each primitive row; capacity: the most intersections a ray
    can have with everything packed; cs_size, cs_prims: the largest CSG tree's intersection
    list and primitive count (per-thread scratch sizes, at least 1); hierarchy: how the
    items are arranged (``bvh``); sky: the world's sky (``layout`` SKY_*; black without
    one: the path integrator's, chapter 21 here).
    """

    pf: np.ndarray
    pi: np.ndarray
    items: np.ndarray
    boxes: np.ndarray
    csg: np.ndarray
    lights: np.ndarray
    shapes: list[Shape | None]
    capacity: int
    cs_size: int
    cs_prims: int
    balls: np.ndarray = field(default_factory=lambda: np.zeros((L.NBALL, 0)), repr=False)
    hierarchy: Hierarchy = field(default_factory=lambda: Hierarchy("off"))
    seconds: float = 0.0  # the time packing took, the hierarchy's build included
    textures: TextureTable = field(default_factory=TextureTable, repr=False)
    light_values: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    tg: np.ndarray = field(default_factory=lambda: np.zeros((0, L.NTG)), repr=False)
    tn: np.ndarray = field(default_factory=lambda: np.zeros((0, L.NTN)), repr=False)
    sky: np.ndarray = field(default_factory=lambda: np.zeros(L.NSKY), repr=False)
    nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, L.NNODE)), repr=False)
    _rows_by_id: dict[int, int] | None = field(default=None, repr=False)
    _texture_arrays: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)

    def row_of(self, shape: Shape) -> int:
        """The primitive row of ``shape`` (by identity), or -1."""
        if self._rows_by_id is None:
            self._rows_by_id = {id(shape): row for row, shape in enumerate(self.shapes)}
        return self._rows_by_id.get(id(shape), -1)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """(pf, pi, items, boxes, csg): the tables (2-D, one row per primitive, item ...)."""
        return self.pf, self.pi, self.items, self.boxes, self.csg

    def flat(self) -> tuple[Any, ...]:
        """(pf, pi, items, n_items, boxes, csg, balls, n_balls): the tables flattened
        (row-major; ``layout``) and the counts, as the kernels take a world."""
        return (
            flat(self.pf), flat(self.pi), flat(self.items), len(self.items),
            self.box_table(), flat(self.csg), flat(self.balls), self.balls.shape[1],
        )  # fmt: skip

    def box_table(self) -> np.ndarray:
        """The boxes flattened, then the compact nodes (where: an I_NODES item's ITEM_B),
        as ``pack`` made them: one table, handed over without a copy."""
        if not len(self.nodes):
            return flat(self.boxes)
        table = self.boxes.base
        if table is None or table is not self.nodes.base or table.ndim != 1:
            raise ValueError("numba: the compact nodes are not in the boxes' table (a bug)")
        return table  # packed as one table (``pack``): no copy

    def light_table(self) -> tuple[np.ndarray, int]:
        """(lights, n_lights): the lights flattened (``layout``), their sequences' values
        after them, and their number."""
        rows = np.ascontiguousarray(self.lights).reshape(-1)
        table = np.concatenate([rows, self.light_values.astype(rows.dtype, copy=False)])
        return (table if table.size else np.zeros(1, dtype=rows.dtype)), len(self.lights)

    def triangle_tables(self) -> tuple[np.ndarray, np.ndarray]:
        """(tg, tn): the compact triangles' corners, edges and normals, and the smooth
        ones' corner normals, flattened (``layout``)."""
        return flat(self.tg), flat(self.tn)

    def triangles(self) -> int:
        """How many primitives the rows stand for (a compact run's row, its triangles)."""
        runs = self.pi[:, L.TRI_FIRST] >= 0
        return int(np.where(runs, self.pi[:, L.TRI_COUNT], 1).sum())

    def texture_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(ti, tf): the texture patterns' records (``layout``, ``textures``), in the
        primitives' precision."""
        if self._texture_arrays is None:
            self._texture_arrays = self.textures.arrays(self.pf.dtype)
        return self._texture_arrays


def flat(table: np.ndarray) -> np.ndarray:
    """A table as the 1-D, C-contiguous array the kernels index (at least one element, so
    that a pointer to it is valid)."""
    values = np.ascontiguousarray(table).reshape(-1)
    return values if values.size else np.zeros(1, dtype=table.dtype)


@dataclass(frozen=True, eq=False)  # an array: compared by identity
class PackedCamera:
    """Chapter 7: the camera as the kernels read it (``layout`` CAM_*)."""

    array: np.ndarray
    hsize: int
    vsize: int
