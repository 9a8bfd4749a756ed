"""Compiling numba's kernels in the background while the pure-Python rows are timed.

A fresh home holds no compiled kernel: each numba option set the bench measures (``numba``,
``numba[float32]``, ``numba[fastmath]`` ...) would compile for tens of seconds inside its
row's warm-up, one after the other, with the second core idle. ``Warmer`` runs one tiny
row of each such variant (4x3 pixels, one timed render, allocations and rays counted: the
kernels a real row loads, the ray-counting one included), one after the other, in a fresh
measuring process (``harness.engine.child``) on a thread of the bench, while the rows that
use one core and compile nothing (naive, cached, prealloc) are timed on the other core. A
row that compiles or asks for more than one core waits for it first (``before``), so no
timed row shares the machine with a compile it did not start. The kernels land on disk
(``RTC_NUMBA_KERNELS``) where the row's own process finds them.

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
from typing import Any

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
        self._thread: threading.Thread | None = None
        self._process: subprocess.Popen[Any] | None = None
        self._stopped = False
        self.seconds = 0.0
        self.current = ""  # the variant being compiled

    def add(self, names: list[str], rays: bool) -> None:
        """Compile ``names`` too (those that compile, not yet listed), before ``start``; with
        their ray-counting kernels when ``rays``."""
        self.names += [n for n in names if warmable(n) and n not in self.names]
        if rays:
            self.rays |= set(names)

    def start(self) -> None:
        """Start compiling in the background (nothing on one core, or nothing to compile)."""
        if self._thread is not None or not self.names or self.cores < 2:
            return
        self.log(
            f"compiling numba's kernels for {', '.join(self.names)} in the background while "
            "the one-core Python rows are timed"
        )
        self._thread = threading.Thread(target=self._run, name="rtc-bench-warmer", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        start = time.monotonic()
        for index, name in enumerate(self.names):
            if self._stopped:
                return
            folder = self.folder / f"{index:02d}"
            folder.mkdir(parents=True, exist_ok=True)
            job = self.job(name, name in self.rays)
            (folder / "job.json").write_text(json.dumps(job), encoding="utf-8")
            command = [sys.executable, "-m", "harness.engine.child", str(folder / "job.json")]
            self.current = name
            with open(folder / "log.txt", "w", encoding="utf-8") as log:
                self._process = start_child(
                    command, child_environment(job.get("threads")), stderr=log
                )
                self._process.wait()
        self.seconds = time.monotonic() - start

    def before(self, name: str) -> None:
        """Before ``name``'s row: wait for the compile unless the row is one-core Python."""
        if self._thread is None or one_core_python(name, self.cores):
            return
        if self._thread.is_alive():
            self.log(f"{name}: waiting for the background compile to finish")
            start = time.monotonic()
            while self._thread.is_alive():
                self._thread.join(timeout=TELL_EVERY)
                if self._thread.is_alive():
                    self.log(f"still compiling {self.current}'s kernels, "
                             f"{time.monotonic() - start:.0f} s so far")  # fmt: skip
        self.log(f"the background compile of {', '.join(self.names)} took {self.seconds:.0f} s")
        self._thread = None

    def stop(self) -> None:
        """Stop the compile (the run ends or was interrupted)."""
        self._stopped = True
        if self._process is not None and self._process.poll() is None:
            stop_group(self._process)
        if self._thread is not None:
            self._thread.join(timeout=10)
