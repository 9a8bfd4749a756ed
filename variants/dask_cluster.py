"""``dask``: chapter 7's ``render`` as tiles on a Dask cluster, over any inner variant (for a
render, or a sweep, that outgrows one machine).

Name and options (the grammar of ``variants.registry``)::

    dask[workers=N,tile=S,timeout=T]:INNER
    dask[scheduler=tcp://HOST:PORT,tile=S,timeout=T]:INNER

- ``workers``: start a ``distributed.LocalCluster`` of N single-threaded worker processes
  for the render (default: the CPUs this process may use), and stop it after;
- ``scheduler``: connect to a running cluster instead (``dask scheduler`` on one machine,
  ``dask worker tcp://HOST:8786`` on the others, each with this project installed);
- ``tile``: the side of a job's square of pixels (default 32);
- ``timeout``: seconds to reach a running scheduler, and for it to have a worker (default 5);
- ``INNER``: the variant that traces the pixels (default ``naive``). Give a threaded inner
  variant one thread per worker (``dask[workers=2]:numba[threads=1]``): the workers are the
  parallelism.

``DaskTracer`` is a ``Wrapper`` that overrides ``render_into`` only. A render:

- sends the camera, world and settings to the cluster once, as the result of one small task
  (``_frame``) that every tile depends on, copied to every worker before the tiles go out
  (so that the scheduler spreads the tiles instead of keeping them beside the one copy). A
  task rather than ``scatter``: the scheduler can run it again when the workers holding it
  die, so a lost worker never loses the scene. The workers take this process's recursion
  limit (raised by the loader for a deeply nested scene);
- submits one future per tile (``trace_tile``); a worker loads the inner variant from the
  registry once (``worker_tracer``: numba's kernels compile, or load from the kernel cache,
  once per worker process, not per tile) and traces the tile with its ``render_region``,
  so the pixels are the inner variant's own;
- writes tiles as they complete and calls ``progress(rows)`` as image rows finish;
- passes on the compiles a worker starts (numba's kernels for a new kind of scene, seconds
  in every worker) to this process's ``on_compile`` listeners (``compiles_announced``), so
  ``rtc render`` says them as it says its own;
- when a worker dies, Dask runs its tiles again elsewhere (its nanny restarts it) and the
  picture is the same; so when a local cluster's worker stops answering (stopped by
  SIGSTOP, frozen) for ``WORKER_TTL_SECONDS`` (``distributed.scheduler.worker-ttl``,
  checked as often: within twice that), its nanny replaces it (a running cluster's own
  ``worker-ttl`` applies to its workers); a tile that kills workers
  ``distributed.scheduler.allowed-failures`` times in a row, or raises, fails the render
  with one ``ClusterError`` line;
- an unreachable scheduler is one ``ClusterError`` line: at once for a refused port, an
  unknown host or something else answering, after ``timeout`` seconds for silence; so is a
  worker that cannot load the inner variant, and a world that does not pickle.

``DaskTracer.session()`` keeps one cluster (and its loaded workers) across several renders:
what the benchmark uses to time start-up apart from rendering.
"""

from __future__ import annotations

import asyncio
import logging
import pickle
import re
import resource
import socket
import sys
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, suppress
from typing import Any

import numpy as np

from compiled.notices import announce, on_compile
from raytracer.camera import Camera, RenderSettings
from raytracer.canvas import Canvas
from raytracer.tracer import Progress, Region, Tracer
from raytracer.world import World
from variants.jobs import (
    RowProgress,
    default_workers,
    describe_job,
    make_jobs,
    recursion_limit_at_least,
    sigint_blocked,
)
from variants.registry import (
    RenderError,
    Unavailable,
    Variant,
    VariantError,
    canonical_name,
    check_options,
    load_variant,
    parse_int,
    tracer_of,
    tracer_variant,
)
from variants.wrapper import Wrapper

NAME = "dask"
DEFAULT_TILE = 32
DEFAULT_TIMEOUT = 5
MAX_WORKERS = 256
# open files a local cluster needs per process (itself, and each worker: its sockets, pipes,
# the monitors' /proc files), measured: 2 workers failed at ulimit -n 32, rendered at 64
FILES_PER_WORKER = 20
WORKER_TTL_SECONDS = 5  # a local worker's silence before it is replaced (pooled's: 10 s)
USAGE = (
    "workers=N (a local cluster of N single-threaded processes, default: the CPU count) or "
    "scheduler=tcp://HOST:PORT (a running cluster), "
    f"tile=S (tile side in pixels, default {DEFAULT_TILE}), "
    f"timeout=T (seconds to reach the scheduler, default {DEFAULT_TIMEOUT}); "
    "wraps INNER (dask:INNER, default naive)"
)


