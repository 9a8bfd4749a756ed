"""Cost against scene size (issue 14): ``rtc bench --sections scene-size``.

The same scene (a floor, one light, a noisy torus of 1,000 to 1,000,000 flat triangles from
``harness.scenery.make_meshes``, ``SCALE_MESHES``) rendered at the run's size and samples by each of
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

Beside it, the OBJ readers alone on each mesh (the ``obj-parse`` entry, one fresh process
per mesh, ``repeat`` reads each): the scene loader's ``read_mesh`` (arrays) and the book's
``parse_obj_file`` (an object per triangle): seconds, the resident set's growth (VmHWM,
reset before each) and, up to ``TRACEMALLOC_MAX`` triangles, ``tracemalloc``'s current and
peak bytes for the book's parser (it slows the parse about 6x).

Then Embree's primary rays on each mesh (the ``scene-size-embree`` entry,
``harness.sections.scene_size.anchor``): the same scene's camera and mesh, intersection only,
one thread, when ``embreex`` is installed; otherwise the entry says why.

And whole commands side by side (the ``scene-size-command`` entry): for each mesh,
``rtc render`` with ``numba`` as a user runs it (a fresh process from start to exit, after
one warm-up command that compiles what it needs) against POV-Ray 3.7 rendering the same
scene (``pov_scene``: the mesh as a ``mesh2``, the same camera, light, floor and colours)
with as many threads, ``repeat`` times each, in turns: wall and CPU seconds, peak resident
set (the kernel's accounting of the child), and POV-Ray's own parse and trace times. Without
POV-Ray (``harness.instruments.povray``) the entry says why and has our commands alone.

Everything lands in the run file's ``series`` (``section``: ``scene-size``, ``obj-parse`` and
``scene-size-command``);
``harness.sections.scene_size.report`` turns it into the report's section and its log-log plot. The
section is not part of the default ``rtc bench`` (the meshes take minutes to load and pack at
a million triangles): run it on its own, ``rtc bench --sections scene-size``, and
``rtc report`` shows the newest run that has it.
"""

from __future__ import annotations

import gc
import itertools
import math
import statistics
import subprocess
import sys
import time
import tracemalloc
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments import povray
from harness.instruments.imagediff import canvas_array, image_error
from harness.instruments.usage import (
    ProcessTimeout,
    Timings,
    current_rss,
    peak_memory,
    reset_peak_rss,
    wait_with_usage,
)
from harness.scenery.make_meshes import CATALOGUE, GENERATED, SCALE_MESHES, mesh_path
from harness.sections.scene_size import anchor
from raytracer.camera import RenderSettings
from raytracer.obj_file import parse_obj_file
from scene import load_scene_text
from scene.obj_mesh import read_mesh
from variants.registry import load_variant

SECTION = "scene-size"
PARSE_SECTION = "obj-parse"
COMMAND_SECTION = "scene-size-command"
COMMAND_VARIANT = "numba"  # the variant of the whole commands set beside POV-Ray
DEFAULT_VARIANTS = "numba,numba[bvh=off]"
TRACEMALLOC_MAX = 100_000  # triangles: above this, the parse's memory is the resident set only
WARM = Size(8, 6)  # the warm-up render's size
SCENE = """\
# the scene of rtc bench's scene-size section (harness/sections/scene_size/measure.py)
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
    - [scale, 0.1, 0.1, 0.1]  # the rings are made ten times larger (harness/scenery/make_meshes.py)
  material:
    color: [0.8, 0.3, 0.2]
"""

Log = Callable[[str], None]


POV_SCENE = """\
// the scene of rtc bench's scene-size section as POV-Ray 3.7 reads it
// (harness/sections/scene_size/measure.py)
#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light rgb <1, 1, 1> }}
camera {{ perspective location <0, 3, -4> look_at <0, 0, 0> sky <0, 1, 0>
  right x * {width} / {height} up y angle degrees(0.8) }}
light_source {{ <-5, 8, -6> color rgb <1, 1, 1> }}
plane {{ y, -0.6 pigment {{ color rgb <1, 1, 1> }}
  finish {{ ambient 0.1 diffuse 0.9 phong 0.9 phong_size 200 }} }}
mesh2 {{
"""
POV_SCENE_END = """\
  pigment { color rgb <0.8, 0.3, 0.2> }
  finish { ambient 0.1 diffuse 0.9 phong 0.9 phong_size 200 }
  scale 0.1
}
"""


def pov_scene(mesh: Path, size: Size, target: Path) -> Path:
    """Write ``target``: the section's scene (``scene_text``) for POV-Ray, the OBJ file
    ``mesh`` as a ``mesh2`` (vertices and faces as the scene loader reads them)."""

    model = read_mesh(mesh.read_bytes(), str(mesh))
    with target.open("w", encoding="ascii") as out:
        out.write(POV_SCENE.format(width=size.width, height=size.height))
        out.write(f"  vertex_vectors {{ {len(model.positions)},\n")
        np.savetxt(out, model.positions, fmt="    <%.17g, %.17g, %.17g>,")
        out.write(f"  }}\n  face_indices {{ {model.count},\n")
        np.savetxt(out, model.triangles, fmt="    <%d, %d, %d>,")
        out.write("  }\n")
        out.write(POV_SCENE_END)
    return target


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


