"""A result computed once per test run and shared by its worker processes (pytest-xdist).

The reference pictures that the equivalence tests compare every variant with are rendered
by ``naive`` (pure Python, seconds to a minute each): every worker needing one would render
it again. ``OncePerRun.get(key, compute)`` computes it in the first process that asks, under
a lock (an ``flock`` on a file in the run's temporary folder, which the workers share), and
the others read what it wrote (a NumPy array, ``.npy``). Where no lock can be had (no
``fcntl``), each process computes it.
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np


class OncePerRun:
    """Arrays kept in ``folder`` (shared by the run's processes), and in this process."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.kept: dict[str, np.ndarray] = {}

    def get(self, key: str, compute: Callable[[], np.ndarray]) -> np.ndarray:
        if key not in self.kept:
            name = re.sub(r"[^A-Za-z0-9_.-]", "_", key)
            path = self.folder / f"{name}.npy"
            with _locked(self.folder / f".{name}.lock"):
                if path.exists():
                    found = np.load(path, allow_pickle=False)
                else:
                    found = np.asarray(compute())
                    partial = path.with_suffix(f".{os.getpid()}.partial.npy")
                    np.save(partial, found, allow_pickle=False)
                    os.replace(partial, path)
            self.kept[key] = found
        return self.kept[key]


@contextlib.contextmanager
def _locked(lock: Path) -> Iterator[None]:
    try:
        import fcntl
    except ImportError:  # not a POSIX system: each process computes it
        yield
        return
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock
