"""Who else used the machine during an ``rtc bench`` run, so that its timings say so.

Two benches at once each measure while the other runs; so does a bench beside a test suite.
A run records (``Watch``):

- the load average at its start and end, and the highest 1-minute load seen meanwhile
  (looked at every ``SAMPLE_SECONDS`` by a thread, and before each measuring job; the
  kernel's count of runnable processes, ours included);
- its CPU share: CPU seconds of the bench and its finished measuring processes per wall
  second (about 1 for one busy core);
- the other ``rtc bench`` runs it saw: each run leaves a lock file, ``.bench-<pid>.lock``,
  in its results folder's ``runs/`` and in a folder shared by the machine's benches
  (``LOCK_DIR``, or ``$RTC_BENCH_LOCK_DIR``), and removes it when it ends. A lock whose
  process is gone is stale and is removed; no bench ever waits on a lock.

The machine counts as shared when the load average went above the cores the run used (its
``--threads``, else every core it may use: a bench uses at most those itself), or another
bench ran meanwhile. ``Watch.finish`` then writes a note, which the run file keeps
(``"shared"``) and ``rtc report`` prints beside the run's figures.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from groundwork.files import recorded_path

LOCK_PREFIX = ".bench-"
LOCK_SUFFIX = ".lock"
SAMPLE_SECONDS = 0.5
LOCK_DIR = Path(tempfile.gettempdir()) / f"rtc-bench-{os.getuid() if hasattr(os, 'getuid') else 0}"


def load_average() -> list[float] | None:
    """The 1, 5 and 15 minute load averages, or None where the system has none."""
    try:
        return [round(value, 2) for value in os.getloadavg()]
    except (OSError, AttributeError):
        return None


PROC_STAT = Path("/proc/stat")


def _cpu_times() -> tuple[float, float] | None:
    """(busy, total) jiffies of every CPU of the machine since boot, or None without
    ``/proc/stat``."""
    try:
        first = PROC_STAT.read_text().splitlines()[0].split()
    except (OSError, IndexError):
        return None
    values = [float(v) for v in first[1:]]
    idle = values[3] + (values[4] if len(values) > 4 else 0.0)  # idle and iowait
    return sum(values) - idle, sum(values)


def busy_cores(seconds: float = 1.0) -> float | None:
    """How many of the machine's cores were busy over the next ``seconds`` (all processes,
    ours included), from ``/proc/stat``; else the 1-minute load average; None without
    either."""
    before = _cpu_times()
    time.sleep(seconds)
    if before is None:
        load = load_average()
        return None if load is None else load[0]
    after = _cpu_times()
    if after is None or after[1] <= before[1]:
        return None
    return (after[0] - before[0]) / (after[1] - before[1]) * (os.cpu_count() or 1)


def wait_for_quiet(
    cores: int,
    longest: float,
    step: float = 1.0,
    report: Callable[[str], object] | None = None,
    every: float = 10.0,
) -> str:
    """Wait until ``cores`` cores are idle (the others' work leaves room for a measurement
    asking for them), or ``longest`` seconds at most; says what it saw, for the log.
    ``report``: told how busy the machine still is every ``every`` seconds of the wait (a
    log that does not fall silent)."""
    total = os.cpu_count() or 1
    waited = reported = 0.0
    while True:
        busy = busy_cores(step)
        waited += step
        if busy is None:
            return "the machine's load is unknown here"
        if total - busy >= min(cores, total) - 0.2:
            return f"{total - busy:.1f} of {total} cores idle after {waited:.0f} s"
        if waited >= longest:
            return f"still {busy:.1f} of {total} cores busy after {waited:.0f} s"
        if report is not None and waited - reported >= every:
            report(f"still waiting: {busy:.1f} of {total} cores busy after {waited:.0f} s")
            reported = waited


def pid_alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (one of another user's counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def process_started(pid: int) -> str | None:
    """When process ``pid`` started (clock ticks after boot, from ``/proc/PID/stat``), or None
    where that cannot be read (no such process, no ``/proc``)."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text(encoding="utf-8", errors="replace")
        return text.rsplit(")", 1)[1].split()[19]
    except (OSError, IndexError):
        return None


def _command_line(pid: int) -> list[str] | None:
    try:
        raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return None
    return [part.decode("utf-8", "replace") for part in raw.split(b"\0") if part]


def is_bench(pid: int, info: Mapping[str, Any]) -> bool:
    """Whether the lock ``info`` of ``pid`` belongs to a live ``rtc bench``: the process that
    wrote it (the same pid started at the same time: a pid the system gave to another process
    since, the machine's init included, is not), or, for a lock that does not say when its
    process started, a process whose command line is an ``rtc bench``. Without ``/proc``: a
    live process."""
    if not pid_alive(pid):
        return False
    started = process_started(pid)
    if started is None:
        return True
    if info.get("process_started") is not None:
        return str(info["process_started"]) == started
    words = _command_line(pid) or []
    return "bench" in words and any(Path(word).name in ("rtc", "cli.py") or word == "rtc.cli"
                                    for word in words)  # fmt: skip


