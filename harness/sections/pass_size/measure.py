"""Pass size against time and memory (issue 16): ``rtc bench --sections pass-size``.

The ``wavefront`` variant traces its rays in passes whose arrays stay under ``max_mb`` MiB.
This section renders the run's scene (at the run's size and samples) through
``--pass-variant`` (default ``wavefront``) with each of ``MAX_MB``, one fresh process per
value (a warm-up render at ``WARM`` first), and records per value:

- the batch size it gives (rays per batch) and the number of passes of the image;
- the render time (``render_into`` of a prepared frame, up to ``repeat`` renders, median)
  and the CPU share of each render;
- the memory: the peak of the bytes ``tracemalloc`` sees during one more render (NumPy's
  arrays included; the canvas, made before, not), and the resident set's high-water mark
  during the timed renders less the resident set before them (canvas included).

Every picture is compared with the first value's: ``max_mb`` cuts the work differently,
never a bit of the picture. Then one big point (``BIG``: 4000x3000, 16 samples, at
``BIG_MAX_MB``), the issue's memory target, unless the sweep's rays per second predict it
to take longer than the run's budget: one render, its time, CPU share and the same two
memory figures (``tracemalloc`` on during it).

Everything lands in the run file's ``series`` (section ``pass-size``);
``harness.sections.pass_size.report`` draws the report's section and its plot (where is the knee?).
"""

from __future__ import annotations

import gc
import math
import sys
import time
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments.imagediff import canvas_array, image_error
from harness.instruments.usage import Timings, current_rss, peak_memory, reset_peak_rss
from harness.scenery.presets import SceneRef, build_scene
from raytracer.camera import RenderSettings
from variants.registry import VariantSpec, load_variant, parse_variant_name

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "pass-size"
DEFAULT_VARIANT = "wavefront"
MAX_MB = (16, 64, 256, 1024)
BIG = (Size(4000, 3000), 16)  # the memory target: size, samples per pixel
BIG_MAX_MB = 256
WARM = Size(16, 12)

Log = Callable[[str], None]


def with_max_mb(variant: str, max_mb: int) -> str:
    """``variant`` (the registry's grammar) with its ``max_mb`` option set to ``max_mb``."""
    spec = parse_variant_name(variant)
    options = (*((k, v) for k, v in spec.options if k != "max_mb"), ("max_mb", str(max_mb)))
    return str(VariantSpec(spec.name, options, spec.inner))


@dataclass(frozen=True)
class Plan:
    """What the section measures: ``variant`` (a registry name; ``max_mb`` is set per
    point) renders ``scene`` at ``size`` with ``samples``, ``depth``, ``seed`` and
    ``epsilon`` (None: the book's); ``threads``: CPUs per measuring process (None: all);
    ``repeat``: timed renders per point; ``budget``: seconds the big point may be predicted
    to take (None: no limit)."""

    variant: str
    scene: SceneRef
    size: Size
    samples: int = 1
    depth: int = 5
    seed: int = 0
    epsilon: float | None = None
    threads: int | None = None
    repeat: int = 3
    budget: float | None = None
    max_mb: tuple[int, ...] = MAX_MB
    big: tuple[Size, int] | None = BIG


def _run_job(folder: Path, job: dict[str, Any], threads: int | None) -> dict[str, Any]:
    result = run_in_child("harness.sections.pass_size.measure", folder, job, threads)
    if isinstance(result, int):
        return {"error": f"the measuring process exited with {result}"}
    return result


def _job(plan: Plan, name: str, size: Size, samples: int, repeat: int) -> dict[str, Any]:
    return {
        "variant": name,
        "scene": plan.scene.as_dict(),
        "size": [size.width, size.height],
        "samples": samples,
        "depth": plan.depth,
        "seed": plan.seed,
        "epsilon": plan.epsilon,
        "repeat": repeat,
    }


def predicted(points: list[dict[str, Any]], rays: int) -> float | None:
    """Seconds for ``rays`` camera rays at the best rate the sweep measured."""
    rates = [p["rays"] / p["render_median"] for p in points if p.get("render_median")]
    return rays / max(rates) if rates else None


