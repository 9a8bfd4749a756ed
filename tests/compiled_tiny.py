"""A tiny compiled function for the kernel cache's tests (``tests/test_hostile.py``): built
into a shared library by ``compiled.library`` in a second or two, where the render kernel
takes many. Self-contained, as ``compiled.library`` requires (numba's cache checks only the
file a function is in)."""

from typing import Any

from numba import cfunc, njit, types

OFFSET = 0.25  # a constant in the library's data: changing it changes every result


@njit(cache=True, error_model="numpy")
def scale(n, src, dst, k):
    """dst[i] = src[i] * k + OFFSET for i < n; returns n."""
    for i in range(n):
        dst[i] = src[i] * k + OFFSET
    return n


def make_entry(cache: bool) -> Any:
    """``scale`` as a C function: ``int64 f(int64 n, double *src, double *dst, double k)``."""
    fp = types.CPointer(types.float64)
    signature = types.int64(types.int64, fp, fp, types.float64)
    return cfunc(signature, cache=cache, _nrt=False, error_model="numpy")(scale.py_func)
