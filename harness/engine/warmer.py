"""Compiling numba's kernels in the background while the pure-Python rows are timed.

A fresh home holds no compiled kernel: each numba option set the bench measures (``numba``,
``numba[float32]``, ``numba[fastmath]`` ...) would compile for tens of seconds inside its
row's warm-up, one after the other, with the second core idle. ``Warmer`` runs one tiny
row of each such variant (4x3 pixels, one timed render, allocations and rays counted: the
kernels a real row loads, the ray-counting one included), one after the other, in a fresh
measuring process (``harness.engine.child``) on a thread of the bench, while the rows that
use one core and compile nothing (naive, cached, prealloc) are timed on the other core. A
row that compiles or asks for more than one core waits for it first (``before``), so no
timed row shares the machine with a compile it did not start; while it waits, the cores it
leaves idle compile too (one measuring process each, taking the next kernels in the list).
A section may add a job of its own (``add_job``: the ladder's mesh row compiles its mesh
kernels so). The kernels land on disk (``RTC_NUMBA_KERNELS``) where the row's own process
finds them.

On a one-core machine the compile would take the timed row's core: nothing runs in the
background there, and each row compiles in its own warm-up as before.
"""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, NamedTuple

from harness.engine import figures
from harness.engine.jobs import child_environment, start_child, stop_group
from harness.instruments.usage import available_cores

WARM_SIZE = [4, 3]
TELL_EVERY = 10.0  # seconds between two lines while a row waits for the compile


def compiles(name: str) -> bool:
    """Whether the variant ``name`` runs numba's compiled kernels (alone or inside a pool)."""
    return "numba" in name


def warmable(name: str) -> bool:
    """Whether the background compile takes ``name``: numba itself, whose tiny render runs in
    one process (a pool or a Dask cluster of numba would start workers on the timed row's
    core; their kernels are numba's, compiled for the plain option set)."""
    return name.startswith("numba")


def one_core_python(name: str, cores: int) -> bool:
    """Whether ``name``'s row can be timed beside a compile: it compiles nothing and asks for
    one core of the ``cores`` there are."""
    return not compiles(name) and figures.cores_asked(name, cores) == 1


def warm_task(rays: bool) -> dict[str, Any]:
    """The tiny row that loads (compiling once) the kernels a row of the variant loads: its
    render kernel, and its ray-counting one when the rows count rays (``rays``)."""
    return {
        "kind": "row", "size": WARM_SIZE, "samples": 1, "repeat": 1, "budget": None,
        "allocations": True, "rays": rays, "compare_size": WARM_SIZE,
    }  # fmt: skip


