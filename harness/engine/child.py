"""One measurement job, run in a fresh Python process: ``python -m harness.engine.child JOB.json``.

Why a fresh process per job: every variant starts from the same state (no caches, compiled
code or pools left by another variant), ``NUMBA_NRT_STATS`` and ``NUMBA_NUM_THREADS`` are set
before numba is imported, the peak memory is this variant's own, and a crash or a hang costs
one row. The parent (``harness.engine.bench``) writes the job, runs this module and reads back
``result.json`` and the images (``.npy``, float RGB) from the job's folder.

A job names a variant, a scene and the settings, and a list of tasks:

- ``row``: the table's measurement. A first tiny render warms the variant up (its time, which
  includes any JIT compilation, is reported apart); probes of growing size estimate a
  render's time as a fixed cost plus a cost per pixel; the budget rule picks the size
  (``harness.engine.budget.fit_to_budget``) for the ``repeat`` timed renders (wall time, CPU time of
  the process tree, peak memory). Then, untimed, at the comparison size (the same for every
  row of a table, so the figures compare): one render counting allocations, whose picture is
  the one compared with naive's, and one counting rays (when the variant can be counted).
- ``series``: one timed render per point (size, samples), for sweeps and scaling plots; a
  point whose estimated time exceeds the budget is skipped and says so.
"""

from __future__ import annotations

import gc
import json
import sys
import time
import traceback
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from groundwork.progress import compile_ticker
from groundwork.sizes import Size
from harness.engine import figures, jobs
from harness.engine.budget import Estimate, fit_to_budget, scaled
from harness.engine.lifeline import watch_parent
from harness.instruments import alloccount, raycount, usage
from harness.instruments.imagediff import canvas_array
from harness.scenery.presets import SceneRef, build_scene
from raytracer.camera import WHITTED, RenderSettings
from variants.registry import load_variant

PROBE_SECONDS = 0.25  # a probe this long is a good enough estimate
WARM_PIXELS = 12  # the warm-up renders' size (the second is the first probe)
PROBE_PIXELS = 48  # the next probe's size


@dataclass
class Timing:
    """One timed render: wall and CPU seconds, peak memory, and the picture."""

    wall: float
    cpu: float
    peak: usage.PeakMemory
    image: np.ndarray


class Renderer:
    """A variant, a scene and the settings, ready to render at any size."""

    def __init__(self, job: Mapping[str, Any]) -> None:
        self.variant = load_variant(job["variant"])
        self.api = self.variant.api
        self.scene = SceneRef.from_dict(job["scene"])
        self.depth = int(job["depth"])
        self.seed = int(job["seed"])
        self.epsilon = job.get("epsilon")
        self.integrator = str(job.get("integrator", WHITTED))
        self.light_sampling = bool(job.get("light_sampling", True))
        self._settings = RenderSettings
        self._scenes: dict[Size, Any] = {}

    def settings(self, samples: int) -> Any:
        extra: dict[str, Any] = {"integrator": self.integrator}
        if self.epsilon is not None:
            extra["epsilon"] = float(self.epsilon)
        if not self.light_sampling:
            extra["light_sampling"] = False
        return self._settings(depth=self.depth, samples=samples, seed=self.seed, **extra)

    def scene_at(self, size: Size) -> Any:
        """(camera, world) at ``size``; the world is built once per size and reused."""
        if size not in self._scenes:
            self._scenes[size] = build_scene(self.scene, self.variant, size)
        return self._scenes[size]

    def render(self, size: Size, samples: int) -> Any:
        camera, world = self.scene_at(size)
        return self.api["render"](camera, world, self.settings(samples))

    def timed(self, size: Size, samples: int) -> Timing:
        self.scene_at(size)
        gc.collect()
        was_reset = usage.reset_peak_rss()
        clock = usage.TreeCpuClock()
        clock.start()
        t0 = time.perf_counter()
        canvas = self.render(size, samples)
        wall = time.perf_counter() - t0
        cpu = clock.stop()
        peak = usage.peak_memory(was_reset)
        return Timing(wall, cpu, peak, canvas_array(canvas, self.api.get("pixel_at")))


def _size(data: Any) -> Size:
    return Size(int(data[0]), int(data[1]))


def _save(folder: Path, name: str, image: np.ndarray) -> str:
    np.save(folder / name, image.astype(np.float64))
    return name


def _warm_up(renderer: Renderer, target: Size, log: Any) -> dict[str, Any]:
    """Two tiny renders: the first includes JIT compilation and first-use costs."""
    size = scaled(target, min(1.0, (WARM_PIXELS / target.pixels) ** 0.5))
    t0 = time.perf_counter()
    renderer.render(size, 1)
    first = time.perf_counter() - t0
    second = renderer.timed(size, 1).wall
    log(f"warm-up {size}: first render {first:.3f} s, second {second:.3f} s")
    return {"size": [size.width, size.height], "first": first, "second": second}


