"""Counting the memory allocations of a render (the Go write-up's "allocations per render").

Three methods, the best one available is used and named beside every figure:

- ``hooks`` (exact): the C extension ``harness.instruments._alloccount``, built at install, wraps
  CPython's RAW, MEM and OBJ allocator domains and NumPy's data-memory handler (NEP 49) with
  counters: every allocation request, and the bytes requested, at about 1.1x the run time.
- ``nrt``: Numba's runtime statistics (``NUMBA_NRT_STATS=1`` set before numba is imported)
  count the allocations compiled code makes (counts only, no bytes); reported beside the
  hooks' figures when numba has been imported.
- ``tracemalloc`` (fallback, when the extension was not built): the blocks still allocated
  and the peak traced bytes; a lower bound, not a count of every allocation.

Worker processes (``pooled``'s) are counted with the hooks too: while a counted render runs,
``RTC_ALLOCCOUNT_DIR`` names a folder, and every Python process started then installs the
counters itself (``harness/workerhook/sitecustomize.py``, on the ``PYTHONPATH`` the harness
gives its measuring process) and writes its counts there when it exits. With the tracemalloc
fallback, workers are not counted.

Objects that CPython takes from its free lists (floats, tuples, frames and others) never
reach an allocator: every method misses them.
"""

from __future__ import annotations

import importlib
import json
import os
import sys
import tempfile
import tracemalloc
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

_alloccount: Any
try:
    _alloccount = importlib.import_module("harness.instruments._alloccount")
except ImportError:  # built without a C compiler: the tracemalloc fallback
    _alloccount = None

WORKER_DIR_VARIABLE = "RTC_ALLOCCOUNT_DIR"
WORKER_HOOK_PATH = str(Path(__file__).resolve().parent / "workerhook")
HOOKS = "hooks"
TRACEMALLOC = "tracemalloc"
FREE_LIST_NOTE = (
    "objects reused from CPython's free lists (floats, tuples, frames ...) never reach an "
    "allocator and are not counted by any method"
)
METHOD_NOTES = {
    HOOKS: "exact: every allocation request in CPython's RAW, MEM and OBJ domains and NumPy's "
    "array buffers, counted by the harness.instruments._alloccount extension",
    TRACEMALLOC: "fallback (harness.instruments._alloccount not built): blocks still allocated "
    "after the render and peak traced bytes, a lower bound",
    "nrt": "Numba runtime statistics: allocations by compiled code (counts only)",
}


def exact_available() -> bool:
    """True when the C extension was built, so counts are exact."""
    return _alloccount is not None


def best_method() -> str:
    return HOOKS if exact_available() else TRACEMALLOC


@dataclass
class Allocations:
    """What one counted render allocated.

    method: ``hooks`` or ``tracemalloc``; count, bytes: the totals (for tracemalloc: blocks
    and bytes still allocated after the render); peak_traced: tracemalloc's peak bytes;
    domains: per domain (raw, mem, obj, numpy) allocations, resizes, frees and bytes;
    nrt: allocations made by numba-compiled code (None when numba is not in use);
    workers: how many worker processes reported, and their summed count and bytes (None when
    workers cannot be counted); ``count`` and ``bytes`` include them.
    """

    method: str
    count: int
    bytes: int
    peak_traced: int | None = None
    domains: dict[str, dict[str, int]] = field(default_factory=dict)
    nrt: int | None = None
    workers: dict[str, int] | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def _nrt_allocations() -> int | None:
    """Numba's running count of NRT allocations, if numba is loaded with statistics on."""
    if "numba" not in sys.modules:
        return None
    try:
        # deferred: saves ~760 ms (numba) of a measuring process of a variant without it
        from numba.core.runtime import rtsys

        stats = rtsys.get_allocation_stats()
    except Exception:  # statistics off (NUMBA_NRT_STATS unset) or runtime not initialized
        return None
    return int(stats.alloc)


def _domain_dict(raw: dict[str, tuple[int, int, int, int]]) -> dict[str, dict[str, int]]:
    keys = ("allocations", "resizes", "frees", "bytes")
    return {name: dict(zip(keys, values, strict=True)) for name, values in raw.items()}


def count_allocations(action: Callable[[], Any], method: str | None = None) -> Allocations:
    """Run ``action()`` once and count what it allocated, by ``method`` (default: the best)."""
    method = method or best_method()
    nrt_before = _nrt_allocations()
    if method == HOOKS:
        if _alloccount is None:
            raise RuntimeError(
                "the allocation-counting extension harness.instruments._alloccount is not built"
            )
        if tracemalloc.is_tracing():
            raise RuntimeError("stop tracemalloc before counting allocations with the hooks")
        with tempfile.TemporaryDirectory(prefix="rtc-alloc-") as folder:
            os.environ[WORKER_DIR_VARIABLE] = folder
            _alloccount.install()
            try:
                _alloccount.reset()
                action()
                raw = _alloccount.counts()
            finally:
                _alloccount.uninstall()
                del os.environ[WORKER_DIR_VARIABLE]
            workers = [json.loads(p.read_text()) for p in Path(folder).glob("worker-*.json")]
        domains = _domain_dict(raw)
        count = sum(d["allocations"] + d["resizes"] for d in domains.values())
        total = sum(d["bytes"] for d in domains.values())
        result = Allocations(HOOKS, count, total, domains=domains)
        if workers:
            worker_domains = [_domain_dict(w) for w in workers]
            w_count = sum(
                d["allocations"] + d["resizes"] for w in worker_domains for d in w.values()
            )
            w_bytes = sum(d["bytes"] for w in worker_domains for d in w.values())
            result.workers = {"processes": len(workers), "count": w_count, "bytes": w_bytes}
            result.count += w_count
            result.bytes += w_bytes
    elif method == TRACEMALLOC:
        tracemalloc.start()
        try:
            before = tracemalloc.take_snapshot()
            tracemalloc.reset_peak()
            action()
            _current, peak = tracemalloc.get_traced_memory()
            after = tracemalloc.take_snapshot()
        finally:
            tracemalloc.stop()
        grown = [s for s in after.compare_to(before, "filename") if s.count_diff > 0]
        result = Allocations(
            TRACEMALLOC,
            sum(s.count_diff for s in grown),
            sum(max(0, s.size_diff) for s in grown),
            peak_traced=peak,
        )
    else:
        raise ValueError(f"unknown allocation-counting method {method!r}: use hooks or tracemalloc")
    nrt_after = _nrt_allocations()
    if nrt_before is not None and nrt_after is not None:
        result.nrt = nrt_after - nrt_before
    return result