class Warmer:
    """The background compile of one bench run (see the module)."""

    def __init__(
        self, folder: Path, job: Callable[[str, bool], Mapping[str, Any]],
        log: Callable[[str], None], cores: int | None = None,
    ) -> None:  # fmt: skip
        self.folder = folder
        self.job = job  # (variant name, rays) -> its job (the run's scene, depth, threads ...)
        self.log = log
        self.cores = cores or available_cores()
        self.names: list[str] = []
        self.rays: set[str] = set()  # the names whose rows count rays
        self.jobs: list[Task] = []  # the sections' own jobs (``add_job``)
        self._pending: list[Task] = []  # what no measuring process has taken yet
        self._threads: list[threading.Thread] = []
        self._processes: list[subprocess.Popen[Any]] = []
        self._lock = threading.Lock()
        self._stopped = False
        self._started = self._ended = 0.0
        self.current: list[str] = []  # what is being compiled
        self._taken = 0  # jobs taken so far (each its own numbered folder)

    @property
    def seconds(self) -> float:
        """From the start to the end of the compile (so far, while it runs)."""
        return (self._ended or time.monotonic()) - self._started if self._started else 0.0

    @property
    def labels(self) -> list[str]:
        """What the compile does, in order: the variants' tiny rows, then the sections' jobs."""
        return [*self.names, *(task.label for task in self.jobs)]

    def add(self, names: list[str], rays: bool) -> None:
        """Compile ``names`` too (those that compile, not yet listed), before ``start``; with
        their ray-counting kernels when ``rays``."""
        self.names += [n for n in names if warmable(n) and n not in self.names]
        if rays:
            self.rays |= set(names)

    def add_job(self, label: str, module: str, job: Mapping[str, Any]) -> None:
        """Run ``python -m MODULE job.json`` too, after the variants' tiny rows: a section's
        own compile (``label`` names it in the progress lines)."""
        self.jobs.append(Task(label, module, dict(job)))

    def start(self) -> None:
        """Start compiling in the background (nothing on one core, or nothing to compile)."""
        if self._threads or not self.labels or self.cores < 2:
            return
        self.log(
            f"compiling numba's kernels for {', '.join(self.labels)} in the background while "
            "the one-core Python rows are timed"
        )
        # the jobs are made here, on the bench's thread (``job`` numbers the bench's folders)
        self._pending = [
            *(Task(name, CHILD, dict(self.job(name, name in self.rays))) for name in self.names),
            *self.jobs,
        ]
        self._started = time.monotonic()
        self._add_thread()

    def _add_thread(self) -> None:
        thread = threading.Thread(
            target=self._run, name=f"rtc-bench-warmer-{len(self._threads)}", daemon=True
        )
        self._threads.append(thread)
        thread.start()

    def _take(self) -> tuple[int, Task] | None:
        """The next job and its folder's number, or None when there is none or the run stops."""
        with self._lock:
            if self._stopped or not self._pending:
                return None
            task = self._pending.pop(0)
            self.current.append(task.label)
            self._taken += 1
            return self._taken - 1, task

    def _run(self) -> None:
        while (taken := self._take()) is not None:
            index, task = taken
            folder = self.folder / f"{index:02d}"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "job.json").write_text(json.dumps(task.job), encoding="utf-8")
            command = [sys.executable, "-m", task.module, str(folder / "job.json")]
            with open(folder / "log.txt", "w", encoding="utf-8") as log:
                with self._lock:
                    if self._stopped:
                        return
                    process = start_child(
                        command, child_environment(task.job.get("threads")), stderr=log
                    )
                    self._processes.append(process)
                process.wait()
            with self._lock:
                self.current.remove(task.label)
                self._ended = time.monotonic()

    def _alive(self) -> bool:
        return any(thread.is_alive() for thread in self._threads)

    def before(self, name: str) -> None:
        """Before ``name``'s row: wait for the compile unless the row is one-core Python. While
        it waits, the idle cores compile too: one measuring process per core."""
        if not self._threads or one_core_python(name, self.cores):
            return
        if self._alive():
            self.log(f"{name}: waiting for the background compile to finish")
            while len(self._threads) < self.cores and self._pending:
                self._add_thread()  # the timed rows wait: every core compiles
            start = time.monotonic()
            while self._alive():
                for thread in [t for t in self._threads if t.is_alive()][:1]:
                    thread.join(timeout=TELL_EVERY)
                if self._alive():
                    self.log(f"still compiling {', '.join(self.current)}'s kernels, "
                             f"{time.monotonic() - start:.0f} s so far")  # fmt: skip
        self.log(f"the background compile of {', '.join(self.labels)} took {self.seconds:.0f} s")
        self._threads = []

    def stop(self) -> None:
        """Stop the compile (the run ends or was interrupted)."""
        with self._lock:
            self._stopped = True
            running = [p for p in self._processes if p.poll() is None]
        for process in running:
            stop_group(process)
        for thread in self._threads:
            thread.join(timeout=10)


CHILD = "harness.engine.child"  # the measuring process of the variants' tiny rows


class Task(NamedTuple):
    """One background job: ``python -m MODULE job.json``; ``label`` names it on the screen."""

    label: str
    module: str
    job: dict[str, Any]