def _larger(target: Size, previous: Size | None, pixels: int) -> Size:
    """A size of ``target``'s aspect with about ``pixels`` pixels, larger than ``previous``
    (sizes come in steps), at most ``target``."""
    factor = (pixels / target.pixels) ** 0.5
    size = scaled(target, factor)
    while previous is not None and size.pixels <= previous.pixels and size != target:
        factor *= 1.25
        size = scaled(target, factor)
    return size


def probed_enough(probes: list[tuple[Size, float]], target: Size) -> bool:
    """Whether the probes so far, (size, seconds) smallest first, can estimate ``target``'s
    time: ``target`` itself was rendered, or there are two, the last took PROBE_SECONDS and
    at least twice the first (so the cost per pixel shows above a fixed start-up cost such as
    a process pool's, and noise in that cost does not decide the estimate)."""
    if not probes:
        return False
    if probes[-1][0] == target:
        return True
    last = probes[-1][1]
    return len(probes) >= 2 and last >= PROBE_SECONDS and last >= 2 * probes[0][1]


def _probe(
    renderer: Renderer, target: Size, samples: int, warm: Mapping[str, Any], log: Any,
    budget: float | None = None,
) -> tuple[dict[str, Any], Estimate]:  # fmt: skip
    """Renders of growing size (the aspect of ``target``) until ``probed_enough``, or until
    two probes have taken the row's ``budget`` (a render whose fixed cost, a pool's start-up
    on a busy machine, outlasts the budget would otherwise probe for minutes, only to be
    measured at the smallest size); the last two give the estimate."""
    probes: list[tuple[Size, float]] = []
    if samples == 1:
        probes.append((_size(warm["size"]), float(warm["second"])))
    pixels = PROBE_PIXELS

    def spent() -> bool:
        return budget is not None and len(probes) >= 2 and sum(t for _, t in probes) >= budget

    while not probed_enough(probes, target) and not spent():
        size = _larger(target, probes[-1][0] if probes else None, pixels)
        probes.append((size, renderer.timed(size, samples).wall))
        long_enough = probes[-1][1] >= max(PROBE_SECONDS, 2 * probes[0][1])
        pixels = size.pixels * (2 if long_enough else 4)
    estimate = Estimate.from_probes(probes)
    log(
        f"probes {', '.join(f'{s}: {t:.3f} s' for s, t in probes)}: estimate "
        f"{estimate.fixed:.3f} s + {estimate.per_pixel * 1e6:.1f} µs per pixel"
    )
    found = {
        "probes": [[s.width, s.height, t] for s, t in probes],
        "fixed": estimate.fixed,
        "per_pixel": estimate.per_pixel,
    }
    return found, estimate


def run_row(renderer: Renderer, task: Mapping[str, Any], folder: Path, log: Any) -> dict[str, Any]:
    """The table's measurement (see the module docstring)."""
    requested, samples, repeat = _size(task["size"]), int(task["samples"]), int(task["repeat"])
    budget = task.get("budget")
    warm = _warm_up(renderer, requested, log)
    probe, estimate = _probe(renderer, requested, samples, warm, log, budget)
    choice = fit_to_budget(requested, estimate, repeat, budget)
    size = choice.size
    if choice.reduced:
        log(choice.note)
    timings = []
    for i in range(repeat):
        timings.append(renderer.timed(size, samples))
        log(f"render {i + 1}/{repeat} at {size}: {timings[-1].wall:.3f} s")
    result: dict[str, Any] = {
        "kind": "row",
        "requested_size": [requested.width, requested.height],
        "size": [size.width, size.height],
        "samples": samples,
        "budget": budget,
        "budget_estimate": choice.estimate,
        "reduced": choice.reduced,
        "budget_note": choice.note,
        "warmup": warm,
        "probe": probe,
        "wall": [t.wall for t in timings],
        "cpu": [t.cpu for t in timings],
        "cores": usage.available_cores(),
        "cpu_source": usage.tree_cpu_source(),
        "peak_memory": {
            "main": max(t.peak.main for t in timings),
            "workers": max((t.peak.workers or 0) for t in timings) or None,
            "method": timings[0].peak.method,
        },
        "image": _save(folder, "image.npy", timings[0].image),
    }
    if task.get("compare_size"):
        result.update(_account(renderer, task, samples, folder, log))
    return result


