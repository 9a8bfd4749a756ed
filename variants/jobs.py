"""How a wrapper divides a render among workers (chapter 7's ``render``, spread out): the
jobs (regions) covering an image and their names in errors, the rows they finish for the
progress line, and what a worker process needs to start well. ``pooled`` and ``dask``
share these; neither imports the other.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Iterator
from contextlib import contextmanager

from raytracer.tracer import Progress, Region

Job = Region  # x0, y0, x1, y1: the pixels x0 <= x < x1, y0 <= y < y1
DEFAULT_TILE = 16  # a tile's side in pixels, unless the wrapper says otherwise


def default_workers() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def make_jobs(hsize: int, vsize: int, granularity: str, tile: int = DEFAULT_TILE) -> list[Job]:
    """The jobs covering an ``hsize`` x ``vsize`` image, top row first."""
    if granularity == "line":
        return [(0, y, hsize, y + 1) for y in range(vsize)]
    if granularity == "pixel":
        return [(x, y, x + 1, y + 1) for y in range(vsize) for x in range(hsize)]
    return [
        (x, y, min(x + tile, hsize), min(y + tile, vsize))
        for y in range(0, vsize, tile)
        for x in range(0, hsize, tile)
    ]


def describe_job(job: Job) -> str:
    x0, y0, x1, y1 = job
    if (x1 - x0, y1 - y0) == (1, 1):
        return f"pixel ({x0}, {y0})"
    if y1 - y0 == 1:
        return f"line {y0}" + (f" x {x0}..{x1 - 1}" if x0 != 0 else "")
    return f"tile x {x0}..{x1 - 1}, y {y0}..{y1 - 1}"


class RowProgress:
    """``progress(rows)`` called as image rows finish, while regions of a ``width`` x
    ``height`` image complete in any order (a pool's or a cluster's)."""

    def __init__(self, width: int, height: int, progress: Progress | None) -> None:
        self.left_in_row = [width] * height
        self.progress = progress

    def done(self, region: Region) -> None:
        """``region`` (x0, y0, x1, y1) is written: report the rows it finished."""
        x0, y0, x1, y1 = region
        finished = 0
        for y in range(y0, y1):
            self.left_in_row[y] -= x1 - x0
            finished += self.left_in_row[y] == 0
        if self.progress is not None and finished:
            self.progress(finished)


def recursion_limit_at_least(limit: int) -> None:
    """In a worker: the recursion limit its parent had (the scene loader raises it for a
    deeply nested scene, ``RTC_SCENE_MAX_DEPTH``), so the worker traces what the parent
    loaded; never lowered."""
    if sys.getrecursionlimit() < limit:
        sys.setrecursionlimit(limit)


@contextmanager
def sigint_blocked() -> Iterator[None]:
    """SIGINT blocked in this thread while a worker starts: the worker inherits the block
    (a Ctrl-C while its interpreter imports would otherwise end it with a traceback) until
    it ignores SIGINT, and a Ctrl-C meant for us meanwhile is not lost: another thread takes
    it, or it waits until the block ends. The resource tracker is started first: starting
    it unblocks SIGINT (CPython's own guard, bpo-33613)."""
    if not hasattr(signal, "pthread_sigmask"):  # not POSIX
        yield
        return
    # deferred: multiprocessing's resource tracker (about 0.1 s) only when a worker starts
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
