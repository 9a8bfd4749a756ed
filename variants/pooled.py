"""``pooled``: chapter 7's ``render`` spread over a pool of worker processes, over any inner
variant (the Go write-up's first step: one image line per job on a pool of workers).

Name and options (the grammar of ``variants.registry``)::

    pooled[workers=N,granularity=line|pixel|tile,tile=S,timeout=T]:INNER

- ``workers``: how many processes (default: the CPUs this process may use). Always spelled
  in the canonical name, since its default depends on the machine.
- ``granularity``: what one job is: an image ``line`` (the default, the write-up's unit), one
  ``pixel`` (to measure why the write-up moved to lines: a round trip per pixel), or a
  ``tile`` of S x S pixels (``tile=S``, default 16, only with ``granularity=tile``).
- ``timeout``: how many seconds a worker may stay silent (default 10) before the render
  fails; see the heartbeat below.
- ``INNER``: the variant that traces the rays (default ``naive``): ``pooled:cached``,
  ``pooled[workers=2]:prealloc``.

``PooledTracer`` is a ``Wrapper`` of the inner variant's tracer that overrides ``render``
only; every other step (and book name) is the inner variant's. ``render(c, w, settings,
progress)``:

- starts the workers with the ``spawn`` start method (a ``fork`` after numba's OpenMP
  threads have run in the parent prints "fork() called from a process already using GNU
  OpenMP" and hangs); each worker loads the inner variant from the registry by its
  canonical name and receives the camera, the world and the settings once, when it starts
  (they must pickle: the twins of ``variants.cached`` do); never per job;
- sends each worker at most ``IN_FLIGHT`` jobs at a time over its own pipe, so the parent
  always knows which jobs each worker holds; a worker traces a job with its inner tracer's
  ``render_region`` (the frame prepared once per worker, through ``Tracer.prepared``:
  ``prealloc`` builds one ``PixelTracer``, ``numba`` packs the world once), so the pixels
  are the inner variant's own;
- calls ``progress(rows)`` as jobs complete, with the number of image rows just finished;
- keeps the pool for one render only: starting it (a fresh interpreter per worker, about
  0.2 to 0.5 s) is part of every render's time;
- raises ``RenderWorkerError`` within moments when a worker dies (killed, crashed, or an
  exception in a job): the message names the worker, its pid, its exit code and the jobs it
  held; the workers are stopped and no image is returned;
- hears from every worker at least every ``HEARTBEAT_SECONDS`` (a thread in the worker sends
  a beat between its results): a worker silent for ``timeout`` seconds (stopped by SIGSTOP,
  frozen, or starved of CPU) fails the render the same way, within ``timeout`` plus a
  quarter of a second, naming the worker and whether the system sees it stopped. Before its
  first word a worker gets ``STARTUP_SECONDS`` (at least): its interpreter starts and the
  world is unpickled then, with no beat. A job that holds the GIL for longer than
  ``timeout`` (a compiled kernel that does not release it) silences the beat too: raise
  ``timeout`` for such jobs;
- leaves no traceback when its parent dies (killed, or Ctrl-C'd): a worker starts with
  SIGINT blocked, then ignores it (Ctrl-C is the parent's to handle), and a worker whose
  pipe closes exits quietly, within one heartbeat. A script that renders with this
  variant keeps its top-level code under ``if __name__ == "__main__":`` (``spawn`` imports
  the main module in every worker).
"""

from __future__ import annotations

import errno
import os
import resource
import signal
import sys
import threading
import time
import traceback
from collections import deque
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from multiprocessing import get_context
from multiprocessing.connection import Connection, wait
from typing import Any

from raytracer.camera import Camera, RenderSettings
from raytracer.canvas import Canvas
from raytracer.tracer import Progress, Tracer
from raytracer.world import World
from variants.jobs import (
    DEFAULT_TILE,
    Job,
    RowProgress,
    default_workers,
    describe_job,
    make_jobs,
    recursion_limit_at_least,
    sigint_blocked,
)
from variants.registry import (
    RenderError,
    Variant,
    VariantError,
    canonical_name,
    check_options,
    load_variant,
    parse_choice,
    parse_int,
    tracer_of,
    tracer_variant,
)
from variants.wrapper import Wrapper

