"""Light samples against pixel samples (issue 15, the bonus chapter "Rendering soft
shadows"): ``rtc bench --sections light-samples``.

A soft shadow costs one shadow ray per cell of an area light, per shading point. The same
quality can be bought with more cells (``usteps`` x ``vsteps``), with random jitter inside
the cells, or with more samples per pixel (each sample draws new jitter: see
``raytracer.sampling.light_jitter``). This section prices them side by side on one scene
(``SCENE``, its area lights rewritten): every configuration of ``CELLS`` (1, 4, 16, 64
cells, square grids) x jitter (off, on) is rendered at each of ``SAMPLES`` samples per
pixel, one fresh process per configuration (a warm-up render at ``WARM`` first, so numba's
compilation stays out), and compared with a ground truth: ``TRUTH_CELLS`` jittered cells at
``TRUTH_SAMPLES`` samples per pixel. The time-error Pareto front (nothing both faster and
closer to the truth) says which knob buys more quality per second.

``repeat`` timed renders per point (the median is the point's time, the first render its
picture: the picture does not change between renders); a point whose time the previous
point predicts (linear in the samples) to exceed the budget is skipped and says so.
Everything lands in the run file's ``series`` (section ``light-samples``: the ground truth as
part ``truth``, then an entry per configuration); ``harness.sections.light_samples.report`` draws
the report's section. Beside them, the bonus chapters' other scene (``PICTURES``: the
texture maps) is rendered once at the same size and settings (part ``picture``), so the
report shows it.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments.imagediff import canvas_array, image_error
from harness.instruments.usage import Timings
from harness.scenery import SCENES
from raytracer.camera import RenderSettings
from scene import load_scene_text
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "light-samples"
TRUTH_PART = "truth"
SCENE = SCENES / "soft-shadows.yml"
PICTURES = (SCENES / "textures.yml",)
PICTURE_PART = "picture"
DEFAULT_VARIANT = "numba"
CELLS = (1, 4, 16, 64)  # cells per area light: square grids, 1x1 to 8x8
SAMPLES = (1, 4, 16, 64)  # samples per pixel
TRUTH_CELLS = 64
TRUTH_SAMPLES = 1024
WARM = Size(8, 6)

Log = Callable[[str], None]


@dataclass(frozen=True)
class Config:
    """One way of sampling the area lights: ``cells`` per light (a square grid) and
    whether the cells are jittered."""

    cells: int
    jitter: bool

    @property
    def steps(self) -> int:
        steps = math.isqrt(self.cells)
        if steps * steps != self.cells or steps < 1:
            raise ValueError(f"{self.cells} cells is not a square grid")
        return steps

    @property
    def label(self) -> str:
        return f"{self.steps}x{self.steps} {'jittered' if self.jitter else 'centred'}"


CONFIGS = tuple(Config(cells, jitter) for jitter in (False, True) for cells in CELLS)


def configured(text: str, config: Config, path: Path) -> str:
    """The scene ``text`` with every area light sampled as ``config`` says (its edges, corner
    and intensity kept); ``ValueError`` naming ``path`` when the scene has no area light."""
    items = yaml.safe_load(text)
    lights = [i for i in items or [] if isinstance(i, dict) and i.get("add") == "area_light"]
    if not lights:
        raise ValueError(f"{path}: the scene has no '- add: area_light' to sample")
    for light in lights:
        light["usteps"] = light["vsteps"] = config.steps
        light["jitter"] = config.jitter
    return yaml.safe_dump(items, sort_keys=False)


@dataclass(frozen=True)
class Plan:
    """What the section measures: ``variant`` (a registry name) renders ``scene`` at
    ``size`` with the render's ``depth`` and ``seed``, ``repeat`` timed renders per point;
    ``threads``: CPUs per measuring process (None: all); ``budget``: seconds one render may
    be predicted to take."""

    variant: str
    size: Size
    scene: Path = SCENE
    depth: int = 5
    seed: int = 0
    repeat: int = 3
    threads: int | None = None
    budget: float | None = None
    configs: tuple[Config, ...] = CONFIGS
    samples: tuple[int, ...] = SAMPLES
    truth: Config = Config(TRUTH_CELLS, True)
    truth_samples: int = TRUTH_SAMPLES
    pictures: tuple[Path, ...] = PICTURES


# ---------------------------------------------------------------------------- the parent


def _job(
    plan: Plan, config: Config | None, samples: list[int], budget: float | None, scene: Path
) -> dict[str, Any]:
    return {
        "variant": plan.variant,
        "scene": str(scene),
        "cells": None if config is None else config.cells,
        "jitter": None if config is None else config.jitter,
        "size": [plan.size.width, plan.size.height],
        "samples": samples,
        "depth": plan.depth,
        "seed": plan.seed,
        "repeat": plan.repeat,
        "budget": budget,
    }


def _run_job(folder: Path, job: dict[str, Any], threads: int | None) -> dict[str, Any]:
    result = run_in_child("harness.sections.light_samples.measure", folder, job, threads)
    if isinstance(result, int):
        return {"error": f"the measuring process exited with {result}"}
    return result


def run(
    plan: Plan, jobs: Path, log: Log, save_image: Callable[[Any, str], str] | None = None
) -> list[dict[str, Any]]:
    """Measure ``plan``: the ground truth, then one entry per configuration.

    jobs: a folder for the jobs' files; save_image(array, file name) -> the picture's path
    in the run (None: pictures are not kept)."""

    base = {"scene": plan.scene.stem, "variant": plan.variant}
    try:
        base["variant"] = load_variant(plan.variant).name
    except LookupError as error:
        reason = str(error.args[0] if error.args else error)
        log(f"{SECTION}: {plan.variant} not run: {reason}")
        return [{"section": SECTION, "part": TRUTH_PART, "name": plan.variant, **base,
                 "status": "unavailable", "error": reason, "points": []}]  # fmt: skip
    log(f"{SECTION}: ground truth, {plan.truth.label} at {plan.truth_samples} spp")
    folder = jobs / "truth"
    job = _job(plan, plan.truth, [plan.truth_samples], None, plan.scene)
    result = _run_job(folder, job, plan.threads)
    truth: dict[str, Any] = {"section": SECTION, "part": TRUTH_PART, "name": plan.truth.label}
    truth.update(base)
    truth.update(cells=plan.truth.cells, jitter=plan.truth.jitter)
    if "error" in result or not result.get("points"):
        truth.update(status="failed", error=result.get("error", "no picture"), points=[])
        log(f"{SECTION}: the ground truth failed: {truth['error']}")
        return [truth]
    point = result["points"][0]
    reference = np.load(folder / point.pop("image"))
    if save_image is not None:
        point["image"] = save_image(reference, "light-truth.png")
    truth.update(status="ok", warm=result.get("warm"), points=[point])
    entries = [truth]
    for index, config in enumerate(plan.configs):
        log(f"{SECTION}: {config.label}, {', '.join(map(str, plan.samples))} spp")
        folder = jobs / f"config-{index:02d}"
        job = _job(plan, config, list(plan.samples), plan.budget, plan.scene)
        result = _run_job(folder, job, plan.threads)
        entry: dict[str, Any] = {"section": SECTION, "name": config.label, **base}
        entry.update(cells=config.cells, jitter=config.jitter)
        if "error" in result:
            entry.update(status="failed", error=result["error"], points=[])
            entries.append(entry)
            continue
        entry.update(status="ok", warm=result.get("warm"), points=result["points"])
        for p in entry["points"]:
            image_file = p.pop("image", None)
            if image_file is None:
                continue
            image = np.load(folder / image_file)
            p["error"] = image_error(image, reference).as_dict()
            if save_image is not None and p["samples"] == plan.samples[0]:
                slug = f"{config.steps}x{config.steps}-{'jittered' if config.jitter else 'centred'}"
                p["image"] = save_image(image, f"light-{slug}-{p['samples']}spp.png")
        entries.append(entry)
    for index, scene in enumerate(plan.pictures):
        log(f"{SECTION}: the picture of {scene.name}")
        folder = jobs / f"picture-{index:02d}"
        result = _run_job(folder, _job(plan, None, [1], None, scene), plan.threads)
        entry = {"section": SECTION, "part": PICTURE_PART, "name": scene.stem, **base,
                 "scene": scene.stem}  # fmt: skip
        if "error" in result or not result.get("points"):
            entry.update(status="failed", error=result.get("error", "no picture"), points=[])
        else:
            point = result["points"][0]
            image = np.load(folder / point.pop("image"))
            if save_image is not None:
                point["image"] = save_image(image, f"picture-{scene.stem}.png")
            entry.update(status="ok", warm=result.get("warm"), points=[point])
        entries.append(entry)
    return entries


# ---------------------------------------------------------------------------- the job


def render_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One configuration: load the scene with its area lights rewritten, a warm-up render at
    ``WARM``, then one timed render per samples count (CPU share beside each)."""

    variant = load_variant(job["variant"])
    tracer = variant.tracer
    if tracer is None:
        return {"error": f"{variant.name} has no tracer"}
    path = Path(job["scene"])
    text = path.read_text(encoding="utf-8")
    if job["cells"] is not None:
        text = configured(text, Config(job["cells"], job["jitter"]), path)
    scene = load_scene_text(text, variant.api, path=path, variant=variant.name)
    world = variant.world_for(scene)
    size = Size(*job["size"])
    started = time.perf_counter()
    warm = scene.resized(WARM.width, WARM.height)
    tracer.render(warm.camera, world, RenderSettings(depth=job["depth"], seed=job["seed"]))
    result: dict[str, Any] = {"warm": time.perf_counter() - started, "points": []}
    scene = scene.resized(size.width, size.height)
    budget = job.get("budget")
    previous: tuple[int, float] | None = None
    for samples in job["samples"]:
        point: dict[str, Any] = {"size": [size.width, size.height], "samples": samples}
        result["points"].append(point)
        if budget is not None and previous is not None:
            guess = previous[1] * samples / previous[0]
            if guess > budget:
                point["skipped"] = (
                    f"predicted to take {guess:.3g} s (linear in the samples), over the "
                    f"{budget:g} s budget"
                )
                continue
        settings = RenderSettings(depth=job["depth"], samples=samples, seed=job["seed"])
        timings = Timings()
        for attempt in range(max(1, int(job.get("repeat", 1)))):
            canvas = timings.time(tracer.render, scene.camera, world, settings)
            if attempt == 0:
                name = f"image-{samples}.npy"
                np.save(folder / name, canvas_array(canvas, variant.api.get("pixel_at")))
                point["image"] = name
            if budget is not None and sum(timings.walls) > budget:
                break
        wall = statistics.median(timings.walls)
        point.update(wall=wall, walls=timings.walls, cpu=statistics.median(timings.shares))
        previous = (samples, wall)
    return result


def measure(bench: Bench) -> None:
    """The section in a bench run (``harness.engine.bench.Bench``): its plan from the run's
    settings (``--light-variant``), its entries into the run's series."""
    s = bench.settings
    plan = Plan(
        variant=s.light_variant, size=s.size, depth=s.depth, seed=s.seed,
        repeat=s.repeat, threads=s.threads, budget=s.budget,
    )  # fmt: skip
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, bench.save_image))


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.light_samples.measure JOB.json``: one configuration's job."""
    return job_main(render_job, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