class ClusterError(RenderError):
    """A render on the cluster failed (no scheduler, a tile that raised or kept killing its
    workers); no image was produced."""


# ------------------------------------------------------------------------------ on a worker

_TRACERS: dict[str, Tracer] = {}  # one inner tracer per variant name, per worker process
COMPILE_TOPIC = "rtc-compile"  # the Dask event a worker logs when it starts compiling
_FORWARDING: list[bool] = []  # whether this worker process forwards its compiles


def worker_tracer(inner: str) -> Tracer:
    """The ``inner`` variant's tracer in this worker process, loaded on first use."""
    tracer = _TRACERS.get(inner)
    if tracer is None:
        tracer = _TRACERS[inner] = tracer_of(NAME, load_variant(inner))
        forward_compiles()
    return tracer


def forward_compiles() -> None:
    """Once per worker process: each compile it starts (numba's kernels: the first render
    of a new kind of scene compiles for seconds, in every worker at once) is logged as a
    Dask event under ``COMPILE_TOPIC``, which the rendering client announces."""
    if _FORWARDING:
        return

    def tell(what: str, seconds: float | None) -> None:
        if seconds is None:  # the start: the end is the render's own business
            with suppress(ValueError):  # not in a worker after all
                worker = _distributed().get_worker()
                worker.log_event(COMPILE_TOPIC, {"what": what, "worker": worker.address})

    on_compile(tell)
    _FORWARDING.append(True)


def _frame(payload: bytes, recursion_limit: int) -> tuple[Camera, World, RenderSettings]:
    """The camera, world and settings of a render (run once; every tile depends on it),
    with the parent's recursion limit (a deeply nested world needs it to be traced here,
    and pickled again for the other workers)."""
    recursion_limit_at_least(recursion_limit)
    frame: tuple[Camera, World, RenderSettings] = pickle.loads(payload)
    return frame


def trace_tile(
    inner: str,
    frame: tuple[Camera, World, RenderSettings],
    region: Region,
    recursion_limit: int = 1000,
) -> np.ndarray:
    """One tile's row-major ``[r, g, b, ...]``, traced by the inner variant's own
    ``render_region`` (the frame is the same object for every tile on this worker, so the
    tracer prepares it once), with at least the parent's recursion limit."""
    recursion_limit_at_least(recursion_limit)
    c, w, settings = frame
    return np.asarray(worker_tracer(inner).render_region(c, w, settings, region), np.float64)


# ------------------------------------------------------------------------------ the cluster


def _distributed() -> Any:
    """The ``distributed`` package, imported on first use: its import takes about a second,
    which a process that only lists the variants does not pay."""
    try:
        import distributed  # deferred: about 1 s (see above)
    except ImportError as error:  # a dependency; this names the fix if it is missing
        raise ImportError(
            "the dask variant needs the 'distributed' package: pip install distributed"
        ) from error
    except Exception as error:  # Dask reads its configuration (DASK_CONFIG ...) on import
        raise Unavailable(f"Dask's configuration cannot be read: {_one_line(error)}") from None
    return distributed


def _one_line(error: BaseException) -> str:
    """An error's message on one line: Dask's message for a malformed config file, then
    YAML's problem and where (its indented excerpt of the file left out)."""
    text = str(error)
    lines = [line.strip() for line in text.splitlines() if line and line[0] != " "]
    where = re.search(r"line (\d+), column (\d+)", text)
    at = f" (at line {where[1]}, column {where[2]})" if where else ""
    return (" ".join(line for line in lines if line) or type(error).__name__) + at


MEMORY_FRACTIONS = ("target", "spill", "pause", "terminate")