def measure(bench: Any) -> None:
    """The section under ``rtc bench`` (``harness.sections``): ``run`` with the bench's
    settings, its entries added to the run's series."""
    s = bench.settings
    plan = Plan(
        variants=s.mesh_variants, meshes=s.meshes, size=s.size, samples=s.samples,
        depth=s.depth, seed=s.seed, threads=s.threads, repeat=s.repeat, budget=s.budget,
    )  # fmt: skip
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, bench.save_image))


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
    """Run one job in a fresh process (``python -m harness.sections.scene_size.measure JOB``); its
    result."""
    result = run_in_child("harness.sections.scene_size.measure", folder, job, threads)
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

    paths = {name: mesh_path(name, plan.folder) for name in plan.meshes}
    folders = (jobs / f"mesh-{n:03d}" for n in itertools.count(1))  # one per job, in turn
    entries = [_parse_entry(plan, paths, folders, log)]
    first_images: dict[str, Any] = {}  # per mesh: the first variant's name and picture
    for variant in plan.variants:
        entry: dict[str, Any] = {"section": SECTION, "name": variant, "points": []}
        try:
            entry["name"] = load_variant(variant).name
        except LookupError as error:
            entry.update(status="unavailable", error=str(error.args[0] if error.args else error))
            log(f"{SECTION}: {variant} not run: {entry['error']}")
        else:
            entry["status"] = "ok"
            for name in plan.meshes:
                point, picture = _render_point(plan, entry, name, paths, folders, log)
                if picture is not None:
                    image = np.load(picture)
                    _picture(point, image, (entry["name"], name), first_images, save_image)
                entry["points"].append(point)
        entries.append(entry)
    meshes = {name: (paths[name], CATALOGUE[name].triangles) for name in plan.meshes}
    entries.append(anchor.entry(meshes, scene_text, plan.size, plan.repeat, folders, log))
    entries.append(commands(plan, paths, jobs, log))
    return entries


def _parse_entry(
    plan: Plan, paths: dict[str, Path], folders: Iterator[Path], log: Log
) -> dict[str, Any]:
    """The ``obj-parse`` entry: each mesh parsed in a fresh process."""
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
        result = _run_job(next(folders), job, plan.threads)
        parse["points"].append({"mesh": name, "triangles": CATALOGUE[name].triangles, **result})
    return parse


def _render_point(
    plan: Plan,
    entry: dict[str, Any],
    name: str,
    paths: dict[str, Path],
    folders: Iterator[Path],
    log: Log,
) -> tuple[dict[str, Any], Path | None]:
    """Mesh ``name`` rendered by ``entry``'s variant in a fresh process, and the file of
    the picture it wrote; or why not (over the budget, from the points before)."""
    point: dict[str, Any] = {"mesh": name, "triangles": CATALOGUE[name].triangles}
    guess = predicted_render(entry["points"], point["triangles"])
    if plan.budget is not None and guess is not None and guess > plan.budget:
        point["skipped"] = (
            f"a render predicted to take {guess:.3g} s (linear in the triangles from "
            f"the largest point measured), over the {plan.budget:g} s budget"
        )
        log(f"{SECTION}: {entry['name']} {name} skipped: {point['skipped']}")
        return point, None
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
    folder = next(folders)
    point.update(_run_job(folder, job, plan.threads))
    image_file = point.pop("image", None)
    return point, folder / image_file if image_file and "error" not in point else None


def _picture(
    point: dict[str, Any],
    image: Any,
    rendered: tuple[str, str],
    first_images: dict[str, Any],
    save_image: Callable[[Any, str], str] | None,
) -> None:
    """The point's picture against the first variant's of the same mesh (``difference``),
    then kept in the run (``image``: its path there) or dropped; ``rendered``: the variant
    and the mesh."""
    variant, mesh = rendered
    if mesh not in first_images:
        first_images[mesh] = (variant, image)
    else:
        against, reference = first_images[mesh]
        point["difference"] = {"against": against, **image_error(image, reference).as_dict()}
    if save_image is not None:
        slug = "".join(c if c.isalnum() else "-" for c in variant).strip("-")
        point["image"] = save_image(image, f"{SECTION}-{slug}-{mesh[:-4]}.png")


def _rtc_render(scene: Path, output: Path, size: Size, threads: int | None) -> list[str]:
    """``rtc render`` with ``COMMAND_VARIANT`` (``threads`` of its own, if given)."""
    variant = COMMAND_VARIANT if threads is None else f"{COMMAND_VARIANT}[threads={threads}]"
    return [
        sys.executable, "-m", "rtc.cli", "render", str(scene), "-o", str(output),
        "--variant", variant, "--size", f"{size.width}x{size.height}",
    ]  # fmt: skip


