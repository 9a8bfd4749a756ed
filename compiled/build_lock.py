"""One builder per library: the processes that need a compiled library that is not built yet
(the test workers of one run, a bench's children) build it one at a time, and the ones that
waited then find it built (``one_builder``)."""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Iterator
from pathlib import Path

from compiled import compile_log


@contextlib.contextmanager
def one_builder(path: Path, what: str) -> Iterator[None]:
    """Hold the lock of the library known as ``path`` (``.<name>.lock`` beside it, an
    ``flock``) while the block runs. The lock goes with the process that holds it, however it
    ends. Where no lock can be had (no ``fcntl``, a lock file that cannot be made), the block
    runs unlocked, each process building as before. A wait is written to the compile log."""
    try:
        import fcntl
    except ImportError:  # not a POSIX system
        yield
        return
    lock = path.parent / f".{path.stem}.lock"
    try:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o600)
    except OSError:
        yield
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:  # another process builds it: wait
            started = time.time(), time.perf_counter(), time.process_time()
            fcntl.flock(fd, fcntl.LOCK_EX)
            waited, cpu = time.perf_counter() - started[1], time.process_time() - started[2]
            compile_log.record("wait", what, waited, cpu, started[0])
        yield
    finally:
        os.close(fd)  # releases the lock