def memory_settings_problem(config: Any) -> str | None:
    """What makes a local worker's memory settings unusable (``distributed.worker.memory``:
    the fractions of its memory limit at which it spills, pauses, is restarted), as a line
    naming the setting and where it comes from; None when they are fine. Dask reads them
    only inside a starting worker, which dies with a traceback (a word as the target:
    ``MemoryError``), so they are checked before a cluster starts. ``config``: ``dask.config``."""
    for key in MEMORY_FRACTIONS:
        name = f"distributed.worker.memory.{key}"
        value = config.get(name, None)
        if value is None or value is False:
            continue
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= 1:
            variable = "DASK_" + name.upper().replace(".", "__")
            return (
                f"the Dask setting {name} is {value!r} (from {variable} or a Dask config "
                "file): expected a fraction from 0 to 1, or false"
            )
    return None


def open_files_problem(workers: int, per_worker: int, what: str) -> str | None:
    """A line naming the open-file limit (``ulimit -n``) when it is below what ``workers``
    worker processes need (``per_worker`` each, and as many for this process); else None.
    Past the limit a cluster's monitors raise in a loop, each with a traceback."""
    soft, _hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    needed = (workers + 1) * per_worker
    if soft == resource.RLIM_INFINITY or soft >= needed:
        return None
    return (
        f"{what}: this process may open only {soft} files (ulimit -n); {workers} workers "
        f"need about {needed}: raise the limit (ulimit -n {max(1024, needed)}) or use fewer "
        "workers"
    )


@contextmanager
def connected(
    scheduler: str | None, workers: int, timeout: float, inner: str | None = None
) -> Iterator[Any]:
    """A ``distributed.Client``: to ``scheduler``, or to a new local cluster of ``workers``
    single-threaded processes (closed on leaving). Every worker has loaded ``inner`` (a
    variant name) when this yields. ``ClusterError`` when the scheduler cannot be reached
    in ``timeout`` s."""
    distributed = _distributed()
    if scheduler is None:  # a local cluster: its workers read this process's settings
        import dask.config  # imported with distributed already

        problem = memory_settings_problem(dask.config) or (
            open_files_problem(workers, FILES_PER_WORKER, "dask render")
        )
        if problem:
            raise ClusterError(problem)
    quiet = logging.ERROR  # a killed worker's restart is Dask's business, not the user's
    cluster = None
    try:
        if scheduler is None:
            # Ctrl-C is ours to handle: the workers (and the cluster's event loop thread)
            # start with SIGINT blocked and keep it so; they stop when the cluster closes
            with sigint_blocked():
                cluster = distributed.LocalCluster(
                    n_workers=workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=":0",  # a free port: no clash with another cluster
                    silence_logs=quiet,
                    # a worker silent this long (stopped, frozen) is restarted by its nanny
                    # and its tiles go to the others (Dask's default waits 5 minutes)
                    scheduler_kwargs={"worker_ttl": f"{WORKER_TTL_SECONDS}s"},
                )
            address = cluster.scheduler_address
        else:
            address = scheduler
            probe(address, timeout)  # a failed Client lingers 20 s in its __del__: ask first
        client = distributed.Client(address, timeout=f"{timeout}s", set_as_default=False)
    except Exception as error:  # refused, timed out, or something else answered
        if cluster is not None:
            cluster.close()
        where = f"the scheduler at {scheduler}" if scheduler else "a local cluster"
        raise ClusterError(
            f"dask render: cannot reach {where}: {_first_line(error)}"
            + ("; is `dask scheduler` running there, and the address right?" if scheduler else "")
        ) from None
    try:
        if scheduler is not None:
            _wait_for_a_worker(client, timeout, scheduler)
        if inner is not None:
            _load_everywhere(client, inner)
        yield client
    finally:
        with suppress(Exception):
            client.close()
        if cluster is not None:
            with suppress(Exception):
                cluster.close()


def probe(address: str, timeout: float) -> None:
    """Reach ``address`` and shake hands as a client would, then hang up; raises what failed.
    A plain socket first, so a refused port or an unknown host fails at once (Dask's own
    connect retries those until its timeout); then Dask's handshake, on an event loop of its
    own (a ``Client`` that fails to start lingers for 20 s in its ``__del__``)."""
    comm = _distributed().comm
    scheme, location = comm.addressing.parse_address(address)
    if scheme in ("tcp", "tls"):
        with socket.create_connection(comm.addressing.parse_host_port(location), timeout=timeout):
            pass

    async def shake_hands() -> None:
        link = await comm.connect(address, timeout=timeout)
        await link.close()

    async def shake_hands_in_time() -> None:  # a peer that answers and then waits: no hang
        try:
            await asyncio.wait_for(shake_hands(), timeout)
        except TimeoutError:
            raise TimeoutError(f"no Dask handshake from {address} within {timeout:g} s") from None

    try:
        asyncio.run(shake_hands_in_time())
    except (OSError, TimeoutError):
        raise
    except Exception as error:  # the other end answered, but not as a Dask scheduler
        raise OSError(
            f"the other end does not speak Dask's protocol ({_first_line(error)})"
        ) from None


