"""Cost against scene size (issue 14): ``rtc bench --sections scene-size``.

The same scene (a floor, one light, a noisy torus of 1,000 to 1,000,000 flat triangles from
``harness.make_meshes``, ``SCALE_MESHES``) rendered at the run's size and samples by each of
``--mesh-variants`` (default ``numba`` and ``numba[bvh=off]``: the hierarchy against the flat
loop), one fresh process per (variant, mesh), with its costs apart:

- ``load``: from the scene file to what the tracer renders: ``load_scene`` (the YAML, the OBJ
  file read into arrays) and the tracer's ``world_for`` (``world``: the book's shapes built
  and divided for a Python tracer; the tables packed for a compiled one), and the memory it
  took (resident set: its high-water mark after the load less the resident set before it);
- ``prepare``: the tracer's ``prepare`` for the frame, once (numba: packing the world into
  arrays, building the hierarchy, loading the compiled render), and of it the hierarchy's
  build when the tracer reports it (``frame.packed.hierarchy.seconds``);
- ``render``: ``render_into`` a prepared frame, ``repeat`` times (median), after a warm-up
  render of the smallest mesh at 8x6 in the same process (compilation stays out).

A point whose render the previous size predicts (linearly in the triangle count) to take
longer than the run's budget is skipped, and says so; the flat loop stops where it gets too
slow. Every variant's picture of a mesh is compared with the first variant's.

Beside it, ``parse_obj_file`` alone on each mesh (the ``obj-parse`` entry, one fresh process
per mesh, ``repeat`` parses): seconds, the resident set's growth (VmHWM, reset before the
parse) and, up to ``TRACEMALLOC_MAX`` triangles, ``tracemalloc``'s current and peak bytes
(tracemalloc slows the parse about 6x, so the largest mesh has the resident set only).

Everything lands in the run file's ``series`` (``section``: ``scene-size`` and ``obj-parse``);
``harness.scene_size_report`` turns it into the report's section and its log-log plot. The
section is not part of the default ``rtc bench`` (the meshes take minutes to load and pack at
a million triangles): run it on its own, ``rtc bench --sections scene-size``, and
``rtc report`` shows the newest run that has it.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from harness.make_meshes import CATALOGUE, GENERATED, SCALE_MESHES, mesh_path
from harness.sizes import Size

SECTION = "scene-size"
PARSE_SECTION = "obj-parse"
DEFAULT_VARIANTS = "numba,numba[bvh=off]"
TRACEMALLOC_MAX = 100_000  # triangles: above this, the parse's memory is the resident set only
WARM = Size(8, 6)  # the warm-up render's size
SCENE = """\
# the scene of rtc bench's scene-size section (harness/scene_size.py)
- add: camera
  width: {width}
  height: {height}
  field-of-view: 0.8
  from: [0, 3, -4]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-5, 8, -6]
  intensity: [1, 1, 1]
- add: plane
  transform:
    - [translate, 0, -0.6, 0]
- add: obj
  file: {mesh}
  transform:
    - [scale, 0.1, 0.1, 0.1]  # the rings are made ten times larger (harness/make_meshes.py)
  material:
    color: [0.8, 0.3, 0.2]
"""

Log = Callable[[str], None]


def scene_text(mesh: str, size: Size) -> str:
    """The section's scene file, its OBJ file ``mesh`` beside it."""
    return SCENE.format(width=size.width, height=size.height, mesh=mesh)


def mesh_names(text: str) -> tuple[str, ...]:
    """``"all"``, or sizes and names separated by commas (``1k,10k``, ``ring-1m.obj``) ->
    catalogue names, smallest first; ``ValueError`` naming a mesh that does not exist."""
    wanted: list[str] = []
    for token in (t.strip() for t in text.split(",")):
        if not token:
            continue
        if token == "all":
            wanted.extend(SCALE_MESHES)
            continue
        name = token if token in CATALOGUE else f"ring-{token.lower()}.obj"
        if name not in CATALOGUE:
            sizes = ", ".join(n.removeprefix("ring-").removesuffix(".obj") for n in SCALE_MESHES)
            raise ValueError(
                f"unknown mesh {token!r}; choose sizes from {sizes}, names from "
                f"{', '.join(CATALOGUE)}, or all"
            )
        wanted.append(name)
    if not wanted:
        raise ValueError("no mesh chosen; expected e.g. 1k,10k,100k,1m or all")
    return tuple(sorted(dict.fromkeys(wanted), key=lambda n: CATALOGUE[n].triangles))


@dataclass(frozen=True)
class Plan:
    """What the section measures.

    variants: canonical names (or names the registry rejects: recorded as unavailable);
    meshes: catalogue names, smallest first; size, samples, depth, seed: the renders';
    threads: CPUs per measuring process (None: all); repeat: renders (and parses) per point;
    budget: seconds one render may be predicted to take (None: no limit); folder: where the
    meshes are (written there when missing).
    """

    variants: tuple[str, ...]
    meshes: tuple[str, ...]
    size: Size
    samples: int = 1
    depth: int = 5
    seed: int = 0
    threads: int | None = None
    repeat: int = 3
    budget: float | None = None
    folder: Path = GENERATED


