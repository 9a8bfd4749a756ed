"""Error against time as convergence (``rtc bench --sections convergence``), chapter 21 here:
for each path-traced scene of the mode (``Mode.convergence_scenes``), every variant's default
that path-traces renders it with 1, 2, 4 ... samples per pixel (one timed render each, in a
fresh process); the fastest of them per sample then renders a converged picture (part
``truth``: ``Mode.convergence_truth`` samples, or fewer within 20 budgets) with another
seed, so its noise is independent of theirs; each picture's RMSE against it is fitted as a
power law of the samples and of the wall time (``fit``), with the time to an RMSE of 0.01
(points with more than a quarter of the converged picture's samples are kept, not fitted).
In a scene with an area light every variant is measured twice, with explicit light sampling
(the default) and without (``RenderSettings.light_sampling``), both against the one
converged picture, rendered with it: both settings converge to the same picture.

Python variants render at ``Mode.convergence_size``, compiled ones (numba, wavefront) at
``Mode.convergence_compiled_size``, each against a converged picture of its own size. A
variant without a path integrator is an entry of part ``refused`` with its one line.
``harness.sections.convergence.report`` reports it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.engine.bench import series_entry, series_task
from harness.engine.jobs import JobOutcome, run_job
from harness.engine.plan import default_names, refusal
from harness.instruments import imagediff
from harness.scenery import SCENES
from harness.scenery.presets import SceneRef
from harness.sections.convergence.fit import power_law, time_to
from raytracer.camera import PATH
from raytracer.lights import AreaLight
from scene import load_scene
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "convergence"
DEPTH = 5  # the C++ report's bounces
TRUTH_BUDGETS = 20  # the converged picture may take this many row budgets
TRUTH_OVER = 4  # a point is fitted when the converged picture has this many times its samples
TRUTH_SEED_STEP = 1_000_003  # the converged picture's seed: the run's plus this
COMPILED = ("variants.numba", "variants.wavefront")  # their tracers render compiled code


def is_compiled(name: str) -> bool:
    """Whether variant ``name``'s tracer is compiled code (it renders the larger size)."""
    tracer = load_variant(name).tracer
    return type(tracer).__module__.startswith(COMPILED)


def path_tracers(bench: Bench, scene: SceneRef) -> list[str]:
    """The defaults of the run's variants that path-trace; the others are entries of part
    ``refused`` with their one line."""
    found = []
    for name in default_names(bench.settings.variants):
        why = refusal(load_variant(name), PATH)
        if why is None:
            found.append(name)
            continue
        bench.log(f"{SECTION}: {name} not run: {why}")
        bench.series.append({"section": SECTION, "part": "refused", "name": name,
                             "scene": scene.name, "status": "refused", "error": why})  # fmt: skip
    return found


def label(entry: dict[str, Any] | Any) -> str:
    """An entry's name in the report: the variant's, and "light sampling off" when so."""
    return entry["name"] + (" (light sampling off)" if entry.get("light_sampling") == "off" else "")


def has_area_light(scene: SceneRef) -> bool:
    """Whether ``scene`` has an area light (light sampling can then be off)."""
    if scene.path is None:
        return False
    loaded = load_scene(scene.path, load_variant("naive").api)
    return any(isinstance(light, AreaLight) for light in loaded.lights)


def _job(
    bench: Bench, name: str, scene: SceneRef, points: list[tuple[Size, int]],
    budget: float | None, extra: dict[str, Any], seed: int | None = None,
) -> tuple[dict[str, Any], JobOutcome]:  # fmt: skip
    settings: dict[str, Any] = {"integrator": PATH}
    if seed is not None:
        settings["seed"] = seed
    # both ways, whatever the run's --light-sampling
    settings["light_sampling"] = extra.get("light_sampling") != "off"
    what = " (converged picture)" if seed else label({"name": "", **extra})
    bench.log(f"{SECTION}: {scene.name}: {name}{what}")
    if bench.watch is not None:
        bench.watch.sample()
    spec = bench.job_spec(name, scene, [series_task(points, budget)], DEPTH, **settings)
    outcome = run_job(*spec)
    return series_entry(SECTION, name, scene, extra, outcome), outcome


def per_sample(entry: dict[str, Any]) -> float:
    """Seconds per camera sample of an entry's largest measured point (inf: none)."""
    done = [p for p in entry.get("points", []) if "wall" in p]
    if entry["status"] != "ok" or not done:
        return math.inf
    p = max(done, key=lambda p: p["size"][0] * p["size"][1] * p["samples"])
    return float(p["wall"]) / (p["size"][0] * p["size"][1] * p["samples"])


