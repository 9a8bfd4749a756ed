"""The ``pooled`` variant: jobs cover the image, workers trace them with the inner tracer's
``render_region`` (one frame prepared per worker), progress counts rows, and a worker that dies
or fails makes the render fail quickly and clearly, returning (and writing) nothing."""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import signal
from pathlib import Path
from typing import Any

import pytest
from book_world import default_scene

from raytracer.camera import Camera, RenderSettings
from raytracer.tracer import TRACER, Tracer
from raytracer.world import World
from rtc.cli import main
from variants.jobs import make_jobs
from variants.pooled import PooledTracer, RenderWorkerError, _serve
from variants.pooled import variant as pooled_variant
from variants.registry import Variant, VariantError, load_variant

REFERENCE_SCENE = Path(__file__).resolve().parent.parent / "scenes" / "reference.yml"


@pytest.mark.parametrize(
    ("granularity", "tile", "count"), [("line", 5, 11), ("pixel", 5, 143), ("tile", 5, 9)]
)
def test_the_jobs_cover_every_pixel_once(granularity: str, tile: int, count: int) -> None:
    jobs = make_jobs(13, 11, granularity, tile)
    covered = [(x, y) for x0, y0, x1, y1 in jobs for y in range(y0, y1) for x in range(x0, x1)]
    assert len(jobs) == count
    assert sorted(covered) == sorted((x, y) for y in range(11) for x in range(13))


@pytest.mark.parametrize(
    "name",
    ["pooled[workers=2]:cached", "pooled[workers=2,granularity=tile,tile=5]:cached"],
)
def test_progress_counts_every_row_once_and_no_worker_is_left(name: str) -> None:
    variant = load_variant(name)
    c, w = default_scene(variant, 13, 11)
    rows: list[int] = []
    image = variant.api["render"](c, w, None, rows.append)
    assert sum(rows) == 11 and all(n > 0 for n in rows)
    assert (image.width, image.height) == (13, 11)
    assert multiprocessing.active_children() == []


def test_killing_a_worker_mid_render_fails_within_seconds_and_returns_nothing() -> None:
    """Within seconds: the death is seen as it happens (the worker's process sentinel), not
    when the worker has been silent for the pool's ``timeout`` (10 s), the only other way
    the render could end with a job lost; which of the two ended it, the message says."""
    variant = load_variant("pooled[workers=2]:cached")
    c, w = default_scene(variant, 40, 30)
    killed: list[int] = []

    def kill_a_worker(rows: int) -> None:
        if not killed:  # after the first row of 30: both workers hold jobs (IN_FLIGHT)
            worker = multiprocessing.active_children()[0]
            os.kill(worker.pid, signal.SIGKILL)  # type: ignore[arg-type]
            killed.append(worker.pid or 0)

    result: list[Any] = []
    with pytest.raises(RenderWorkerError) as error:
        result.append(variant.api["render"](c, w, None, kill_a_worker))
    message = str(error.value)
    assert not result
    assert "sent no heartbeat" not in message  # not the timeout's: the death itself
    assert f"(pid {killed[0]}) died with exit code -9 (killed by SIGKILL)" in message
    assert "no image is returned" in message and "jobs were done" in message
    assert "while holding job" in message or "while waiting for work" in message
    assert multiprocessing.active_children() == []


def test_an_exception_in_a_worker_names_the_job_and_carries_its_traceback() -> None:
    variant = load_variant("pooled[workers=2]:cached")
    c, w = default_scene(variant, 8, 8)
    w.objects[0].transform = variant.api["scaling"](1, 0, 1)  # fails on first use, in a worker
    with pytest.raises(RenderWorkerError) as error:
        variant.api["render"](c, w)
    message = str(error.value)
    assert "failed on job" in message and "(line " in message
    assert "transform is not invertible" in message
    assert multiprocessing.active_children() == []


def test_a_worker_that_cannot_load_its_inner_variant_says_so() -> None:
    tracer = PooledTracer(TRACER, "no-such-variant", workers=1)
    c, w = default_scene(load_variant("naive"), 4, 4)
    with pytest.raises(RenderWorkerError, match=r"worker 0 \(pid \d+\) could not start") as error:
        tracer.render(c, w)
    assert "unknown variant 'no-such-variant'" in str(error.value)


