"""The ``dask`` variant: tiles traced on a Dask cluster (a ``LocalCluster`` of worker processes,
or a running scheduler's) are the inner variant's own pixels; progress counts rows; a worker
killed mid-render costs time, not the picture; an unreachable scheduler, a tile that raises and
a bad option are one clear line each."""

from __future__ import annotations

import dataclasses
import faulthandler
import os
import signal
import socket
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from book_world import default_scene
from holding import HANG_SECONDS

from raytracer.camera import RenderSettings
from rtc.cli import main
from variants import dask_cluster
from variants.dask_cluster import ClusterError, DaskTracer
from variants.registry import VariantError, load_variant

distributed = pytest.importorskip("distributed")  # a declared dependency: always there in CI

REFERENCE_SCENE = Path(__file__).resolve().parent.parent / "scenes" / "reference.yml"


def _same_pixels(a: Any, b: Any) -> bool:
    return (a.width, a.height) == (b.width, b.height) and all(
        (p.red, p.green, p.blue) == (q.red, q.green, q.blue)
        for p, q in zip(a.pixels, b.pixels, strict=True)
    )


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """A running cluster in this process (threads, not processes): enough for the tests that
    only need an address to connect to."""
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        yield cluster.scheduler_address


# ------------------------------------------------------------------------------ names


@pytest.mark.parametrize(
    ("name", "canonical"),
    [
        ("dask[workers=2]:numba[threads=1]", "dask[workers=2]:numba[threads=1]"),
        ("dask[tile=8,workers=1]", "dask[tile=8,workers=1]:naive"),
        (
            "dask[scheduler=tcp://10.0.0.5:8786]:cached",
            "dask[scheduler=tcp://10.0.0.5:8786]:cached",
        ),
    ],
)
def test_names_are_canonical(name: str, canonical: str) -> None:
    assert load_variant(name).name == canonical


@pytest.mark.parametrize(
    ("name", "words"),
    [
        ("dask[workers=2,scheduler=tcp://h:1]", "give one of them"),
        ("dask[scheduler=localhost]", "not an address like tcp://HOST:8786"),
        ("dask[scheduler=tcp://h:99999]", "port outside 1..65535"),
        ("dask[scheduler=tcp://h]", "missing port"),
        ("dask[workers=0]", "workers"),
        ("dask[tile=0]", "tile"),
        ("dask[colour=red]", "colour"),
    ],
)
def test_bad_options_are_one_clear_error(name: str, words: str) -> None:
    with pytest.raises(VariantError, match=words.replace("(", r"\(").replace(".", r"\.")) as info:
        load_variant(name)
    assert "\n" not in str(info.value)


# ------------------------------------------------------------------------------ renders


@pytest.mark.parametrize("inner", ["naive", "cached"])
def test_a_local_cluster_render_is_the_inner_variants_picture_and_counts_every_row(
    inner: str,
) -> None:
    variant = load_variant(f"dask[workers=2,tile=5]:{inner}")
    own = load_variant(inner)
    c, w = default_scene(own, 13, 11)
    rows: list[int] = []
    image = variant.api["render"](c, w, None, rows.append)
    assert sum(rows) == 11 and all(n > 0 for n in rows)
    assert _same_pixels(image, own.api["render"](c, w))


def test_numba_tiles_on_the_cluster_equal_numbas_own_render() -> None:
    from scene import load_scene

    variant = load_variant("dask[workers=2,tile=16]:numba[threads=1]")
    own = load_variant("numba[threads=1]")
    scene = load_scene(str(REFERENCE_SCENE), own.api).resized(40, 30)
    settings = RenderSettings(samples=2)
    image = variant.api["render"](scene.camera, scene.world, settings)
    expected = own.api["render"](scene.camera, scene.world, settings)
    assert _same_pixels(image, expected)


def test_a_session_keeps_one_cluster_and_each_worker_loads_the_inner_variant_once() -> None:
    variant = load_variant("dask[workers=2,tile=4]:cached")
    tracer = variant.tracer
    assert isinstance(tracer, DaskTracer)
    c, w = default_scene(variant, 12, 8)
    with tracer.session() as client:
        first = client.run(os.getpid)
        loaded_before = client.run(lambda: id(dask_cluster._TRACERS["cached"]))
        for _ in range(2):
            tracer.render(c, w)
        assert client.run(os.getpid) == first  # the same worker processes throughout
        assert client.run(lambda: id(dask_cluster._TRACERS["cached"])) == loaded_before