def truth_samples(bench: Bench, size: Size, seconds_per_sample: float) -> int:
    """The converged picture's samples: the mode's, halved until it fits ``TRUTH_BUDGETS``
    budgets (16 at the least)."""
    samples = bench.settings.mode.convergence_truth
    budget = bench.settings.budget
    if budget is not None:
        while samples > 16 and seconds_per_sample * size.pixels * samples > TRUTH_BUDGETS * budget:
            samples //= 2
    return samples


def _truth(
    bench: Bench, scene: SceneRef, name: str, size: Size, seconds_per_sample: float
) -> tuple[dict[str, Any], Any]:
    """The converged picture at ``size`` by ``name``: its entry (part ``truth``) and the
    picture (None when it failed)."""
    samples = truth_samples(bench, size, seconds_per_sample)
    seed = (bench.settings.seed + TRUTH_SEED_STEP) % 2**64
    extra = {"part": "truth", "samples": samples, "seed": seed}
    entry, outcome = _job(bench, name, scene, [(size, samples)], None, extra, seed)
    point = entry["points"][0] if entry.get("points") else {}
    picture = None
    if outcome.ok and point.get("image"):
        picture = outcome.image(point["image"])
        filename = f"{SECTION}-{scene.name}-{size.width}x{size.height}-truth.png"
        point["image"] = bench.save_image(picture, filename)
    outcome.discard()
    bench.series.append(entry)
    return entry, picture


def fitted(entry: dict[str, Any], truth: int) -> None:
    """The entry's fits (``fit``): RMSE against samples and against wall time, and the
    headline, the time to an RMSE of 0.01, over the points with at most 1/``TRUTH_OVER``
    of the converged picture's ``truth`` samples (nearer it, its own noise is the error)."""
    done = [p for p in entry.get("points", []) if "wall" in p and p.get("error")]
    for p in done:
        p["fitted"] = p["samples"] * TRUTH_OVER <= truth
    done = [p for p in done if p["fitted"]]
    rmse = [p["error"]["rmse"] for p in done]
    by_samples = power_law([p["samples"] for p in done], rmse)
    by_time = power_law([p["wall"] for p in done], rmse)
    entry["fit"] = {
        "samples": None if by_samples is None else by_samples.as_dict(),
        "time": None if by_time is None else by_time.as_dict(),
        "time_to": time_to(by_time),
    }


def measure_scene(bench: Bench, scene: SceneRef) -> None:
    """One scene: the variants' series, the converged pictures, their errors and fits."""
    mode = bench.settings.mode
    measured: list[tuple[dict[str, Any], JobOutcome, Size]] = []
    both = [{}, {"light_sampling": "off"}] if has_area_light(scene) else [{}]
    for name in path_tracers(bench, scene):
        size = mode.convergence_compiled_size if is_compiled(name) else mode.convergence_size
        points = [(size, n) for n in mode.convergence_samples]
        for extra in both:
            entry, outcome = _job(bench, name, scene, points, bench.settings.budget, extra)
            measured.append((entry, outcome, size))
    if not measured:
        bench.notes.append(f"convergence of {scene.name}: no variant path-traces")
        return
    sampled = [m for m in measured if m[0].get("light_sampling") != "off"]
    fastest = min(sampled, key=lambda m: per_sample(m[0]))
    pictures: dict[Size, Any] = {}
    truths: dict[Size, int] = {}
    for size in sorted({m[2] for m in measured}, key=lambda s: s.pixels):
        entry, picture = _truth(bench, scene, fastest[0]["name"], size, per_sample(fastest[0]))
        if picture is None:
            bench.notes.append(f"convergence of {scene.name} at {size}: the converged picture "
                               f"failed ({entry.get('error')})")  # fmt: skip
        pictures[size] = picture
        truths[size] = int(entry.get("samples", 0))
    for entry, outcome, size in measured:
        reference = pictures.get(size)
        for point in entry.get("points", []):
            if point.get("image") and reference is not None:
                image = outcome.image(point["image"])
                point["error"] = imagediff.image_error(image, reference).as_dict()
            point["image"] = None
        outcome.discard()
        fitted(entry, truths.get(size, 0))
        bench.series.append(entry)


def measure(bench: Bench) -> None:
    for name in bench.settings.mode.convergence_scenes:
        measure_scene(bench, SceneRef(name, SCENES / f"{name}.yml"))