def _command(args: list[str], cwd: Path) -> dict[str, Any]:
    """One whole process, from start to exit: wall and CPU seconds, peak resident set."""

    started = time.perf_counter()
    process = subprocess.Popen(
        args, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )  # fmt: skip
    try:
        status, cpu, peak = wait_with_usage(process, COMMAND_TIMEOUT, started)
    except ProcessTimeout as error:
        return {"error": f"{args[3]}: {error}"}
    wall = time.perf_counter() - started
    err = process.stderr.read().decode(errors="replace") if process.stderr else ""
    if status != 0:
        return {"error": f"exit status {status}: {err.strip()[-300:]}"}
    return {"wall": wall, "cpu": cpu, "peak": peak}


COMMAND_TIMEOUT = 600.0  # seconds one whole command may take


def commands(plan: Plan, paths: dict[str, Path], jobs: Path, log: Log) -> dict[str, Any]:
    """The ``scene-size-command`` entry: per mesh, ``rtc render`` with ``numba`` against
    POV-Ray on the same scene, whole processes, ``repeat`` times each in turns (see the
    module)."""
    found = povray.find()
    threads = plan.threads or 2
    entry: dict[str, Any] = {
        "section": COMMAND_SECTION, "name": COMMAND_VARIANT, "status": "ok", "points": [],
        "threads": threads, "povray": found.version if found else None,
        "povray_missing": None if found else povray.missing(),
    }  # fmt: skip
    folder = (jobs / "commands").resolve()  # the commands run in it: no relative path
    folder.mkdir(parents=True, exist_ok=True)
    for name in plan.meshes:
        scene = folder / f"{name[:-4]}.yml"
        scene.write_text(scene_text(str(paths[name].resolve()), plan.size), encoding="utf-8")
        pov = pov_scene(paths[name], plan.size, folder / f"{name[:-4]}.pov") if found else None
        ours = _rtc_render(scene, folder / f"{name[:-4]}.png", plan.size, plan.threads)
        log(f"{COMMAND_SECTION}: rtc render --variant {COMMAND_VARIANT} and POV-Ray, {name}")
        point: dict[str, Any] = {"mesh": name, "triangles": CATALOGUE[name].triangles}
        warm = _command(ours, folder)  # compiles what the scene needs, if anything
        if "error" in warm:
            point["error"] = warm["error"]
            entry["points"].append(point)
            continue
        runs: dict[str, list[dict[str, Any]]] = {"ours": [], "povray": []}
        for _ in range(plan.repeat):
            runs["ours"].append(_command(ours, folder))
            if found is not None and pov is not None:
                try:
                    done = povray.render(found, pov, plan.size, threads, timeout=COMMAND_TIMEOUT)
                except povray.PovrayError as error:
                    runs["povray"].append({"error": str(error)})
                else:
                    runs["povray"].append(done.as_dict())
        for key, measured_runs in runs.items():
            good = [r for r in measured_runs if "error" not in r]
            if measured_runs and not good:
                point[key] = {"error": measured_runs[0]["error"]}
            elif good:
                point[key] = {
                    field: statistics.median(float(r[field]) for r in good)
                    for field in ("wall", "cpu", "peak", "parse", "trace")
                    if all(r.get(field) is not None for r in good)
                } | {"walls": [float(r["wall"]) for r in good]}
        entry["points"].append(point)
    return entry


# ---------------------------------------------------------------------------- the jobs


def _peak_since_reset(was_reset: bool) -> int:
    return peak_memory(was_reset).main


def parse_job(job: dict[str, Any]) -> dict[str, Any]:
    """One OBJ file: the scene loader's ``read_mesh`` (seconds of each of ``repeat`` reads,
    from the file's bytes, and the resident set's growth during the first), then the
    book's ``parse_obj_file`` (read time, parse seconds, the resident set's growth during
    the first parse, and tracemalloc's figures if asked)."""

    path = Path(job["mesh"])
    result: dict[str, Any] = {"arrays": []}
    for attempt in range(int(job["repeat"])):
        gc.collect()
        before = current_rss()
        was_reset = reset_peak_rss()
        started = time.perf_counter()
        mesh = read_mesh(path.read_bytes(), str(path))
        result["arrays"].append(time.perf_counter() - started)
        if attempt == 0:
            result["arrays_rss_growth"] = max(_peak_since_reset(was_reset) - before, 0)
            result["arrays_triangles"] = mesh.count
        del mesh
    result["arrays_median"] = statistics.median(result["arrays"])
    started = time.perf_counter()
    text = path.read_text(encoding="utf-8", errors="replace")
    result.update(read=time.perf_counter() - started, bytes=len(text))
    seconds: list[float] = []
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
    """``python -m harness.sections.scene_size.measure JOB.json``: a parse or a render job."""
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
