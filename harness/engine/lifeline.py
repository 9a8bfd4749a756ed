"""A measuring process's lifeline: it exits when the process that started it dies, so that a
killed ``rtc bench`` or ``rtc profile`` leaves no render running. Imports nothing heavy (a
profiled process would show it as start-up)."""

from __future__ import annotations

import os
import threading
import time


def watch_parent() -> None:
    """Exit (status 3) within half a second of the parent's death."""
    parent = os.getppid()

    def watch() -> None:
        while True:
            time.sleep(0.5)
            if os.getppid() != parent:
                os._exit(3)

    threading.Thread(target=watch, daemon=True, name="watch-parent").start()