def _cpu_seconds() -> float:
    """CPU seconds of this process and of its children that have ended (the measuring
    processes, and in turn their own workers)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


class BenchLock:
    """This run's lock files, one in each of ``folders`` (made when missing); ``others``
    lists the live runs whose locks are there too."""

    def __init__(self, folders: Iterable[Path], results: Path) -> None:
        self.pid = os.getpid()
        self.paths: list[Path] = []
        info = {
            "pid": self.pid,
            "process_started": process_started(self.pid),
            "started": datetime.now(UTC).isoformat(timespec="seconds"),
            "results": str(results.resolve()),
        }
        for folder in folders:
            path = folder / f"{LOCK_PREFIX}{self.pid}{LOCK_SUFFIX}"
            try:
                folder.mkdir(parents=True, exist_ok=True)
                path.write_text(json.dumps(info), encoding="utf-8")
            except OSError:  # a lock we cannot write only makes us less observant, and one
                with contextlib.suppress(OSError):  # written in part (a full disk) goes
                    path.unlink(missing_ok=True)
                continue
            self.paths.append(path)

    def others(self) -> dict[int, dict[str, Any]]:
        """The other live benches' lock contents by pid; stale locks (their process gone,
        or no longer the bench that wrote it: ``is_bench``) are removed."""
        found: dict[int, dict[str, Any]] = {}
        for folder in {path.parent for path in self.paths}:
            for path in folder.glob(f"{LOCK_PREFIX}*{LOCK_SUFFIX}"):
                try:
                    pid = int(path.name[len(LOCK_PREFIX) : -len(LOCK_SUFFIX)])
                except ValueError:
                    continue
                if pid == self.pid:
                    continue
                try:
                    info = json.loads(path.read_text(encoding="utf-8"))
                except (OSError, ValueError):
                    info = {}
                if not is_bench(pid, info if isinstance(info, dict) else {}):
                    with contextlib.suppress(OSError):
                        path.unlink()
                    continue
                found[pid] = {
                    "pid": pid,
                    "started": str(info.get("started", "?")) if isinstance(info, dict) else "?",
                    "results": recorded_path(str(info["results"]))
                    if isinstance(info, dict) and isinstance(info.get("results"), str)
                    else "?",
                }
        return found

    def release(self) -> None:
        for path in self.paths:
            with contextlib.suppress(OSError):
                path.unlink()
        self.paths = []


class Watch:
    """The load and CPU share of one bench run, and the other benches seen during it."""

    def __init__(self, results: Path, cores: int, lock_dir: Path | None = None) -> None:
        self.cores = cores
        machine = lock_dir or Path(os.environ.get("RTC_BENCH_LOCK_DIR") or LOCK_DIR)
        self.lock = BenchLock([results / "runs", machine], results)
        self.start = load_average()
        self.peak = self.start[0] if self.start else None
        self.seen: dict[int, dict[str, Any]] = {}
        self._wall = time.monotonic()
        self._cpu = _cpu_seconds()
        self._guard = threading.Lock()
        self._done = threading.Event()
        self.sample()
        self._thread = threading.Thread(target=self._watch, name="rtc-bench-watch", daemon=True)
        self._thread.start()

    def _watch(self) -> None:
        while not self._done.wait(SAMPLE_SECONDS):
            self.sample()

    def sample(self) -> None:
        """Look again: the load now, and other benches."""
        load = load_average()
        others = self.lock.others()
        with self._guard:
            if load is not None:
                self.peak = load[0] if self.peak is None else max(self.peak, load[0])
            self.seen.update(others)

    def finish(self) -> dict[str, Any]:
        """What the run saw, for the run file: ``load`` (a dict) and ``shared`` (a note, or
        None when the machine was the run's own). Releases the locks."""
        self._stop()
        self.sample()
        self.lock.release()
        wall = time.monotonic() - self._wall
        end = load_average()
        if end is not None:
            self.peak = end[0] if self.peak is None else max(self.peak, end[0])
        load = {
            "cores": self.cores,
            "start": self.start,
            "end": end,
            "peak": self.peak,
            "cpu_share": round((_cpu_seconds() - self._cpu) / wall, 3) if wall > 0 else None,
            "other_benches": sorted(self.seen.values(), key=lambda info: info["pid"]),
        }
        return {"load": load, "shared": shared_note(load)}

    def abandon(self) -> None:
        self._stop()
        self.lock.release()

    def _stop(self) -> None:
        self._done.set()
        if self._thread is not threading.current_thread():
            self._thread.join(timeout=5)


def shared_note(load: Mapping[str, Any]) -> str | None:
    """The note for a run whose machine was shared (see the module), or None."""
    cores = int(load.get("cores") or 1)
    peak = load.get("peak")
    others = list(load.get("other_benches") or [])
    busy = isinstance(peak, (int, float)) and peak > cores
    if not busy and not others:
        return None
    parts = []
    if others:
        names = ", ".join(f"pid {o['pid']} (started {o['started']})" for o in others)
        parts.append(f"another `rtc bench` ran at the same time: {names}")
    if busy:
        start, end = load.get("start"), load.get("end")
        ends = f" ({start[0]:.2f} at the start, {end[0]:.2f} at the end)" if start and end else ""
        parts.append(
            f"the 1-minute load average reached {peak:.2f} with {cores} "
            f"core{'s' if cores != 1 else ''} in use by this run{ends}"
        )
    share = load.get("cpu_share")
    share_text = f"; the run's processes got {share:.2f} cores on average" if share else ""
    return (
        f"{'; '.join(parts)}{share_text}. Other work shared the machine: these timings are "
        "slower than the machine alone would give; measure again on a quiet machine to compare."
    )


def brief(load: Mapping[str, Any] | None) -> str:
    """A short clause for a run whose machine was shared: ``load average up to 3.40 on 2
    cores, another rtc bench running``."""
    if not load:
        return ""
    parts = []
    peak, cores = load.get("peak"), int(load.get("cores") or 1)
    if isinstance(peak, (int, float)) and peak > cores:
        parts.append(f"load average up to {peak:.2f} on {cores} core{'s' if cores != 1 else ''}")
    if load.get("other_benches"):
        parts.append("another rtc bench running")
    return ", ".join(parts) or "see the run's note"