def test_a_running_scheduler_renders_the_same_picture(scheduler: str) -> None:
    variant = load_variant(f"dask[scheduler={scheduler},tile=6]:naive")
    own = load_variant("naive")
    c, w = default_scene(own, 12, 9)
    assert _same_pixels(variant.api["render"](c, w), own.api["render"](c, w))


# ------------------------------------------------------------------------------ faults


def test_killing_a_worker_mid_render_still_gives_the_same_picture() -> None:
    variant = load_variant("dask[workers=2,tile=2]:naive")
    own = load_variant("naive")
    tracer = variant.tracer
    assert isinstance(tracer, DaskTracer)
    c, w = default_scene(own, 16, 12)
    killed: list[int] = []
    with tracer.session() as client:
        pids = list(client.run(os.getpid).values())

        def kill_a_worker(rows: int) -> None:
            if not killed:  # after the first finished row: the other tiles are in flight
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])

        image = tracer.render(c, w, None, kill_a_worker)
        after = list(client.run(os.getpid).values())
    assert killed and killed[0] not in after  # it really died (its nanny started another)
    assert _same_pixels(image, own.api["render"](c, w))


@pytest.fixture
def closed_port() -> Iterator[int]:
    """A port of this machine on which nothing listens, for the test's whole length: bound
    by this test (so that nothing else, a cluster another test starts meanwhile included,
    can listen on it) and never listened on, so a connection is refused at once."""
    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        yield held.getsockname()[1]


