"""The GIL handed over quickly while a pass runs on several threads (chapter 21 here: the
wavefront's ``threads`` option).

NumPy lets go of the GIL inside its loops. A thread that comes back from one while another
thread runs Python waits for the GIL; CPython makes the holder let go only after the switch
interval (``sys.setswitchinterval``, 5 ms by default), so a pass of many short NumPy calls
spends much of its time waiting. ``quick_handoffs`` shortens the interval while threaded
passes run and puts the process's own value back when the last of them ends (a count, so
two renders on two threads of one program restore it once). It changes when threads take
turns, never what they compute.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

INTERVAL = 0.0001  # seconds; measured against 5, 1, 0.5, 0.2 and 0.05 ms (the package docstring)

_lock = threading.Lock()
_users = 0
_saved = 0.0


@contextmanager
def quick_handoffs() -> Iterator[None]:
    """Within the block, the switch interval is at most ``INTERVAL``."""
    global _users, _saved
    with _lock:
        if _users == 0:
            _saved = sys.getswitchinterval()
            sys.setswitchinterval(min(_saved, INTERVAL))
        _users += 1
    try:
        yield
    finally:
        with _lock:
            _users -= 1
            if _users == 0:
                sys.setswitchinterval(_saved)