def predicted_render(points: list[dict[str, Any]], triangles: int) -> float | None:
    """A render of ``triangles`` estimated from the largest measured point, as if time grew
    linearly with the triangle count (the flat loop's rate; a hierarchy does better)."""
    measured = [p for p in points if p.get("render")]
    if not measured:
        return None
    last = max(measured, key=lambda p: p["triangles"])
    return float(last["render_median"]) * triangles / last["triangles"]


# ---------------------------------------------------------------------------- the parent


def _run_job(folder: Path, job: dict[str, Any], threads: int | None) -> dict[str, Any]:
    """Run one job in a fresh process (``python -m harness.scene_size JOB``); its result."""
    from harness.jobs import run_in_child

    result = run_in_child("harness.scene_size", folder, job, threads)
    if isinstance(result, int):
        return {"error": f"the measuring process exited with {result}"}
    return result


def run(
    plan: Plan,
    jobs: Path,
    log: Log,
    save_image: Callable[[Any, str], str] | None = None,
) -> list[dict[str, Any]]:
    """Measure ``plan``: the ``obj-parse`` entry, then one ``scene-size`` entry per variant.

    jobs: a folder for the jobs' files (made here); save_image(array, file name) -> the
    picture's path in the run (None: pictures are not kept).
    """
    import numpy as np

    from harness.imagediff import image_error
    from variants.registry import load_variant

    paths = {name: mesh_path(name, plan.folder) for name in plan.meshes}
    counter = iter(range(1, 1_000_000))
    parse: dict[str, Any] = {"section": PARSE_SECTION, "name": "parse_obj_file", "status": "ok"}
    parse["points"] = []
    for name in plan.meshes:
        log(f"{SECTION}: parse_obj_file {name}")
        job = {
            "kind": "parse",
            "mesh": str(paths[name]),
            "repeat": plan.repeat,
            "tracemalloc": CATALOGUE[name].triangles <= TRACEMALLOC_MAX,
        }
        result = _run_job(jobs / f"mesh-{next(counter):03d}", job, plan.threads)
        parse["points"].append({"mesh": name, "triangles": CATALOGUE[name].triangles, **result})
    entries = [parse]
    first_images: dict[str, Any] = {}
    for variant in plan.variants:
        entry: dict[str, Any] = {"section": SECTION, "name": variant, "points": []}
        try:
            entry["name"] = load_variant(variant).name
        except LookupError as error:
            entry.update(status="unavailable", error=str(error.args[0] if error.args else error))
            log(f"{SECTION}: {variant} not run: {entry['error']}")
            entries.append(entry)
            continue
        entry["status"] = "ok"
        for name in plan.meshes:
            point: dict[str, Any] = {"mesh": name, "triangles": CATALOGUE[name].triangles}
            guess = predicted_render(entry["points"], point["triangles"])
            if plan.budget is not None and guess is not None and guess > plan.budget:
                point["skipped"] = (
                    f"a render predicted to take {guess:.3g} s (linear in the triangles from "
                    f"the largest point measured), over the {plan.budget:g} s budget"
                )
                log(f"{SECTION}: {entry['name']} {name} skipped: {point['skipped']}")
                entry["points"].append(point)
                continue
            log(f"{SECTION}: {entry['name']} {name}")
            job = {
                "kind": "render",
                "variant": entry["name"],
                "mesh": str(paths[name]),
                "warm_mesh": str(paths[plan.meshes[0]]),
                "size": [plan.size.width, plan.size.height],
                "samples": plan.samples,
                "depth": plan.depth,
                "seed": plan.seed,
                "repeat": plan.repeat,
                "budget": plan.budget,
            }
            folder = jobs / f"mesh-{next(counter):03d}"
            result = _run_job(folder, job, plan.threads)
            point.update(result)
            image_file = point.pop("image", None)
            if image_file and "error" not in point:
                image = np.load(folder / image_file)
                if name not in first_images:
                    first_images[name] = (entry["name"], image)
                else:
                    against, reference = first_images[name]
                    found = image_error(image, reference).as_dict()
                    point["difference"] = {"against": against, **found}
                if save_image is not None:
                    slug = "".join(c if c.isalnum() else "-" for c in entry["name"]).strip("-")
                    point["image"] = save_image(image, f"{SECTION}-{slug}-{name[:-4]}.png")
            entry["points"].append(point)
        entries.append(entry)
    return entries


# ---------------------------------------------------------------------------- the jobs


def _peak_since_reset(was_reset: bool) -> int:
    from harness.usage import peak_memory

    return peak_memory(was_reset).main