@pytest.fixture
def no_client(monkeypatch: pytest.MonkeyPatch) -> None:
    """A ``distributed.Client`` may not be made: the one that fails to start lingers for 20 s
    in its ``__del__`` (and retries a refused port until its timeout), which is what the
    probe before it (``dask_cluster.probe``) keeps a failed connection from."""

    def refuse(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("a distributed.Client was made for a scheduler the probe failed")

    monkeypatch.setattr(distributed, "Client", refuse)


def test_an_unreachable_scheduler_is_one_line_within_seconds(
    closed_port: int, no_client: None
) -> None:
    """Within seconds, whatever the machine's speed: refused at once by the probe's plain
    socket, no Client made (``no_client``), no timeout waited for (the message is the
    refusal's, not a timeout's)."""
    variant = load_variant(f"dask[scheduler=tcp://127.0.0.1:{closed_port},timeout=3]:naive")
    c, w = default_scene(variant, 4, 3)
    with pytest.raises(
        ClusterError, match=r"cannot reach the scheduler at tcp://127\.0\.0\.1"
    ) as info:
        variant.api["render"](c, w)
    assert "Connection refused" in str(info.value), info.value
    assert "\n" not in str(info.value)


def test_something_else_listening_is_not_taken_for_a_scheduler(no_client: None) -> None:
    """The other end answers nonsense and then keeps the connection open, silent, until the
    test ends: the probe gives up on its own (its ``timeout``, or the nonsense), not because
    the other end hung up; no Client is made (``no_client``)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    port = server.getsockname()[1]
    done = threading.Event()

    def answer_nonsense() -> None:
        connection, _ = server.accept()
        with connection:
            connection.sendall(b"HTTP/1.0 200 OK\r\n\r\n" + b"\xff" * 64)
            done.wait()

    threading.Thread(target=answer_nonsense, daemon=True).start()
    variant = load_variant(f"dask[scheduler=tcp://127.0.0.1:{port},timeout=2]:naive")
    c, w = default_scene(variant, 4, 3)
    try:
        with pytest.raises(ClusterError, match="cannot reach the scheduler") as info:
            variant.api["render"](c, w)
    finally:
        done.set()
        server.close()
    assert "\n" not in str(info.value)


class _Broken:
    def render_region(self, *args: Any) -> list[float]:
        raise ZeroDivisionError("a bug in the inner tracer")


def test_a_tile_that_raises_fails_the_render_naming_the_tile(
    scheduler: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the in-process cluster's worker shares this module's table of loaded tracers
    monkeypatch.setitem(dask_cluster._TRACERS, "cached", _Broken())  # type: ignore[arg-type]
    variant = load_variant(f"dask[scheduler={scheduler},tile=4]:cached")
    c, w = default_scene(variant, 8, 4)
    with pytest.raises(
        ClusterError,
        match=r"tile x \d+\.\.\d+, y 0\.\.3 failed on a worker: "
        "ZeroDivisionError: a bug in the inner tracer",
    ) as info:
        variant.api["render"](c, w)
    assert "\n" not in str(info.value)


def test_rtc_render_with_no_scheduler_is_one_line_exit_2_and_no_image(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], closed_port: int
) -> None:
    output = tmp_path / "out.png"
    code = main(
        [
            "render",
            str(REFERENCE_SCENE),
            "--variant",
            f"dask[scheduler=tcp://127.0.0.1:{closed_port}]:naive",
            "--size",
            "8x6",
            "-o",
            str(output),
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and not output.exists()
    assert err.count("\n") == 1 and "cannot reach the scheduler" in err


class _Exits:
    def render_region(self, *args: Any) -> list[float]:
        os._exit(3)  # a crash that takes the worker process with it


def _install_a_crashing_tracer() -> None:
    dask_cluster._TRACERS["cached"] = _Exits()  # type: ignore[assignment]


def test_a_tile_that_keeps_killing_its_workers_is_one_line() -> None:
    import dask

    variant = load_variant("dask[workers=1,tile=4]:cached")
    tracer = variant.tracer
    assert isinstance(tracer, DaskTracer)
    c, w = default_scene(variant, 4, 4)
    # the scheduler runs in this process: after one death the tile is given up
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), tracer.session() as client:
        client.run(_install_a_crashing_tracer)
        with pytest.raises(ClusterError, match="killed the workers that ran it") as info:
            tracer.render(c, w)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("name", ["pooled[workers=2]:cached", "dask[workers=2,tile=2]:cached"])
def test_a_deeply_nested_world_renders_in_the_workers_as_here(name: str) -> None:
    # the loader raises the recursion limit for a scene nested this deep (RTC_SCENE_MAX_DEPTH);
    # the workers take the parent's limit, so they trace (and pass on) what it loaded
    own = load_variant("cached")
    api = own.api
    c, _ = default_scene(own, 4, 3)
    shape = api["sphere"]()
    for _ in range(400):
        group = api["group"]()
        api["add_child"](group, shape)
        shape = group
    w = dataclasses.replace(api["default_world"](), objects=[shape])
    before = sys.getrecursionlimit()
    sys.setrecursionlimit(12 * 400 + 400)
    # a worker that cannot pickle the world for another one leaves Dask waiting for ever:
    # if that comes back, end the run with the stacks instead of hanging CI
    faulthandler.dump_traceback_later(120, exit=True)
    try:
        image = load_variant(name).api["render"](c, w)
        expected = own.api["render"](c, w)
    finally:
        faulthandler.cancel_dump_traceback_later()
        sys.setrecursionlimit(before)
    assert _same_pixels(image, expected)


def test_a_world_that_does_not_pickle_is_one_line() -> None:
    variant = load_variant("dask[workers=1]:cached")
    c, w = default_scene(variant, 4, 3)
    w = dataclasses.replace(w, objects=[*w.objects, lambda: None])
    with pytest.raises(ClusterError, match="must pickle to go to the workers") as info:
        variant.api["render"](c, w)
    assert "\n" not in str(info.value)


def test_a_worker_that_cannot_load_the_inner_variant_is_one_line(
    scheduler: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    def missing(name: str) -> Any:
        raise ImportError("No module named 'numba'")

    # the in-process cluster's worker loads variants through this module's names
    monkeypatch.setattr(dask_cluster, "load_variant", missing)
    monkeypatch.delitem(dask_cluster._TRACERS, "cached", raising=False)
    tracer = DaskTracer(load_variant("cached").tracer, "cached", 1, scheduler=scheduler)
    c, w = default_scene(load_variant("cached"), 4, 3)
    with pytest.raises(ClusterError, match="a worker cannot load 'cached': ImportError") as info:
        tracer.render(c, w)
    assert "\n" not in str(info.value)


def _start_compiling_on_a_worker() -> None:
    from variants.numba import specialize

    dask_cluster.forward_compiles()
    specialize.announce("numba's kernels for a test")


def test_a_compile_a_worker_starts_is_announced_here_naming_the_worker() -> None:
    # the first render of a new kind of scene compiles numba's kernels in every worker for
    # seconds: rtc render's compile listener hears it, as it hears its own compiles
    from variants.numba import specialize

    heard: list[tuple[str, float | None]] = []
    remove = specialize.on_compile(lambda what, seconds: heard.append((what, seconds)))
    try:
        with (
            distributed.LocalCluster(
                n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0"
            ) as cluster,
            distributed.Client(cluster) as client,
            dask_cluster.compiles_announced(client),
        ):
            client.submit(_start_compiling_on_a_worker, pure=False).result()
            address = next(iter(client.scheduler_info()["workers"]))
            deadline = time.monotonic() + HANG_SECONDS  # a hang guard: it comes in moments
            while not heard and time.monotonic() < deadline:
                time.sleep(0.05)
    finally:
        remove()
    assert heard == [(f"numba's kernels for a test on worker {address}", None)]
