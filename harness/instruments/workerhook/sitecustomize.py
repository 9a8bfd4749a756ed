"""Counting the allocations of worker processes (``pooled``'s workers) during a counted render.

This folder is put on ``PYTHONPATH`` of the harness's measuring process, so every Python
process started from it imports this module at start-up. It does nothing unless
``RTC_ALLOCCOUNT_DIR`` is set, which the harness sets only around the render whose
allocations it counts: a worker started then installs the allocation counters at once and,
when it exits normally, writes its counts to ``$RTC_ALLOCCOUNT_DIR/worker-<pid>.json``. The
harness adds them up. A worker that is killed writes nothing, and the row says how many
workers reported. Allocations made before this module runs (interpreter start-up) are not
counted.

Any other ``sitecustomize`` on the path is imported afterwards, as if this one were absent.
"""

from __future__ import annotations

import atexit
import importlib
import importlib.machinery
import importlib.util
import json
import os
import sys


def _install() -> None:
    folder = os.environ.get("RTC_ALLOCCOUNT_DIR")
    if not folder:
        return

    try:
        _alloccount = importlib.import_module("harness.instruments._alloccount")
    except ImportError:
        return

    _alloccount.install()
    _alloccount.reset()

    def report() -> None:
        counts = _alloccount.counts()
        path = os.path.join(folder, f"worker-{os.getpid()}.json")
        with open(path + ".tmp", "w") as out:
            json.dump(counts, out)
        os.replace(path + ".tmp", path)

    atexit.register(report)


def _chain() -> None:
    """Import the next ``sitecustomize`` on the path, if there is one."""
    here = os.path.dirname(os.path.abspath(__file__))
    rest = [p for p in sys.path if os.path.abspath(p or ".") != here]

    spec = importlib.machinery.PathFinder.find_spec("sitecustomize", rest)
    if spec is None or spec.loader is None:
        return
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)


_install()
_chain()
