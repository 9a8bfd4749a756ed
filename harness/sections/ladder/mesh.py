"""The ladder's mesh row beside Embree (issue 36): the bonus chapter's dragon (its stand-in,
``knot-23k.obj``, 23,000 triangles) in front of the camera, primary rays only, one thread.

The scene (``SCENE``: a camera 2.5 times the model's radius in front of it, no light, so a
render is one primary ray per pixel and a black picture) is rendered by ``VARIANT`` and the
same camera's rays are intersected with the same triangles by Embree
(``harness.instruments.embree``), in one fresh process, in turns (each round in another
order), ``rounds`` times each: the calling thread's CPU
seconds (the machine may be shared; the medians and the ratio of each pair are kept); the
kernel's steps (``STEPS``: the variant with one of its options turned back) in the same
turns, so that the row shows what each buys. A
render's time includes what a primary-ray render adds to the intersections (the camera's
rays, writing the canvas; with no light every hit is black, so a render skips the hit's
normal and shading); Embree's is the intersections alone. Without
``embreex`` the entry says why (``status: unavailable``) and the report prints that line.
The row's kernels are compiled before, in the bench's background compile (``warm``).
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments import embree
from harness.scenery.make_meshes import mesh_path
from raytracer.camera import RenderSettings
from scene import load_scene_text
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

PART = "mesh-anchor"
MESH = "knot-23k.obj"
VARIANT = "numba[bvh=sah4,threads=1]"
# the mesh kernel's steps, each an option of the variant, measured in the same turns: what
# the variant is without the step, and what the step is
STEPS = (
    ("numba[threads=1]", "without wide nodes: the compact nodes of two children"),
    ("numba[bvh=sah-items,threads=1]", "without compact nodes: the hierarchy walked as items"),
)
SIZE = Size(640, 480)
SCENE = """\
# the ladder's mesh row (harness/sections/ladder/mesh.py): the dragon's stand-in, no light
- add: camera
  width: {width}
  height: {height}
  field-of-view: 0.8
  from: [0, 0, -3.25]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: obj
  file: {mesh}
"""


def entry(bench: Bench, section: str) -> dict[str, Any]:
    """The ladder's mesh entry for ``bench``'s run (see the module)."""
    result: dict[str, Any] = {
        "section": section, "part": PART, "name": "Embree", "mesh": MESH,
        "variant": VARIANT, "size": [SIZE.width, SIZE.height], "points": [],
    }  # fmt: skip
    if embree.find() is None:
        result.update(status="unavailable", error=embree.missing())
        bench.log(f"{section}: Embree not run: {result['error']}")
        return result
    if bench.warmer is not None:
        bench.warmer.before(VARIANT)  # its kernels, compiled in the background (``warm``)
    bench.log(f"{section}: {VARIANT} and Embree on {MESH}, {SIZE}, in turns")
    job = {**_job(), "rounds": max(3, bench.settings.repeat)}
    outcome = run_in_child(__name__, bench.jobs_folder(f"{section}-{PART}"), job, 1)
    if isinstance(outcome, int):
        result.update(status="failed", error=f"the measuring process exited with {outcome}")
    elif "error" in outcome:
        result.update(status="failed", error=str(outcome["error"]))
    else:
        result.update(status="ok", **outcome)
    return result


def warm(bench: Bench) -> None:
    """Compile the row's kernels (the variant's and its steps', a job each, so that two
    cores compile two) in the bench's background compile, when the row will run (Embree is
    there): the row then only measures."""
    if embree.find() is not None:
        for name in [VARIANT, *(step for step, _ in STEPS)]:
            job = {**_job(), "variant": name, "steps": [], "warm": True, "threads": 1}
            bench.warm_job(f"{name} on {MESH}", __name__, job)


def _job() -> dict[str, Any]:
    return {"variant": VARIANT, "steps": [name for name, _ in STEPS], "mesh": MESH,
            "size": [SIZE.width, SIZE.height]}  # fmt: skip


def _setup(name: str, job: dict[str, Any]) -> Any:
    """(tracer, camera, world, the mesh's model) for variant ``name``, compiled and warm."""
    variant = load_variant(name)
    tracer = variant.tracer
    if tracer is None:
        raise LookupError(f"{variant.name} has no tracer to render with")
    mesh = mesh_path(job["mesh"])  # written first if missing
    text = SCENE.format(width=job["size"][0], height=job["size"][1], mesh=mesh.name)
    scene = load_scene_text(text, variant.api, path=mesh.parent / "scene.yml",
                            variant=variant.name)  # fmt: skip
    (model,) = [spec.mesh for spec in scene.objects if spec.mesh is not None]
    c, w = scene.camera, variant.world_for(scene)
    tracer.render(c, w, SETTINGS)  # compiles, builds the hierarchy
    return tracer, c, w, model


SETTINGS = RenderSettings(depth=1, samples=1, seed=0)


def _render_cpu(setup: Any) -> float:
    """A render's CPU seconds on the calling thread, where a one-thread render runs: not the
    process's, which counted Embree's builder threads still spinning after its turn (up to a
    fifth more, on the turns after Embree's)."""
    tracer, c, w, _ = setup
    canvas = tracer.new_canvas(c)
    started = time.thread_time()
    tracer.render_into(canvas, c, w, SETTINGS)
    return time.thread_time() - started


def _ratios(ours: list[float], theirs: list[float]) -> list[float]:
    return sorted(a / b for a, b in zip(ours, theirs, strict=True))


def measure_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One process: the variant's render, its steps' (``job["steps"]``) and Embree's rays,
    in turns (see the module); with ``job["warm"]``, only their kernels compiled."""
    names = [job["variant"], *job.get("steps", [])]
    try:
        setups = [_setup(name, job) for name in names]
    except LookupError as error:
        return {"error": str(error)}
    if job.get("warm"):
        return {"warmed": names}
    found = embree.find()
    times: list[list[float]] = [[] for _ in names]
    theirs: list[float] = []
    rays = None
    _, c, _, model = setups[0]
    for turn in range(int(job["rounds"])):
        # each round in another order, Embree first or last: the first render after another
        # kind of work runs on cold caches, and no one is always first
        order = [(turn + k) % len(names) for k in range(len(names))]
        if turn % 2:
            rays = embree.primary_rays(c, model.positions, model.triangles, 1, found)
            theirs.append(rays.cpu[0])
        for k in order:
            times[k].append(_render_cpu(setups[k]))
        if not turn % 2:
            rays = embree.primary_rays(c, model.positions, model.triangles, 1, found)
            theirs.append(rays.cpu[0])
    assert rays is not None  # rounds >= 1
    ours = times[0]
    steps = [
        {"variant": name, "ours": own, "median": statistics.median(own),
         "ratios": _ratios(own, theirs)}
        for name, own in zip(names[1:], times[1:], strict=True)
    ]  # fmt: skip
    return {
        "version": rays.version, "triangles": setups[0][3].count, "rays": rays.rays,
        "hits": rays.hits, "ours": ours, "embree": theirs,
        "ours_median": statistics.median(ours), "embree_median": statistics.median(theirs),
        "ratios": _ratios(ours, theirs), "steps": steps,
    }  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.ladder.mesh JOB.json``."""
    return job_main(measure_job, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
