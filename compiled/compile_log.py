"""A log of every compile of a run, to see where a cold run's time goes (``RTC_COMPILE_LOG``).

With ``RTC_COMPILE_LOG`` set to a file, every process of a run (the test workers and the
processes they start inherit it) appends one JSON line to it per compile:

- ``library``: a shared library built (``compiled.library.load_once``: the numba variant's
  render for one kernel configuration, the hierarchy builder, the OBJ scanner ...), its
  wall and CPU seconds, numba's compile and the C compiler's link included;
- ``numba``: numba compiling one of its dispatchers outside a library build (the book API's
  entry points of a kernel module, ``cache=True`` functions) with the argument types: a miss
  of numba's disk cache;
- ``wait``: a process that waited for another's build of the same library (the kernel
  folder's lock) instead of compiling it again.

Each line names the process, the test it ran in (pytest's ``PYTEST_CURRENT_TEST``), when
it started and the kernel folder (a compile repeated in one folder is a failure to share).
``python -m compiled.compile_log FILE`` sums a log up: how many compiles, of what, the
seconds each, what was compiled more than once and in how many folders, the tests that
paid for them.
Without ``RTC_COMPILE_LOG`` nothing is recorded and numba is not touched.
"""

from __future__ import annotations

import json
import os
import sys
import threading
import time
from collections import defaultdict
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

ENVIRONMENT = "RTC_COMPILE_LOG"
_state = threading.local()
_watching = False
folder_in_use = ""  # the kernel folder this process last used (set by compiled.folder)


def enabled() -> bool:
    return bool(os.environ.get(ENVIRONMENT))


def record(kind: str, what: str, wall: float, cpu: float, started: float) -> None:
    """Append one compile's line to the log (a no-op without ``RTC_COMPILE_LOG``)."""
    path = os.environ.get(ENVIRONMENT)
    if not path:
        return
    line = {
        "kind": kind,
        "what": what,
        "wall": round(wall, 3),
        "cpu": round(cpu, 3),
        "start": round(started, 3),
        "pid": os.getpid(),
        "test": os.environ.get("PYTEST_CURRENT_TEST", "").rsplit(" (", 1)[0],
        "folder": _folder(),
    }
    data = (json.dumps(line) + "\n").encode("utf-8")
    try:  # one write of a short line to a file opened for appending: lines never mix
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
        try:
            os.write(fd, data)
        finally:
            os.close(fd)
    except OSError as error:
        print(f"rtc: cannot write the compile log {path}: {error}", file=sys.stderr)


def _folder() -> str:
    """The kernel folder this process uses (a compile repeated in another folder is no
    failure to share: a test of the folder's rules, a home of its own), "" before any."""
    return folder_in_use


@contextmanager
def timed(kind: str, what: str) -> Iterator[None]:
    """Record the block as one compile of ``what``; numba's compiles inside it are part of
    it (not recorded again)."""
    if not enabled():
        yield
        return
    depth = getattr(_state, "inside", 0)
    _state.inside = depth + 1
    started, wall, cpu = time.time(), time.perf_counter(), time.process_time()
    try:
        yield
    finally:
        _state.inside = depth
        if depth == 0:
            record(kind, what, time.perf_counter() - wall, time.process_time() - cpu, started)


def watch_numba() -> None:
    """Record numba's compiles of its dispatchers (once per process; a no-op without
    ``RTC_COMPILE_LOG``). Called before numba compiles anything of ours."""
    global _watching
    if _watching or not enabled():
        return
    _watching = True
    from numba.core import event

    class Listener(event.Listener):
        def on_start(self, ev: Any) -> None:
            depth = getattr(_state, "inside", 0)
            _state.inside = depth + 1
            if depth == 0:
                _state.numba = (time.time(), time.perf_counter(), time.process_time())

        def on_end(self, ev: Any) -> None:
            depth = getattr(_state, "inside", 1) - 1
            _state.inside = depth
            if depth == 0:
                started, wall, cpu = _state.numba
                record(
                    "numba",
                    _describe(ev.data),
                    time.perf_counter() - wall,
                    time.process_time() - cpu,
                    started,
                )

    event.register("numba:compile", Listener())


def _describe(data: Any) -> str:
    """A dispatcher's function, its argument types and its kernel module's first docstring
    line (the feature set and configuration of a generated kernel module)."""
    function = getattr(data.get("dispatcher"), "py_func", None)
    module = getattr(function, "__module__", "?")
    name = getattr(function, "__qualname__", "?")
    doc = (getattr(sys.modules.get(module), "__doc__", None) or "").strip().splitlines()
    about = (
        f" [{doc[0].removeprefix('Generated by variants.numba.specialize: ')}]"
        if (module.startswith("rtc_numba_") and doc)
        else ""
    )
    args = ", ".join(str(arg) for arg in data.get("args", ()))
    return f"{module}.{name}({args}){about}"


def summary(lines: list[dict[str, Any]], top: int = 15) -> list[str]:
    """A log's figures, as lines of text."""
    out = []
    compiles = [line for line in lines if line["kind"] != "wait"]
    waits = [line for line in lines if line["kind"] == "wait"]
    pids = {line["pid"] for line in compiles}
    for kind in ("library", "numba"):
        some = [line for line in compiles if line["kind"] == kind]
        out.append(
            f"{kind}: {len(some)} compiles, {sum(x['wall'] for x in some):.0f} s wall, "
            f"{sum(x['cpu'] for x in some):.0f} s CPU"
        )
    out.append(
        f"{len(pids)} processes compiled; {len(waits)} waits for another's build "
        f"({sum(x['wall'] for x in waits):.0f} s)"
    )
    by_what: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for line in compiles:
        by_what[line["what"]].append(line)
    again = {what: found for what, found in by_what.items() if len(found) > 1}
    out.append(
        f"{len(by_what)} distinct things compiled; {len(again)} of them more than once "
        f"({sum(x['cpu'] for found in again.values() for x in found[1:]):.0f} s CPU again)"
    )
    for what, found in again.items():
        folders = {line.get("folder") for line in found}
        where = (
            "kernel folder not logged"
            if None in folders
            else f"in {len(folders)} kernel folders"
            if len(folders) > 1
            else "in one kernel folder"
        )
        out.append(f"  again, {where}: {len(found)}x {what[:200]}")
    out.append(f"the {top} costliest (CPU s, times compiled, what):")
    ranked = sorted(by_what.items(), key=lambda item: -sum(x["cpu"] for x in item[1]))
    for what, found in ranked[:top]:
        out.append(f"  {sum(x['cpu'] for x in found):7.1f} {len(found):3d}x {what[:300]}")
    by_test: dict[str, float] = defaultdict(float)
    for line in compiles:
        by_test[line["test"] or "(outside a test)"] += line["cpu"]
    out.append(f"the {top} tests that compiled most (CPU s):")
    for test, cpu in sorted(by_test.items(), key=lambda item: -item[1])[:top]:
        out.append(f"  {cpu:7.1f} {test}")
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python -m compiled.compile_log FILE (written under RTC_COMPILE_LOG)")
        return 2
    with open(argv[0], encoding="utf-8") as log:
        lines = [json.loads(line) for line in log if line.strip()]
    print("\n".join(summary(lines)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
