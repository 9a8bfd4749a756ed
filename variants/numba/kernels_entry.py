"""Kernel template, the last render part: the render's entry point (chapter 7), a C function
over raw pointers that renders rows k, k + T ... of a region for thread k of T with the
book's Whitted integrator (``kernels_trace.render_rows``) or, in a kernel module compiled
with ``HAS_PATH``, the path integrator (``kernels_path.path_rows``, chapter 21 here).
``make_render_entry`` compiles it with numba's ``cfunc``; ``variants.numba.specialize``
links it into a shared library, which ``render`` calls from T Python threads through
ctypes (which lets go of the GIL).
"""

from typing import Any

import numpy as np
from numba import cfunc, types

from variants.numba.kernel_flags import (
    FASTMATH,
    HAS_PATH,
    F,
)
from variants.numba.kernels_path import (
    path_rows,
)
from variants.numba.kernels_trace import (
    render_rows,
)
from variants.numba.layout import (
    INTEGRATOR_PATH,
    INTEGRATOR_PATH_CROSSED,
)

# ---- kernel template ----


def render_entry(
    out, x0, y0, x1, y1, k, step, cam, pf, pi, items, n_items, boxes, csg, balls, n_balls,
    light, n_lights, ti, tf, tg, tn, depth, samples, seed_key, eps, stack, sf, si, tb, sky,
    integrator, roulette,
):  # fmt: skip
    """The render's entry point, compiled as a C function (``make_render_entry``):
    ``integrator`` ``INTEGRATOR_PATH`` path-traces (under the sky ``sky``, with Russian
    roulette from bounce ``roulette`` on, 0: never), ``INTEGRATOR_PATH_CROSSED`` too with
    light sampling off, else the book's integrator."""
    w = (pf, pi, items, n_items, boxes, csg, balls, n_balls, light, n_lights, (ti, tf), (tg, tn))
    s = (sf, si, tb)
    if HAS_PATH and INTEGRATOR_PATH <= integrator <= INTEGRATOR_PATH_CROSSED:
        return path_rows(
            out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, s, sky, roulette,
            integrator == INTEGRATOR_PATH,
        )  # fmt: skip
    return render_rows(
        out, x0, y0, x1, y1, k, step, cam, w, depth, samples, seed_key, eps, stack, s
    )


def make_render_entry(cache):
    """Compile ``render_entry`` as a C-callable function (numba's ``cfunc``) over raw
    pointers: ``int64 f(F* out, int64 x0, int64 y0, int64 x1, int64 y1, int64 k, int64
    step, F* cam, F* pf, int64* pi, int32* items, int64 n_items, F* boxes, int64* csg, F*
    balls, int64 n_balls, F* light, int64 n_lights, int64* ti, F* tf, F* tg, F* tn, int64
    depth, int64 samples, uint64 seed_key, float64 eps, F* stack, F* sf, int64* si, F* tb,
    F* sky, int64 integrator, int64 roulette)``. Without the numba runtime: it cannot
    allocate. ``cache``: numba's disk cache (used only when the render cannot be linked as
    a shared library); without it, compiled for ``compiled.linking.link`` alone (numba's
    JIT never makes its machine code: ``link`` makes it once)."""
    real = types.float32 if F is np.float32 else types.float64
    fp = types.CPointer(real)
    ip = types.CPointer(types.int64)
    i32p = types.CPointer(types.int32)
    i64 = types.int64
    signature = types.int64(
        fp, i64, i64, i64, i64, i64, i64, fp, fp, ip, i32p, i64, fp, ip, fp, i64, fp, i64, ip, fp,
        fp, fp, i64, i64, types.uint64, types.float64, fp, fp, ip, fp, fp, i64, i64,
    )  # fmt: skip
    flags: dict[str, Any] = {"_nrt": False, "fastmath": FASTMATH, "error_model": "numpy"}
    if not cache:
        from compiled.linking import ForLinking

        return ForLinking(render_entry, signature, **flags)
    return cfunc(signature, cache=True, **flags)(render_entry)
