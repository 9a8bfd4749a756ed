"""CPU time and peak memory of a render, worker processes included.

CPU time of the process tree = this process's CPU time + that of its children that have been
waited for (``RUSAGE_CHILDREN``) + that of its living descendants (read from ``/proc``, on
Linux). Each process is counted once at any moment, so the difference between two readings is
the CPU time the whole tree spent in between, whether a pool's workers live on or were
reaped. Without ``/proc`` living workers are missed until they exit; ``tree_cpu_source`` says
which way was used.

Peak memory: on Linux the resident-set high-water mark (``VmHWM``) is reset before a render by
writing 5 to ``/proc/self/clear_refs``, and read after it; living descendants' own marks are
summed beside it. Elsewhere ``ru_maxrss`` (the peak of the process's whole life) is used and
labelled so.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")

PROC = Path("/proc")
_TICKS = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def _stat_fields(pid: int) -> list[str] | None:
    """The fields of /proc/PID/stat after the command name, or None if it is gone."""
    try:
        text = (PROC / str(pid) / "stat").read_text()
    except OSError:
        return None
    return text[text.rfind(")") + 2 :].split()


def _children_map() -> dict[int, list[int]]:
    tree: dict[int, list[int]] = {}
    for entry in PROC.iterdir():
        if not entry.name.isdigit():
            continue
        fields = _stat_fields(int(entry.name))
        if fields is not None:
            tree.setdefault(int(fields[1]), []).append(int(entry.name))
    return tree


def living_descendants(pid: int | None = None) -> list[int]:
    """Process ids of every living descendant of ``pid`` (default: this process); Linux."""
    if not PROC.is_dir():
        return []
    tree = _children_map()
    found: list[int] = []
    todo = list(tree.get(pid if pid is not None else os.getpid(), []))
    while todo:
        child = todo.pop()
        found.append(child)
        todo.extend(tree.get(child, []))
    return found


def _proc_cpu(pid: int) -> float:
    fields = _stat_fields(pid)
    if fields is None:
        return 0.0
    # fields[11], [12] are utime and stime (fields 14 and 15 of stat, in clock ticks)
    return (int(fields[11]) + int(fields[12])) / _TICKS


def tree_cpu_source() -> str:
    return "process tree via /proc" if PROC.is_dir() else "this process + reaped children"


def others_cpu_seconds() -> float:
    """CPU seconds used so far by this process's descendants (reaped and living)."""
    reaped = resource.getrusage(resource.RUSAGE_CHILDREN)
    living = sum(_proc_cpu(pid) for pid in living_descendants())
    return reaped.ru_utime + reaped.ru_stime + living


class TreeCpuClock:
    """CPU time of this process and its descendants between ``start()`` and ``stop()``.

    The descendants are read outside the window (reading /proc costs CPU time of its own),
    this process's time inside it, just around the work.
    """

    def start(self) -> None:
        self._others = others_cpu_seconds()
        self._own = time.process_time()

    def stop(self) -> float:
        own = time.process_time() - self._own
        return own + others_cpu_seconds() - self._others


@dataclass
class Timings:
    """Repeated timed work (a section job's renders): each call's wall seconds and the
    CPU share it got (CPU seconds of this process and its descendants over wall seconds)."""

    walls: list[float] = field(default_factory=list)
    shares: list[float] = field(default_factory=list)

    def time(self, work: Callable[..., T], *args: Any) -> T:
        """``work(*args)``, timed; its value."""
        clock = TreeCpuClock()
        clock.start()
        began = time.perf_counter()
        value = work(*args)
        wall = time.perf_counter() - began
        self.walls.append(wall)
        self.shares.append(clock.stop() / wall if wall > 0 else 0.0)
        return value

    def fields(self) -> dict[str, Any]:
        """A render job's result fields: ``render`` (the walls), ``render_median``, ``cpu``."""
        return {
            "render": self.walls,
            "render_median": statistics.median(self.walls),
            "cpu": self.shares,
        }


def _status_kib(pid: int | str, key: str) -> int | None:
    try:
        for line in (PROC / str(pid) / "status").read_text().splitlines():
            if line.startswith(key + ":"):
                return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        return None
    return None


def current_rss() -> int:
    """This process's resident set now, in bytes (0 where /proc is missing)."""
    return (_status_kib("self", "VmRSS") or 0) * 1024


def reset_peak_rss() -> bool:
    """Reset this process's resident-set high-water mark; True if the system allows it."""
    try:
        (PROC / "self" / "clear_refs").write_text("5")
    except OSError:
        return False
    return True


@dataclass(frozen=True)
class PeakMemory:
    """Peak resident memory during a render, in bytes.

    main: the rendering process; workers: the largest peak of any process it started (living
    ones: VmHWM; finished ones: their ru_maxrss, over this process's life); None without
    any; method: how ``main`` was measured.
    """

    main: int
    workers: int | None
    method: str


def peak_memory(was_reset: bool) -> PeakMemory:
    """The peak since ``reset_peak_rss()`` (when ``was_reset``), else the life-long peak."""
    scale = 1 if sys.platform == "darwin" else 1024  # ru_maxrss: bytes on macOS, else KiB
    living = [_status_kib(pid, "VmHWM") or 0 for pid in living_descendants()]
    finished = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * scale
    workers = max([kib * 1024 for kib in living] + [finished]) or None
    hwm = _status_kib("self", "VmHWM") if was_reset else None
    if hwm is not None:
        return PeakMemory(hwm * 1024, workers, "VmHWM reset before the render")
    maxrss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale
    return PeakMemory(maxrss, workers, "ru_maxrss (peak of the whole process)")


def available_cores() -> int:
    """The CPUs this process may run on (its affinity), else the machine's count."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def pin_to_cores(count: int) -> list[int]:
    """Restrict this process (and the workers it starts) to ``count`` of its CPUs."""
    try:
        cpus = sorted(os.sched_getaffinity(0))
    except AttributeError:
        return []
    chosen = cpus[: max(1, count)]
    os.sched_setaffinity(0, chosen)
    return chosen


class ProcessTimeout(RuntimeError):
    """A child ran over its time and was stopped."""


def wait_with_usage(
    process: subprocess.Popen[bytes], timeout: float | None, started: float
) -> tuple[int, float, int]:
    """Wait for ``process``: its exit status, CPU seconds (user + system, the kernel's
    accounting of that one child: ``os.wait4``) and its peak resident set in bytes; a
    ``ProcessTimeout`` (the child killed) after ``timeout`` seconds from ``started``.

    The peak is the highest ``VmHWM`` read from /proc while it runs (every few
    milliseconds): a child's ``ru_maxrss`` also counts the image it was forked from before
    it ran its program (the whole parent), so it cannot tell a small command's memory.
    Without /proc, ``ru_maxrss`` it is."""
    peak = 0
    polled = False
    while True:
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
        if pid == process.pid:
            process.returncode = os.waitstatus_to_exitcode(status)
            scale = 1 if sys.platform == "darwin" else 1024  # ru_maxrss: KiB but on macOS
            cpu = usage.ru_utime + usage.ru_stime
            return process.returncode, cpu, peak if polled else int(usage.ru_maxrss) * scale
        hwm = _status_kib(process.pid, "VmHWM")
        if hwm is not None:
            polled = True
            peak = max(peak, hwm * 1024)
        if timeout is not None and time.perf_counter() - started > timeout:
            process.kill()
            process.wait()
            raise ProcessTimeout(f"ran over {timeout:g} s and was stopped")
        time.sleep(0.003)
