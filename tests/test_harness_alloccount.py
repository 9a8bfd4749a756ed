"""The allocation counter counts what it should: N new objects show as at least N."""

from __future__ import annotations

import multiprocessing
import os

import numpy as np
import pytest

from harness.instruments import alloccount
from harness.instruments.alloccount import HOOKS, TRACEMALLOC, WORKER_HOOK_PATH, count_allocations

N = 20_000

needs_extension = pytest.mark.skipif(
    not alloccount.exact_available(),
    reason="harness.instruments._alloccount was not built (no C compiler at install): "
    "the tracemalloc fallback is tested below",
)


class Thing:
    """A plain object: each one is one allocation in CPython's object domain."""


def _make_things(keep: list) -> None:
    keep.extend(Thing() for _ in range(N))


def _allocate_in_a_worker() -> None:
    things = [Thing() for _ in range(N)]
    del things


@needs_extension
def test_the_hooks_count_every_new_object():
    keep: list = []
    found = count_allocations(lambda: _make_things(keep), HOOKS)
    assert found.method == HOOKS
    assert found.domains["obj"]["allocations"] >= N
    assert found.count >= N
    assert found.bytes >= N * 16  # every object has at least a header
    # and nothing much besides: the counters are removed after the action
    empty = count_allocations(lambda: None, HOOKS)
    assert empty.count < 100


@needs_extension
def test_the_hooks_count_numpy_array_buffers():
    arrays: list = []
    found = count_allocations(lambda: arrays.extend(np.empty(1000) for _ in range(50)), HOOKS)
    assert found.domains["numpy"]["allocations"] >= 50
    assert found.domains["numpy"]["bytes"] >= 50 * 8000


@needs_extension
def test_worker_processes_count_their_own_allocations(monkeypatch):
    # the measuring process gets this PYTHONPATH from the harness (harness.engine.jobs)
    paths = [WORKER_HOOK_PATH, *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(paths))

    def run_worker() -> None:
        worker = multiprocessing.get_context("spawn").Process(target=_allocate_in_a_worker)
        worker.start()
        worker.join(timeout=60)
        assert worker.exitcode == 0

    found = count_allocations(run_worker, HOOKS)
    assert found.workers is not None
    assert found.workers["processes"] == 1
    assert found.workers["count"] >= N
    assert found.count >= found.workers["count"]


def test_the_tracemalloc_fallback_sees_objects_still_alive():
    keep: list = []
    found = count_allocations(lambda: _make_things(keep), TRACEMALLOC)
    assert found.method == TRACEMALLOC
    assert found.count >= N
    assert found.peak_traced is not None and found.peak_traced >= found.bytes > 0


def test_an_unknown_method_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown allocation-counting method 'memray'"):
        count_allocations(lambda: None, "memray")