NAME = "pooled"
GRANULARITIES = ("line", "pixel", "tile")
DEFAULT_GRANULARITY = "line"
MAX_WORKERS = 256
START_METHOD = "spawn"
IN_FLIGHT = 2  # jobs sent ahead to each worker, so it never waits for the parent
STOP_SECONDS = 5.0  # how long finished workers get to exit before they are terminated
HEARTBEAT_SECONDS = 0.25  # a worker's beat interval, and how often the parent checks
DEFAULT_TIMEOUT = 10  # seconds a worker may stay silent before the render fails
STARTUP_SECONDS = 60.0  # the least silence allowed before a worker's first word
MAX_TIMEOUT = 86_400
USAGE = (
    "workers=N (default: the CPU count), granularity=line|pixel|tile (default line), "
    f"tile=S (tile side in pixels, default {DEFAULT_TILE}, with granularity=tile), "
    f"timeout=T (seconds a silent worker is waited for, default {DEFAULT_TIMEOUT}); "
    "wraps INNER (pooled:INNER, default naive)"
)


class RenderWorkerError(RenderError):
    """A pooled render failed in a worker; no image was produced."""


def _unit(granularity: str, tile: int) -> str:
    return f"{tile}x{tile} tile" if granularity == "tile" else granularity


# ------------------------------------------------------------------------------ a worker