def test_a_world_that_does_not_pickle_is_a_clear_error() -> None:
    variant = load_variant("pooled[workers=1]")
    c, w = default_scene(variant, 4, 4)
    w.objects[0].material = dataclasses.replace(w.objects[0].material, pattern=lambda p: p)
    with pytest.raises(
        RenderWorkerError,
        match=r"cannot start worker 0: the camera, world and settings must pickle",
    ):
        variant.api["render"](c, w)
    assert multiprocessing.active_children() == []


def test_rtc_render_writes_no_file_when_a_worker_dies(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rtc import cmd_render

    class KillAWorker:
        """``rtc render``'s progress, which kills a worker at the first row done."""

        def __call__(self, rows: int) -> None:
            children = multiprocessing.active_children()
            if children:
                os.kill(children[0].pid, signal.SIGKILL)  # type: ignore[arg-type]

        def write(self, text: str) -> None:
            pass

        def exclude(self, seconds: float) -> None:
            pass

        def close(self) -> None:
            pass

    monkeypatch.setattr(cmd_render, "_progress", lambda args, rows, name, settings: KillAWorker())
    output = tmp_path / "out.png"
    arguments = ["render", str(REFERENCE_SCENE), "-o", str(output), "--size", "32x24"]
    try:
        code = main([*arguments, "--variant", "pooled[workers=2]:cached"])
    except RenderWorkerError:
        code = None
    assert code != 0
    assert not output.exists() and list(tmp_path.iterdir()) == []


def test_pooling_works_after_numba_threads_ran_in_the_same_process() -> None:
    """A fork-based pool hangs once numba's OpenMP threads have run in the parent (GNU
    OpenMP cannot be forked); the pool spawns its workers. (This guards the ordinary case; a
    worker that itself runs numba code is covered by the numba variant's own tests.)"""
    numba = pytest.importorskip("numba")
    import numpy as np

    @numba.njit(parallel=True)
    def total(values: Any) -> float:
        result = 0.0
        for i in numba.prange(values.shape[0]):
            result += values[i]
        return result

    assert total(np.ones(1000)) == 1000.0
    variant = load_variant("pooled[workers=2]:cached")
    c, w = default_scene(variant, 6, 6)
    image = variant.api["render"](c, w, RenderSettings(depth=2))
    assert (image.width, image.height) == (6, 6)


@pytest.mark.parametrize("inner", ["cached", "prealloc"])
def test_a_pooled_render_is_its_inner_variants_picture(inner: str) -> None:
    """Workers trace with the inner tracer's ``render_region``: the pixels are its own (and
    naive's, bit for bit, for these two)."""
    pooled = load_variant(f"pooled[workers=2,granularity=tile,tile=3]:{inner}")
    plain = load_variant(inner)
    c, w = default_scene(plain, 9, 7)
    settings = RenderSettings(depth=3, samples=2, seed=5)
    expected = plain.api["render"](c, w, settings)
    assert pooled.api["render"](c, w, settings).pixels == expected.pixels
    naive_c, naive_w = default_scene(load_variant("naive"), 9, 7)
    assert load_variant("naive").api["render"](naive_c, naive_w, settings).pixels == expected.pixels


class CountingTracer(Tracer):
    """The reference's tracer, counting the frames it prepares."""

    __slots__ = ("prepared_frames",)

    def __init__(self) -> None:
        super().__init__()
        self.prepared_frames = 0

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Any:
        self.prepared_frames += 1
        return super().prepare(c, w, settings)


def test_a_worker_prepares_its_frame_once_and_calls_render_region_per_job() -> None:
    c, w = default_scene(load_variant("naive"), 5, 4)
    settings = RenderSettings()
    jobs = make_jobs(5, 4, "tile", 2)
    parent_end, worker_end = multiprocessing.Pipe()
    for index, job in enumerate(jobs):
        parent_end.send((index, job))
    parent_end.send(None)
    tracer, reference = CountingTracer(), Tracer()
    try:
        _serve(worker_end, tracer, c, w, settings)
        assert tracer.prepared_frames == 1
        for index, job in enumerate(jobs):
            assert parent_end.recv() == (
                "done",
                index,
                reference.render_region(c, w, settings, job),
            )
        assert not parent_end.poll()
    finally:
        parent_end.close()
        worker_end.close()


def test_a_variant_without_a_tracer_cannot_be_pooled() -> None:
    """A learner's own variant answers through its api alone: no ``render_region`` for the
    workers to call."""
    learners = Variant("learners", "a learner's own", dict(load_variant("naive").api))
    with pytest.raises(VariantError, match=r"'pooled' cannot wrap 'learners': it has no tracer"):
        pooled_variant(learners, workers="1")