def run(
    plan: Plan, jobs: Path, log: Log, save_image: Callable[[Any, str], str] | None = None
) -> list[dict[str, Any]]:
    """Measure ``plan``: one ``pass-size`` entry with a point per ``max_mb`` and the big
    point. jobs: a folder for the jobs' files; save_image(array, file name) -> the
    picture's path in the run (None: pictures are not kept)."""

    entry: dict[str, Any] = {"section": SECTION, "name": plan.variant, "points": []}
    entry.update(scene=plan.scene.name, size=[plan.size.width, plan.size.height])
    entry.update(samples=plan.samples)
    try:
        entry["name"] = load_variant(plan.variant).name
        names = [load_variant(with_max_mb(plan.variant, mb)).name for mb in plan.max_mb]
    except LookupError as error:
        entry.update(status="unavailable", error=str(error.args[0] if error.args else error))
        log(f"{SECTION}: {plan.variant} not run: {entry['error']}")
        return [entry]
    entry["status"] = "ok"
    first: tuple[str, Any] | None = None
    for index, (mb, name) in enumerate(zip(plan.max_mb, names, strict=True)):
        log(f"{SECTION}: {name} at {plan.size.width}x{plan.size.height}, {plan.samples} spp")
        folder = jobs / f"point-{index:02d}"
        result = _run_job(
            folder, _job(plan, name, plan.size, plan.samples, plan.repeat), plan.threads
        )
        point: dict[str, Any] = {"max_mb": mb, "variant": name, **result}
        image_file = point.pop("image", None)
        if image_file and "error" not in point:
            image = np.load(folder / image_file)
            if first is None:
                first = (name, image)
            else:
                point["difference"] = {
                    "against": first[0],
                    **image_error(image, first[1]).as_dict(),
                }
            if save_image is not None and index == 0:
                point["image"] = save_image(image, f"{SECTION}-{plan.scene.name}.png")
        entry["points"].append(point)
    if plan.big is not None:
        size, samples = plan.big
        name = load_variant(with_max_mb(plan.variant, BIG_MAX_MB)).name
        big: dict[str, Any] = {"max_mb": BIG_MAX_MB, "variant": name, "big": True}
        big.update(size=[size.width, size.height], samples=samples)
        guess = predicted(entry["points"], size.width * size.height * samples)
        if plan.budget is not None and (guess is None or guess > plan.budget):
            big["skipped"] = (
                "no point of the sweep measured a render"
                if guess is None
                else f"predicted to take {guess:.0f} s (at the sweep's best rays per second), "
                f"over the {plan.budget:g} s budget (rtc bench --budget 0: no limit)"
            )
            log(f"{SECTION}: the big point skipped: {big['skipped']}")
        else:
            log(f"{SECTION}: {name} at {size.width}x{size.height}, {samples} spp (memory)")
            job = _job(plan, name, size, samples, 1)
            job["big"] = True
            result = _run_job(jobs / "big", job, plan.threads)
            result.pop("image", None)
            big.update(result)
        entry["points"].append(big)
    return [entry]


# ---------------------------------------------------------------------------- the job


def render_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One ``max_mb``: load the scene, a warm-up render at ``WARM``, the timed renders (RSS
    high-water mark over them), one render under ``tracemalloc``; the big point: one render
    under ``tracemalloc``, RSS measured over it."""

    variant = load_variant(job["variant"])
    tracer = variant.tracer
    if tracer is None:
        return {"error": f"{variant.name} has no tracer"}
    size = Size(*job["size"])
    extra = {} if job.get("epsilon") is None else {"epsilon": job["epsilon"]}
    settings = RenderSettings(depth=job["depth"], samples=job["samples"], seed=job["seed"], **extra)
    ref = SceneRef.from_dict(job["scene"])
    started = time.perf_counter()
    camera, world = build_scene(ref, variant, WARM)
    tracer.render(camera, world, settings)
    result: dict[str, Any] = {"warm": time.perf_counter() - started}
    camera, world = build_scene(ref, variant, size)
    options = getattr(tracer, "options", None)
    cap = options.cap() if options is not None else None
    pixels = size.width * size.height
    result.update(rays=pixels * job["samples"], batch=cap)
    if cap is not None:
        result["passes"] = math.ceil(pixels / max(1, cap // job["samples"]))
    frame_started = time.perf_counter()
    tracer.prepared(camera, world, settings)
    result["prepare"] = time.perf_counter() - frame_started
    timings = Timings()
    image = None
    canvas = tracer.new_canvas(camera)
    gc.collect()
    before = current_rss()
    was_reset = reset_peak_rss()
    big = bool(job.get("big"))
    if big:
        tracemalloc.start()
    for _ in range(int(job["repeat"])):
        timings.time(tracer.render_into, canvas, camera, world, settings)
    peak = peak_memory(was_reset)
    result.update(timings.fields())
    result["rss_growth"] = max(peak.main - before, 0)
    result["rss_method"] = peak.method
    result["rss_before"] = before
    if not big:
        image = canvas_array(canvas, variant.api.get("pixel_at"))
        tracemalloc.start()
        tracer.render_into(canvas, camera, world, settings)
    result["tracemalloc_peak"] = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    result["canvas"] = int(getattr(getattr(canvas, "array", None), "nbytes", 0))
    if image is not None:
        np.save(folder / "image.npy", image)
        result["image"] = "image.npy"
    return result


def measure(bench: Bench) -> None:
    """The section in a bench run (``harness.engine.bench.Bench``): its plan from the run's
    settings (``--pass-variant``), its entries into the run's series."""
    s = bench.settings
    plan = Plan(
        variant=s.pass_variant, scene=s.scene, size=s.size, samples=s.samples,
        depth=s.depth, seed=s.seed, epsilon=s.epsilon, threads=s.threads,
        repeat=s.repeat, budget=s.budget,
    )  # fmt: skip
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, bench.save_image))


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.pass_size.measure JOB.json``: one point's job."""
    return job_main(render_job, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
