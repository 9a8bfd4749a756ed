"""A Dask task that holds its worker until the test releases it (``tests/test_hostile.py``):
a module of its own, light to import on a worker."""

import os
import time
from pathlib import Path


def held(folder: str, release: str, index: int) -> tuple[int, int]:
    """Say it started (a file named by ``index`` and this process), wait for ``release`` to
    exist, then return ``(index, pid)``."""
    Path(folder, f"started-{index}-{os.getpid()}").touch()
    while not Path(release).exists():
        time.sleep(0.05)
    return index, os.getpid()
