"""What a cluster buys and costs (issue 17): ``rtc bench --sections cluster``.

Renders the run's scene through ``CONFIGS`` (numba on 1 and 2 threads, and 1 and 2 local
Dask workers each tracing with one-thread numba), one fresh process per configuration, and
records per configuration:

- start-up: everything before the timed renders (loading the variant; for ``dask``, starting
  the ``LocalCluster`` and loading numba in every worker, in ``DaskTracer.session``), and a
  first render at ``WARM`` (numba's kernels compiled or loaded from their cache);
- the render time of ``repeat`` renders in that session (median), the CPU share each got
  (this process and its descendants: the cluster's workers too), the rays per second;
- the tiles a dask render hands out.

The number of samples per pixel is chosen by the first configuration (one thread, no
cluster): enough for its render to take about ``TARGET_SECONDS`` at the run's size (at
least 5 s: long enough to amortize a cluster's overheads), never fewer than the run's own.
Every picture is compared with the first configuration's: a cluster changes where tiles
are traced, never a pixel.

The entry lands in the run file's ``series`` (section ``cluster``);
``harness.sections.cluster.report`` draws the report's section: throughput of 2 workers against 1
(the issue's target: at least 1.7x), the start-up, and the cost per tile.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments.imagediff import canvas_array, image_error
from harness.instruments.usage import Timings
from harness.scenery.presets import SceneRef, build_scene
from raytracer.camera import RenderSettings
from variants.dask_cluster import DaskTracer
from variants.jobs import make_jobs
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "cluster"
CONFIGS = (
    "numba[threads=1]",
    "numba[threads=2]",
    "dask[workers=1]:numba[threads=1]",
    "dask[workers=2]:numba[threads=1]",
)
TARGET_SECONDS = 6.0  # the first configuration's render takes about this long (>= 5 s)
CALIBRATION_SAMPLES = 2  # samples per pixel of the render that times one sample
MAX_SAMPLES = 4096
WARM = Size(16, 12)

Log = Callable[[str], None]


@dataclass(frozen=True)
class Plan:
    """What the section measures: each of ``configs`` renders ``scene`` at ``size`` with
    ``samples`` (at least; see the module), ``depth``, ``seed`` and ``epsilon`` (None: the
    book's); ``repeat``: timed renders per configuration; ``target``: seconds the first
    configuration's render should take."""

    scene: SceneRef
    size: Size
    samples: int = 1
    depth: int = 5
    seed: int = 0
    epsilon: float | None = None
    repeat: int = 3
    target: float = TARGET_SECONDS
    configs: tuple[str, ...] = CONFIGS


def _job(plan: Plan, name: str, samples: int, calibrate: bool) -> dict[str, Any]:
    return {
        "variant": name,
        "scene": plan.scene.as_dict(),
        "size": [plan.size.width, plan.size.height],
        "samples": samples,
        "depth": plan.depth,
        "seed": plan.seed,
        "epsilon": plan.epsilon,
        "repeat": plan.repeat,
        "calibrate": plan.target if calibrate else None,
    }


def run(
    plan: Plan, jobs: Path, log: Log, save_image: Callable[[Any, str], str] | None = None
) -> list[dict[str, Any]]:
    """Measure ``plan``: one ``cluster`` entry with a point per configuration. jobs: a
    folder for the jobs' files; save_image(array, file name) -> the picture's path in the
    run (None: pictures are not kept)."""

    entry: dict[str, Any] = {"section": SECTION, "name": SECTION, "points": []}
    entry.update(scene=plan.scene.name, size=[plan.size.width, plan.size.height])
    try:
        names = [load_variant(name).name for name in plan.configs]
    except LookupError as error:
        entry.update(status="unavailable", error=str(error.args[0] if error.args else error))
        log(f"{SECTION}: not run: {entry['error']}")
        return [entry]
    entry["status"] = "ok"
    samples = plan.samples
    first: tuple[str, Any] | None = None
    for index, name in enumerate(names):
        calibrate = index == 0
        log(
            f"{SECTION}: {name} at {plan.size.width}x{plan.size.height}"
            + (" (choosing the samples per pixel)" if calibrate else f", {samples} spp")
        )
        folder = jobs / f"point-{index:02d}"
        job = _job(plan, name, samples, calibrate)
        result = run_in_child("harness.sections.cluster.measure", folder, job, threads=None)
        if isinstance(result, int):
            result = {"error": f"the measuring process exited with {result}"}
        point: dict[str, Any] = {"variant": name, **result}
        if calibrate and "error" not in point:
            samples = int(point["samples"])
        image_file = point.pop("image", None)
        if image_file and "error" not in point:
            image = np.load(folder / image_file)
            if first is None:
                first = (name, image)
                if save_image is not None:
                    point["image"] = save_image(image, f"{SECTION}-{plan.scene.name}.png")
            else:
                point["difference"] = {
                    "against": first[0],
                    **image_error(image, first[1]).as_dict(),
                }
        entry["points"].append(point)
    entry["samples"] = samples
    return [entry]


# ---------------------------------------------------------------------------- the job


def _chosen_samples(seconds_per_sample: float, target: float, least: int) -> int:
    """Samples per pixel for a render of at least ``target`` seconds."""
    wanted = math.ceil(target / max(seconds_per_sample, 1e-6))
    return max(least, min(MAX_SAMPLES, wanted))


def render_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One configuration: load it (a dask variant opens its cluster session), a warm-up
    render at ``WARM``, the samples chosen when asked (``calibrate``), then the timed
    renders; the picture of the last one."""
    def settings_with(samples: int) -> RenderSettings:
        extra = {} if job.get("epsilon") is None else {"epsilon": job["epsilon"]}
        return RenderSettings(depth=job["depth"], samples=samples, seed=job["seed"], **extra)

    started = time.perf_counter()
    variant = load_variant(job["variant"])
    tracer = variant.tracer
    if tracer is None:
        return {"error": f"{variant.name} has no tracer"}
    ref = SceneRef.from_dict(job["scene"])
    size = Size(*job["size"])
    result: dict[str, Any] = {}
    with ExitStack() as stack:
        if isinstance(tracer, DaskTracer):
            stack.enter_context(tracer.session())
            result["session"] = time.perf_counter() - started
            result["tiles"] = len(make_jobs(size.width, size.height, "tile", tracer.tile))
            result["tile"] = tracer.tile
        camera, world = build_scene(ref, variant, WARM)
        tracer.render(camera, world, settings_with(1))
        result["startup"] = time.perf_counter() - started
        camera, world = build_scene(ref, variant, size)
        samples = int(job["samples"])
        if job.get("calibrate"):
            once = time.perf_counter()
            tracer.render(camera, world, settings_with(CALIBRATION_SAMPLES))
            result["seconds_per_sample"] = (time.perf_counter() - once) / CALIBRATION_SAMPLES
            samples = _chosen_samples(result["seconds_per_sample"], job["calibrate"], samples)
        settings = settings_with(samples)
        timings = Timings()
        canvas = tracer.new_canvas(camera)
        for _ in range(int(job["repeat"])):
            timings.time(tracer.render_into, canvas, camera, world, settings)
    result.update(samples=samples, rays=size.width * size.height * samples)
    result.update(timings.fields())
    median = result["render_median"]
    result["rays_per_second"] = result["rays"] / median if median > 0 else None
    np.save(folder / "image.npy", canvas_array(canvas, variant.api.get("pixel_at")))
    result["image"] = "image.npy"
    return result


def measure(bench: Bench) -> None:
    """The section in a bench run (``harness.engine.bench.Bench``): its plan from the run's
    settings, its entry into the run's series."""
    s = bench.settings
    plan = Plan(
        scene=s.scene, size=s.size, samples=s.samples, depth=s.depth, seed=s.seed,
        epsilon=s.epsilon, repeat=s.repeat,
    )  # fmt: skip
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, bench.save_image))


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.cluster.measure JOB.json``: one configuration's job."""
    return job_main(render_job, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