def _load_everywhere(client: Any, inner: str) -> None:
    """Load the inner variant on every worker, once (a worker without it, or without its
    dependencies, is one ``ClusterError`` line)."""
    try:
        client.run(worker_tracer, inner)
    except Exception as error:
        raise ClusterError(
            f"dask render: a worker cannot load {inner!r}: {_first_line(error)} (is this "
            "project, with its dependencies, installed where the workers run?)"
        ) from None


def _wait_for_a_worker(client: Any, timeout: float, scheduler: str) -> None:
    try:
        client.wait_for_workers(1, timeout=timeout)
    except (OSError, TimeoutError):
        raise ClusterError(
            f"dask render: the scheduler at {scheduler} has no workers after {timeout:g} s; "
            f"start some with `dask worker {scheduler}`"
        ) from None


@contextmanager
def compiles_announced(client: Any) -> Iterator[None]:
    """While inside: the workers' compile events reach this process's ``on_compile``
    listeners (``rtc render`` prints them) as "WHAT on worker ADDRESS"."""

    def told(event: tuple[float, Any]) -> None:
        _, message = event
        announce(f"{message['what']} on worker {message['worker']}")

    client.subscribe_topic(COMPILE_TOPIC, told)
    try:
        yield
    finally:
        with suppress(Exception):  # a cluster already gone
            client.unsubscribe_topic(COMPILE_TOPIC)


def _first_line(error: BaseException) -> str:
    text = str(error).strip().splitlines()
    return f"{type(error).__name__}: {text[0]}" if text else type(error).__name__


# ------------------------------------------------------------------------------ render


class DaskTracer(Wrapper):
    """Chapter 7's ``render`` as ``tile`` x ``tile`` jobs on a Dask cluster, each traced by
    the ``inner_name`` variant's tracer on a worker; every other step is ``inner``'s."""

    def __init__(
        self,
        inner: Tracer,
        inner_name: str,
        workers: int,
        scheduler: str | None = None,
        tile: int = DEFAULT_TILE,
        timeout: float = DEFAULT_TIMEOUT,
    ) -> None:
        super().__init__(inner)
        self.inner_name = inner_name
        self.workers = workers
        self.scheduler = scheduler
        self.tile = tile
        self.timeout = timeout
        self._client: Any = None

    @contextmanager
    def session(self) -> Iterator[Any]:
        """One cluster (its workers started and the inner variant loaded) for every render
        inside; a render outside a session starts and stops its own."""
        if self._client is not None:
            yield self._client
            return
        with connected(self.scheduler, self.workers, self.timeout, self.inner_name) as client:
            self._client = client
            try:
                yield client
            finally:
                self._client = None

    def render_into(
        self,
        image: Canvas,
        c: Camera,
        w: World,
        settings: RenderSettings,
        progress: Progress | None = None,
    ) -> None:
        """Chapter 7: fill ``image`` with the tiles the cluster traces; ``progress(rows)``
        as rows complete."""
        distributed = _distributed()
        jobs = make_jobs(c.hsize, c.vsize, "tile", self.tile)
        rows = RowProgress(c.hsize, c.vsize, progress)
        try:
            payload = pickle.dumps((c, w, settings), protocol=pickle.HIGHEST_PROTOCOL)
        except Exception as error:  # a lambda in a pattern, an open file in a shape ...
            raise ClusterError(
                f"dask render: the camera, world and settings must pickle to go to the "
                f"workers ({_first_line(error)})"
            ) from None
        with self.session() as client, compiles_announced(client):
            limit = sys.getrecursionlimit()
            key = f"rtc-frame-{time.time_ns()}"
            frame = client.submit(_frame, payload, limit, pure=False, key=key)
            # on every worker before the tiles: else the scheduler keeps the tiles beside
            # the one copy (data locality) and the other workers wait for stealing
            client.replicate([frame])
            futures = {
                client.submit(trace_tile, self.inner_name, frame, job, limit, pure=False): index
                for index, job in enumerate(jobs)
            }
            try:
                for future in distributed.as_completed(futures, loop=client.loop):
                    index = futures[future]
                    values = self._result(future, jobs[index], len(jobs))
                    self.write_region(image, jobs[index], values.tolist())
                    rows.done(jobs[index])
            finally:
                client.cancel([*futures, frame])

    def _result(self, future: Any, job: Region, count: int) -> np.ndarray:
        try:
            values: np.ndarray = future.result()
        except _distributed().KilledWorker:
            raise ClusterError(
                f"dask render: {describe_job(job)} (one of {count} tiles) killed the workers "
                "that ran it, again and again (distributed.scheduler.allowed-failures); no "
                "image is returned"
            ) from None
        except Exception as error:
            raise ClusterError(
                f"dask render: {describe_job(job)} failed on a worker: {_first_line(error)}; "
                "no image is returned"
            ) from error
        return values

    def explain(self, w: World) -> str:
        where = (
            f"the cluster at {self.scheduler}"
            if self.scheduler
            else f"a local cluster of {self.workers} single-threaded worker processes"
        )
        return (
            f"{type(self).__name__}: {self.tile}x{self.tile} tiles as futures on {where}, "
            f"each traced with {self.inner_name}; {self.inner.explain(w)}"
        )


