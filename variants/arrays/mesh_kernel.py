"""An OBJ model's triangles as the flattening tracers pack them (``variants.arrays.flatten``),
compiled: each triangle's corner p1, edges e1, e2 and face normal (chapter 15, the
reference's arithmetic operation by operation: ``Triangle.__post_init__``, ``face_normal``)
and its world-space box (the bonus chapter on bounding boxes, as ``flatten.world_boxes``
computes it), in one pass over the mesh's arrays, with no temporary arrays.

This file is self-contained (numba's ``cache=True`` checks only the file a function is in):
it imports no project module. ``variants.arrays.flatten`` calls it through a small shared
library (``compiled.library``), or through numba itself where no C compiler is found.
"""

import math
from typing import Any

from numba import cfunc, njit, types

NTG = 12  # per triangle in ``tg``: p1, e1, e2, normal (``variants.numba.layout``)


@njit(cache=True, error_model="numpy")
def pack_mesh(n, positions, tri, fwd, tg, bounds, pad):
    """Triangles 0 to n - 1: their corners are rows ``tri[3 t ...]`` of ``positions`` (3
    floats each); ``fwd``: object to world space, rows 0-2 of the matrix (12 floats); writes
    ``tg`` (NTG floats each) and ``bounds`` (6 each: lo, hi, padded by ``pad`` relative and
    absolute; NaN where a value is not finite). Returns n."""
    for t in range(n):
        a = 3 * tri[3 * t]
        b = 3 * tri[3 * t + 1]
        c = 3 * tri[3 * t + 2]
        p1x = positions[a]
        p1y = positions[a + 1]
        p1z = positions[a + 2]
        e1x = positions[b] - p1x
        e1y = positions[b + 1] - p1y
        e1z = positions[b + 2] - p1z
        e2x = positions[c] - p1x
        e2y = positions[c + 1] - p1y
        e2z = positions[c + 2] - p1z
        # normalize(cross(e2, e1)); zero for a triangle without area
        nx = e2y * e1z - e2z * e1y
        ny = e2z * e1x - e2x * e1z
        nz = e2x * e1y - e2y * e1x
        length = math.sqrt(nx * nx + ny * ny + nz * nz + 0.0)
        if length == 0.0:
            nx = 0.0
            ny = 0.0
            nz = 0.0
        else:
            nx = nx / length
            ny = ny / length
            nz = nz / length
        g = NTG * t
        tg[g] = p1x
        tg[g + 1] = p1y
        tg[g + 2] = p1z
        tg[g + 3] = e1x
        tg[g + 4] = e1y
        tg[g + 5] = e1z
        tg[g + 6] = e2x
        tg[g + 7] = e2y
        tg[g + 8] = e2z
        tg[g + 9] = nx
        tg[g + 10] = ny
        tg[g + 11] = nz
        finite = True
        for k in range(3):
            lo = 0.0
            hi = 0.0
            for j in range(3):
                v = a if j == 0 else (b if j == 1 else c)
                x = positions[v]
                y = positions[v + 1]
                z = positions[v + 2]
                w = fwd[4 * k] * x + fwd[4 * k + 1] * y + fwd[4 * k + 2] * z + fwd[4 * k + 3]
                if j == 0:
                    lo = w
                    hi = w
                else:
                    lo = min(lo, w)
                    hi = max(hi, w)
            grow = pad * (1.0 + abs(lo) + abs(hi))
            bounds[6 * t + k] = lo - grow
            bounds[6 * t + 3 + k] = hi + grow
            finite = finite and math.isfinite(lo - grow) and math.isfinite(hi + grow)
        if not finite:
            for k in range(6):
                bounds[6 * t + k] = math.nan
    return n


def make_entry(cache: bool) -> Any:
    """``pack_mesh`` as a C function over raw pointers (numba's ``cfunc``): ``int64
    f(int64 n, double *positions, int32 *tri, double *fwd, double *tg, double *bounds,
    double pad)``; ``cache``: numba's disk cache."""
    fp = types.CPointer(types.float64)
    signature = types.int64(types.int64, fp, types.CPointer(types.int32), fp, fp, fp, types.float64)
    flags: dict[str, Any] = {"_nrt": False, "error_model": "numpy"}
    return cfunc(signature, cache=cache, **flags)(pack_mesh.py_func)
