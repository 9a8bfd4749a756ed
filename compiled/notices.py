"""What compiled code tells: the start and end of every compile to the ``on_compile``
listeners (a command line shows what compiles, and that it happens once), and a one-time line
on stderr (``say``) about the kernel folder or a library built again."""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable

_lock = threading.Lock()

CompileListener = Callable[[str, float | None], object]
"""Told ``(what, None)`` when a compile starts and ``(what, seconds)`` when it ends."""
_listeners: list[CompileListener] = []
_said: set[str] = set()


def on_compile(listener: CompileListener) -> Callable[[], None]:
    """Call ``listener`` around every compile of this process (a shared library built, or
    numba compiling where none can be built): a command line shows what is compiling and
    that it happens once. Returns a function that removes the listener."""
    _listeners.append(listener)
    return lambda: _listeners.remove(listener)


def announce(what: str, seconds: float | None = None) -> None:
    """Tell the ``on_compile`` listeners: compiling ``what`` starts (``seconds`` None), or
    took ``seconds`` (a Dask worker's compiles reach the client this way)."""
    for listener in list(_listeners):
        listener(what, seconds)


def say(line: str) -> None:
    """One line on stderr about the compiled code (a library built again, a folder made
    private), once per process for each line."""
    with _lock:
        if line in _said:
            return
        _said.add(line)
    print(f"rtc: {line}", file=sys.stderr, flush=True)