class _Link:
    """A worker's end of its pipe, shared by the job loop and the heartbeat thread (one send
    at a time). When the parent is gone (the pipe is closed) there is nobody to report to:
    the worker exits at once and quietly, whichever thread finds out."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.lock = threading.Lock()

    def send(self, message: tuple[str, int, Any]) -> None:
        try:
            with self.lock:
                self.conn.send(message)
        except (OSError, EOFError):  # BrokenPipeError, ConnectionResetError
            os._exit(0)

    def recv(self) -> Any:
        try:
            return self.conn.recv()
        except (OSError, EOFError):
            os._exit(0)

    def beat(self, interval: float) -> None:
        """Send a beat every ``interval`` seconds, for ever (a daemon thread's loop)."""
        while True:
            time.sleep(interval)
            self.send(("beat", -1, None))


def _serve(
    conn: Connection | _Link, tracer: Tracer, c: Camera, w: World, settings: RenderSettings
) -> None:
    """Trace the jobs ``conn`` brings with ``tracer.render_region`` until ``None`` (one frame:
    the tracer prepares it once, for the first job)."""
    while True:
        message = conn.recv()
        if message is None:
            return
        index, job = message
        try:
            values = list(tracer.render_region(c, w, settings, job))
        except BaseException:
            conn.send(("error", index, traceback.format_exc()))
            return
        conn.send(("done", index, values))


def _worker_main(
    conn: Connection,
    inner: str,
    c: Camera,
    w: World,
    settings: RenderSettings,
    recursion_limit: int = 1000,
) -> None:
    """One worker: start the heartbeat, load the inner variant by name, then trace the jobs
    it is sent until ``None`` with its tracer.

    Sends ``("beat", -1, None)`` every ``HEARTBEAT_SECONDS`` from a thread,
    ``("done", index, [r, g, b, ...])`` per job (row-major), or ``("error", index,
    traceback)`` and stops; ``("init-error", -1, traceback)`` if it cannot start.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    recursion_limit_at_least(recursion_limit)
    link = _Link(conn)
    link.send(("beat", -1, None))  # the first word: started
    beats = threading.Thread(
        target=link.beat, args=(HEARTBEAT_SECONDS,), name="rtc-pooled-heartbeat", daemon=True
    )
    beats.start()
    try:
        tracer = tracer_of(NAME, load_variant(inner))
    except BaseException:
        link.send(("init-error", -1, traceback.format_exc()))
        return
    _serve(link, tracer, c, w, settings)


# ------------------------------------------------------------------------------ the pool


@dataclass
class _Worker:
    number: int
    process: Any  # a multiprocessing Process
    conn: Connection
    held: deque[int]  # the jobs sent to it and not yet returned, oldest first
    heard: float  # time.monotonic() when its last message (or its start) was seen
    stopped: bool = False  # told to stop (no jobs left for it)
    broken: bool = False  # its pipe closed: it died
    talked: bool = False  # it has sent something (the startup allowance is over)
    silent: bool = False  # it stayed silent too long: killed, not asked, when closing

    @property
    def label(self) -> str:
        return f"worker {self.number} (pid {self.process.pid})"


def _process_state(pid: int | None) -> str | None:
    """The state letter Linux shows for ``pid`` (``T``: stopped, ``R``: running ...), or
    None where it cannot be read."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return None


def _silence_text(pid: int | None) -> str:
    state = _process_state(pid)
    if state in ("T", "t"):
        return "it is stopped (a SIGSTOP, Ctrl-Z or a debugger)"
    if state == "D":
        return "it is blocked in the kernel (waiting on a disk or device)"
    return "it is frozen or starved of CPU"


def _exit_text(code: int | None) -> str:
    if code is None:
        return "exit code unknown (still running)"
    if code < 0:
        try:
            return f"exit code {code} (killed by {signal.Signals(-code).name})"
        except ValueError:
            return f"exit code {code} (killed by signal {-code})"
    return f"exit code {code}"


def start_problem(error: OSError) -> str:
    """Why a worker process could not be started, from the ``OSError`` its start raised:
    the open-file limit (``ulimit -n``) named as what to raise, else the error itself."""
    if error.errno in (errno.EMFILE, errno.ENFILE):
        soft, _hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        return (
            f"too many open files (this process may open {soft}: ulimit -n); raise the "
            "limit or use fewer workers"
        )
    return f"{type(error).__name__}: {error.strerror or error}"


class _Pool:
    """Worker processes, each with its own pipe; ``results`` yields (job index, values) as
    jobs finish and raises ``RenderWorkerError`` when a worker fails."""

    def __init__(
        self,
        count: int,
        inner: str,
        c: Camera,
        w: World,
        settings: RenderSettings,
        timeout: float = DEFAULT_TIMEOUT,
    ) -> None:
        context: Any = get_context(START_METHOD)
        self.timeout = timeout
        self.workers: list[_Worker] = []
        try:
            for number in range(count):
                try:
                    parent_end, child_end = context.Pipe()
                except OSError as error:
                    raise RenderWorkerError(
                        f"pooled render: cannot start worker {number}: {start_problem(error)}"
                    ) from None
                process = context.Process(
                    target=_worker_main,
                    args=(child_end, inner, c, w, settings, sys.getrecursionlimit()),
                    name=f"rtc-pooled-{number}",
                    daemon=True,
                )
                try:
                    with sigint_blocked():
                        process.start()
                except OSError as error:  # EMFILE: the open-file limit, not the world
                    raise RenderWorkerError(
                        f"pooled render: cannot start worker {number}: {start_problem(error)}"
                    ) from None
                except Exception as error:
                    raise RenderWorkerError(
                        f"pooled render: cannot start worker {number}: the camera, world and "
                        f"settings must pickle ({type(error).__name__}: {error})"
                    ) from error
                finally:
                    child_end.close()
                self.workers.append(_Worker(number, process, parent_end, deque(), time.monotonic()))
        except BaseException:
            self.close()
            raise

    def results(self, jobs: list[Job]) -> Iterator[tuple[int, list[float]]]:
        pending = deque(range(len(jobs)))
        remaining = len(jobs)
        for worker in self.workers:
            self._feed(worker, pending, jobs)
        while remaining:
            # a worker told to stop holds no job; only the others can still fail or deliver
            by_object: dict[Any, _Worker] = {}
            for worker in self.workers:
                if not worker.stopped:
                    by_object[worker.conn] = worker
                    by_object[worker.process.sentinel] = worker
            for ready in wait(list(by_object), timeout=HEARTBEAT_SECONDS):
                worker = by_object[ready]
                if worker.stopped:
                    continue
                for index, values in self._receive(worker, jobs):
                    remaining -= 1
                    yield index, values
                if ready is worker.process.sentinel or worker.broken:
                    self._died(worker, jobs, remaining)
                self._feed(worker, pending, jobs)
            for worker in self.workers:
                if not worker.stopped:
                    self._check_heard(worker, jobs, remaining)

    def _receive(self, worker: _Worker, jobs: list[Job]) -> Iterator[tuple[int, list[float]]]:
        """Everything the worker has sent so far (``broken`` when its pipe has closed)."""
        while not worker.broken:
            try:
                if not worker.conn.poll():
                    return
                kind, index, payload = worker.conn.recv()
            except (EOFError, OSError):
                worker.broken = True  # it died: the caller reports it
                return
            worker.heard = time.monotonic()
            worker.talked = True
            if kind == "beat":
                continue
            if kind == "done":
                worker.held.remove(index)
                yield index, payload
            else:
                what = (
                    "could not start"
                    if kind == "init-error"
                    else f"failed on job {index} ({describe_job(jobs[index])})"
                )
                raise RenderWorkerError(
                    f"pooled render: {worker.label} {what}; no image is returned. "
                    f"The worker's error:\n{payload}"
                )

    def _feed(self, worker: _Worker, pending: deque[int], jobs: list[Job]) -> None:
        try:
            while pending and len(worker.held) < IN_FLIGHT:
                index = pending.popleft()
                worker.held.append(index)
                worker.conn.send((index, jobs[index]))
            if not pending and not worker.held and not worker.stopped:
                worker.stopped = True
                worker.conn.send(None)
        except (BrokenPipeError, ConnectionResetError, EOFError):
            worker.broken = True  # it died: ``results`` reports it when its sentinel fires

    def _holding(self, worker: _Worker, jobs: list[Job]) -> str:
        held = ", ".join(f"job {i} ({describe_job(jobs[i])})" for i in worker.held)
        return f"while holding {held}" if held else "while waiting for work"

    def _died(self, worker: _Worker, jobs: list[Job], remaining: int) -> None:
        worker.process.join(timeout=1.0)
        raise RenderWorkerError(
            f"pooled render: {worker.label} died with {_exit_text(worker.process.exitcode)} "
            f"{self._holding(worker, jobs)}; {len(jobs) - remaining} of {len(jobs)} jobs "
            "were done; no image is returned"
        )

    def _check_heard(self, worker: _Worker, jobs: list[Job], remaining: int) -> None:
        """A ``RenderWorkerError`` when ``worker`` has been silent for longer than allowed
        (``timeout``; before its first word, at least ``STARTUP_SECONDS``). Silence is
        counted from when its last message was read, and a message waiting unread counts as
        heard, so a parent that was itself paused does not blame its workers."""
        limit = self.timeout if worker.talked else max(self.timeout, STARTUP_SECONDS)
        silence = time.monotonic() - worker.heard
        if silence <= limit or worker.broken:
            return
        try:
            if worker.conn.poll():  # it spoke while we were busy: read on the next round
                return
        except (EOFError, OSError):
            return  # its pipe closed: its sentinel reports it
        worker.silent = True
        raise RenderWorkerError(
            f"pooled render: {worker.label} sent no heartbeat for {silence:.1f} s (the limit "
            f"is {limit:g} s: pooled[timeout=T]) {self._holding(worker, jobs)}: "
            f"{_silence_text(worker.process.pid)}; {len(jobs) - remaining} of {len(jobs)} "
            "jobs were done; no image is returned"
        )

    def close(self, timeout: float = STOP_SECONDS) -> None:
        """Stop every worker: politely when they were told to stop, else terminate."""
        for worker in self.workers:
            if worker.silent:  # a stopped process only acts on SIGKILL
                worker.process.kill()
            elif not worker.stopped:
                worker.process.terminate()
        for worker in self.workers:
            worker.process.join(timeout=timeout if worker.stopped else 1.0)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join(timeout=1.0)
            worker.conn.close()


# ------------------------------------------------------------------------------ render


class PooledTracer(Wrapper):
    """Chapter 7's ``render`` on a pool of ``workers`` processes, each tracing regions with
    the ``inner_name`` variant's tracer; every other step is ``inner``'s (the same variant's
    tracer in this process). ``granularity`` and ``tile`` choose the jobs."""

    def __init__(
        self,
        inner: Tracer,
        inner_name: str,
        workers: int,
        granularity: str = DEFAULT_GRANULARITY,
        tile: int = DEFAULT_TILE,
        timeout: float = DEFAULT_TIMEOUT,
    ) -> None:
        super().__init__(inner)
        self.inner_name = inner_name
        self.workers = workers
        self.granularity = granularity
        self.tile = tile
        self.timeout = timeout

    def render_into(
        self,
        image: Canvas,
        c: Camera,
        w: World,
        settings: RenderSettings,
        progress: Progress | None = None,
    ) -> None:
        """Chapter 7: fill ``image`` with the regions the workers trace; ``progress(rows)``
        as rows complete."""
        jobs = make_jobs(c.hsize, c.vsize, self.granularity, self.tile)
        rows = RowProgress(c.hsize, c.vsize, progress)
        pool = _Pool(min(self.workers, len(jobs)), self.inner_name, c, w, settings, self.timeout)
        try:
            for index, values in pool.results(jobs):
                self.write_region(image, jobs[index], values)
                rows.done(jobs[index])
        finally:
            pool.close()

    def explain(self, w: World) -> str:
        unit = _unit(self.granularity, self.tile)
        return (
            f"{type(self).__name__}: {self.workers} worker processes, one {unit} per job, "
            f"each tracing with {self.inner_name}; {self.inner.explain(w)}"
        )


# ------------------------------------------------------------------------------ factory


def _settings(options: Mapping[str, str]) -> tuple[int, str, int, int]:
    check_options(NAME, options, ("workers", "granularity", "tile", "timeout"))
    workers = (
        parse_int(NAME, "workers", options["workers"], 1, MAX_WORKERS)
        if "workers" in options
        else default_workers()
    )
    granularity = parse_choice(
        NAME, "granularity", options.get("granularity", DEFAULT_GRANULARITY), GRANULARITIES
    )
    tile = DEFAULT_TILE
    if "tile" in options:
        if granularity != "tile":
            raise VariantError(
                f"variant {NAME!r}: option tile={options['tile']} applies only with "
                "granularity=tile"
            )
        tile = parse_int(NAME, "tile", options["tile"], 1, 4096)
    timeout = DEFAULT_TIMEOUT
    if "timeout" in options:
        timeout = parse_int(NAME, "timeout", options["timeout"], 1, MAX_TIMEOUT)
    return workers, granularity, tile, timeout


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: ``pooled[workers=N,granularity=G,tile=S]:INNER``."""
    workers, granularity, tile, timeout = _settings(options)
    inner = inner if inner is not None else load_variant("naive")
    tracer = PooledTracer(tracer_of(NAME, inner), inner.name, workers, granularity, tile, timeout)
    spelled: dict[str, object] = {"workers": workers}
    if granularity != DEFAULT_GRANULARITY:
        spelled["granularity"] = granularity
    if granularity == "tile" and tile != DEFAULT_TILE:
        spelled["tile"] = tile
    if timeout != DEFAULT_TIMEOUT:
        spelled["timeout"] = timeout
    return tracer_variant(
        canonical_name(NAME, spelled, inner),
        f"render on {workers} worker processes, one {_unit(granularity, tile)} per job, "
        f"tracing with {inner.name}",
        tracer,
        api={**inner.api},
        overrides=inner.overrides,
        base=inner.name,
        usage=USAGE,
        tolerance=inner.tolerance,
        differences=inner.differences,
    )
