"""Freed pass arrays kept for the next pass (chapter 21 here: the C++ write-up's lesson that
a pass should not allocate its memory afresh, done the cheap way).

A pass makes many temporary arrays of a batch's size (hundreds of KiB to tens of MiB).
glibc's malloc serves each one above its mmap threshold (128 KiB at first) with fresh pages
from the kernel and hands them back when NumPy frees it, so every pass takes a page fault
per 4 KiB of every temporary: about a quarter of a path-traced render's CPU time, most of it
in the kernel. ``keep_freed_arrays`` raises the threshold to glibc's largest (32 MiB) and
the trim threshold to 256 MiB, so a freed array's memory stays in the heap and the next
pass's arrays reuse it, already mapped. It changes only where this process's malloc finds
memory (the process keeps up to 256 MiB it freed, about one pass at the default ``max_mb``),
never what a render computes; it is set once, on the first wavefront frame, and only where
the C library is glibc (elsewhere it does nothing and says so).
"""

from __future__ import annotations

import ctypes
import platform
import threading

M_TRIM_THRESHOLD = -1  # glibc's mallopt parameters (malloc.h)
M_MMAP_THRESHOLD = -3
MMAP_THRESHOLD = 32 << 20  # glibc's largest allowed on 64-bit
TRIM_THRESHOLD = 256 << 20

_lock = threading.Lock()
_set: list[bool] = []  # the answer, once known


def keep_freed_arrays() -> bool:
    """Make this process's malloc keep freed large arrays for reuse (the module docstring);
    True when it did (glibc), False where it cannot. Idempotent."""
    with _lock:
        if not _set:
            _set.append(_mallopt())
        return _set[0]


def _mallopt() -> bool:
    if platform.libc_ver()[0] != "glibc":
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    mapped = mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1
    trimmed = mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1
    return mapped and trimmed