def parse_job(job: dict[str, Any]) -> dict[str, Any]:
    """``parse_obj_file`` on one file: read time, parse seconds (each of ``repeat``), the
    resident set's growth during the first parse, and tracemalloc's figures if asked."""
    import gc
    import tracemalloc

    from harness.usage import current_rss, reset_peak_rss
    from raytracer.obj_file import parse_obj_file

    path = Path(job["mesh"])
    started = time.perf_counter()
    text = path.read_text(encoding="utf-8", errors="replace")
    read = time.perf_counter() - started
    seconds: list[float] = []
    result: dict[str, Any] = {"read": read, "bytes": len(text)}
    for attempt in range(int(job["repeat"])):
        gc.collect()
        before = current_rss()
        was_reset = reset_peak_rss()
        started = time.perf_counter()
        parser = parse_obj_file(text, source=str(path))
        seconds.append(time.perf_counter() - started)
        if attempt == 0:
            result["rss_growth"] = max(_peak_since_reset(was_reset) - before, 0)
            result["rss_method"] = "VmHWM" if was_reset else "ru_maxrss"
            result["parsed_triangles"] = parser.triangles
            result["degenerate"] = parser.degenerate_triangles
        del parser
    result["parse"] = seconds
    result["parse_median"] = statistics.median(seconds)
    if job.get("tracemalloc"):
        gc.collect()
        tracemalloc.start()
        parser = parse_obj_file(text, source=str(path))
        current, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        result["tracemalloc"] = {"current": current, "peak": peak}
        del parser
    return result


def _count_primitives(specs: Any) -> int:
    """The leaf shapes a scene description holds (an OBJ model's triangles each)."""
    total = 0
    for spec in specs:
        if spec.mesh is not None:
            total += spec.mesh.count
        else:
            parts = spec.parts()
            total += _count_primitives(parts) if parts else 1
    return total


def render_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One variant on one mesh: load, prepare, warm-up, timed renders (see the module)."""
    import gc

    import numpy as np

    from harness.imagediff import canvas_array
    from harness.usage import Timings, current_rss, reset_peak_rss
    from raytracer.camera import RenderSettings
    from scene import load_scene_text
    from variants.registry import load_variant

    variant = load_variant(job["variant"])
    tracer = variant.tracer
    if tracer is None:
        return {"error": f"{variant.name} has no tracer to prepare frames with"}
    settings = RenderSettings(depth=job["depth"], samples=job["samples"], seed=job["seed"])
    size = Size(*job["size"])

    def load(mesh: Path, at: Size) -> Any:
        text = scene_text(mesh.name, at)
        path = mesh.parent / "scene.yml"  # not written: its OBJ file is beside it
        return load_scene_text(text, variant.api, path=path, variant=variant.name)

    started = time.perf_counter()
    warm = load(Path(job["warm_mesh"]), WARM)
    tracer.render(warm.camera, variant.world_for(warm), settings)
    result: dict[str, Any] = {"warm": time.perf_counter() - started}
    del warm
    tracer.forget()
    gc.collect()
    before = current_rss()
    was_reset = reset_peak_rss()
    started = time.perf_counter()
    scene = load(Path(job["mesh"]), size)
    loaded = time.perf_counter()
    c, w = scene.camera, variant.world_for(scene)
    result["load"] = time.perf_counter() - started
    result["world"] = time.perf_counter() - loaded
    result["load_rss"] = max(_peak_since_reset(was_reset) - before, 0)
    result["primitives"] = _count_primitives(scene.objects)
    started = time.perf_counter()
    frame = tracer.prepared(c, w, settings)
    result["prepare"] = time.perf_counter() - started
    hierarchy = getattr(getattr(frame, "packed", None), "hierarchy", None)
    if hierarchy is not None:
        result["hierarchy"] = {
            key: getattr(hierarchy, key)
            for key in ("structure", "units", "nodes", "leaves", "depth", "seconds")
            if hasattr(hierarchy, key)
        }
    timings = Timings()
    image = None
    budget = job.get("budget")
    while len(timings.walls) < int(job["repeat"]):
        canvas = tracer.new_canvas(c)
        timings.time(tracer.render_into, canvas, c, w, settings)
        if image is None:
            image = canvas_array(canvas, variant.api.get("pixel_at"))
        if budget is not None and sum(timings.walls) >= budget:
            break
    result.update(timings.fields())
    result["peak_rss"] = _peak_since_reset(was_reset)
    if image is not None:
        np.save(folder / "image.npy", image)
        result["image"] = "image.npy"
    return result


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.scene_size JOB.json``: a parse or a render job."""
    from harness.jobs import job_main

    def run(job: dict[str, Any], folder: Path) -> dict[str, Any]:
        return parse_job(job) if job["kind"] == "parse" else render_job(job, folder)

    return job_main(run, sys.argv[1:] if argv is None else argv)


def slope(points: list[tuple[float, float]]) -> float | None:
    """The least-squares slope of log(y) against log(x) (``None`` with fewer than two
    distinct x): 0 means the cost does not grow, 1 linear, 0.1-0.2 logarithmic-ish."""
    pairs = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len({x for x, _ in pairs}) < 2:
        return None
    mx = statistics.fmean(x for x, _ in pairs)
    my = statistics.fmean(y for _, y in pairs)
    sxx = sum((x - mx) ** 2 for x, _ in pairs)
    sxy = sum((x - mx) * (y - my) for x, y in pairs)
    return sxy / sxx


if __name__ == "__main__":
    sys.exit(main())