# ------------------------------------------------------------------------------ factory


def cluster_settings(options: Mapping[str, str]) -> tuple[int, str | None, int, int]:
    """(workers, scheduler, tile, timeout) from a ``dask[...]`` name's options, checked."""
    check_options(NAME, options, ("workers", "scheduler", "tile", "timeout"))
    scheduler = options.get("scheduler")
    if scheduler is not None and "workers" in options:
        raise VariantError(
            f"variant {NAME!r}: workers=N starts a local cluster and scheduler=ADDRESS joins "
            "a running one: give one of them"
        )
    if scheduler is not None:
        _check_address(scheduler)
    workers = (
        parse_int(NAME, "workers", options["workers"], 1, MAX_WORKERS)
        if "workers" in options
        else default_workers()
    )
    tile = parse_int(NAME, "tile", options["tile"], 1, 4096) if "tile" in options else DEFAULT_TILE
    timeout = (
        parse_int(NAME, "timeout", options["timeout"], 1, 3600)
        if "timeout" in options
        else DEFAULT_TIMEOUT
    )
    return workers, scheduler, tile, timeout


def _check_address(scheduler: str) -> None:
    """A ``VariantError`` unless ``scheduler`` reads as SCHEME://HOST:PORT."""
    addressing = _distributed().comm.addressing
    try:
        scheme, location = addressing.parse_address(scheduler, strict=True)
        if scheme in ("tcp", "tls"):
            host, port = addressing.parse_host_port(location)
            if not host or not 0 < int(port) < 65536:
                raise ValueError(f"{location} has no host or a port outside 1..65535")
    except (ValueError, TypeError) as error:
        raise VariantError(
            f"variant {NAME!r}: scheduler={scheduler} is not an address like "
            f"tcp://HOST:8786 ({_first_line(error)})"
        ) from None


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: ``dask[workers=N]:INNER`` or ``dask[scheduler=ADDR]:INNER``."""
    workers, scheduler, tile, timeout = cluster_settings(options)
    _distributed()  # unavailable, with the reason, when distributed is not installed
    inner = inner if inner is not None else load_variant("naive")
    tracer = DaskTracer(tracer_of(NAME, inner), inner.name, workers, scheduler, tile, timeout)
    spelled: dict[str, object] = {"scheduler": scheduler} if scheduler else {"workers": workers}
    if tile != DEFAULT_TILE:
        spelled["tile"] = tile
    if timeout != DEFAULT_TIMEOUT:
        spelled["timeout"] = timeout
    where = f"the cluster at {scheduler}" if scheduler else f"{workers} local Dask workers"
    return tracer_variant(
        canonical_name(NAME, spelled, inner),
        f"render {tile}x{tile} tiles on {where}, tracing with {inner.name}",
        tracer,
        api={**inner.api},
        overrides=inner.overrides,
        base=inner.name,
        usage=USAGE,
        tolerance=inner.tolerance,
        differences=inner.differences,
    )