def _account(
    renderer: Renderer, task: Mapping[str, Any], samples: int, folder: Path, log: Any
) -> dict[str, Any]:
    """Untimed renders at the comparison size (the same for every row of a table): one with
    allocation counting, whose picture is compared with naive's, and one counting rays."""
    size = _size(task["compare_size"])
    found: dict[str, Any] = {"compare_size": [size.width, size.height]}
    canvases: list[Any] = []
    if task.get("allocations", True):
        renderer.scene_at(size)
        gc.collect()
        counted = alloccount.count_allocations(
            lambda: canvases.append(renderer.render(size, samples))
        )
        found["allocations"] = counted.as_dict()
        log(f"allocations at {size} ({counted.method}): {counted.count} ({counted.bytes} bytes)")
    else:
        canvases.append(renderer.render(size, samples))
    image = canvas_array(canvases[0], renderer.api.get("pixel_at"))
    found["compare_image"] = _save(folder, "compare.npy", image)
    if task.get("rays", True) and raycount.counting_method(renderer.variant) is not None:
        camera, world = renderer.scene_at(size)
        found["rays"] = raycount.count_rays(
            renderer.variant, camera, world, renderer.settings(samples)
        )
        log(f"rays at {size}: {found['rays']['total']}")
    return found


def run_series(
    renderer: Renderer, task: Mapping[str, Any], folder: Path, log: Any
) -> dict[str, Any]:
    """One timed render per point, smallest work first; estimates grow from measured points."""
    points = [(_size(p["size"]), int(p["samples"])) for p in task["points"]]
    budget = task.get("budget")
    biggest = max(points, key=lambda p: p[0].pixels)[0]
    warm = _warm_up(renderer, biggest, log)
    probe, first = _probe(renderer, biggest, 1, warm, log)
    fixed, per_sample = first.fixed, first.per_pixel  # per_pixel of one sample
    done = []
    for size, samples in sorted(points, key=lambda p: p[0].pixels * p[1]):
        estimate = fixed + per_sample * size.pixels * samples
        entry: dict[str, Any] = {"size": [size.width, size.height], "samples": samples}
        if budget is not None and estimate > budget:
            entry["skipped"] = (
                f"estimated {figures.rough_seconds(estimate)}, over the {budget:g} s budget"
            )
            log(f"{size} x {samples} spp skipped: {entry['skipped']}")
            done.append(entry)
            continue
        timing = renderer.timed(size, samples)
        per_sample = max(per_sample, (timing.wall - fixed) / (size.pixels * samples))
        entry.update(
            wall=timing.wall,
            cpu=timing.cpu,
            image=_save(folder, f"image-{size}-{samples}spp.npy", timing.image)
            if task.get("images", True)
            else None,
        )
        log(f"{size} x {samples} spp: {timing.wall:.3f} s")
        done.append(entry)
    return {
        "kind": "series",
        "warmup": warm,
        "probe": probe,
        "points": done,
        "cores": usage.available_cores(),
    }


def _announce_compiles(log: Callable[[str], None]) -> None:
    """Log what numba compiles and for how long (the first render of an option set or a new
    kind of scene compiles for tens of seconds, which would otherwise pass in silence)."""
    if "variants.numba" not in sys.modules:
        return
    # deferred: saves ~120 ms (numba's loader) of a measuring process of another variant
    from variants.numba.specialize import on_compile

    def told(what: str, seconds: float | None) -> None:
        if seconds is None:
            log(f"compiling {what}: first time only, kept for later runs")
        else:
            log(f"compiled in {seconds:.1f} s")

    on_compile(compile_ticker(log))  # a line every few seconds while it compiles; first:
    on_compile(told)  # it has stopped when the end of a compile is told


def main(argv: list[str]) -> int:
    job_path = Path(argv[0])
    folder = job_path.parent
    job = json.loads(job_path.read_text())
    watch_parent()
    prefix = f"  [{job['variant']}]"

    def log(message: str) -> None:
        print(f"{prefix} {message}", file=sys.stderr, flush=True)

    try:
        if job.get("threads"):
            usage.pin_to_cores(int(job["threads"]))
        renderer = Renderer(job)
        _announce_compiles(log)
        outcome: dict[str, Any] = {
            "variant": renderer.variant.name,
            "summary": renderer.variant.summary,
            "allocation_method": alloccount.best_method(),
            "tasks": [],
        }
        for task in job["tasks"]:
            run = run_row if task["kind"] == "row" else run_series
            outcome["tasks"].append(run(renderer, task, folder, log))
        status = 0
    except Exception as error:  # reported as the row's error, the bench goes on
        outcome = {
            "variant": job["variant"],
            "error": f"{type(error).__name__}: {error}",
            "traceback": traceback.format_exc(),
        }
        if jobs.disk_error(error):  # the disk is full, not the variant wrong: the bench stops
            outcome["disk"] = f"{getattr(error, 'strerror', None) or error}"
        else:
            log(f"failed: {outcome['error']}")
        status = 1
    return jobs.write_result(folder, outcome) or status


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except KeyboardInterrupt:  # a SIGINT sent to this process: the parent reports it
        sys.exit(130)
