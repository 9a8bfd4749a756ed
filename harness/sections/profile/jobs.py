"""A profiling process (``python -m harness.sections.profile.jobs JOB.json``): the render's
stages timed (run under py-spy for the flame graph), or the render under cProfile (see
``harness.sections.profile.profiler``)."""

from __future__ import annotations

import cProfile
import marshal
import pstats
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from groundwork.images import write_image
from harness.engine.jobs import job_main
from harness.scenery.make_meshes import provide
from harness.sections.profile.profiler import is_compiled
from harness.sections.profile.stats import collect, summarize
from raytracer.camera import WHITTED, RenderSettings
from scene import load_scene
from variants.registry import load_variant

# ---------------------------------------------------------------------------- the jobs


def _load(job: Mapping[str, Any], variant: Any) -> Any:
    scene = load_scene(job["scene"], variant.api, variant=variant.name, provide_mesh=provide)
    return scene.resized(*job["size"])


def _settings(job: Mapping[str, Any]) -> Any:
    return RenderSettings(
        depth=job["depth"], samples=job["samples"], seed=job["seed"],
        integrator=job.get("integrator", WHITTED),
        light_sampling=bool(job.get("light_sampling", True)),
    )  # fmt: skip


def _kernel_files() -> set[str]:
    # deferred: keeps ~85 ms (numba's loader) out of other variants' flame graphs
    from variants.numba.specialize import kernel_folder

    return {p.name for p in kernel_folder().glob("*.so")}


def stages_job(job: Mapping[str, Any]) -> dict[str, Any]:
    """The render timed stage by stage (see the module), then repeated (untimed) until the
    flame graph has ``flame_seconds`` of rendering to sample."""
    variant = load_variant(job["variant"])
    settings = _settings(job)
    compiled = is_compiled(variant)
    stages: dict[str, float] = {}
    result: dict[str, Any] = {"compiled": compiled}
    started = clock = time.perf_counter()

    def lap() -> float:
        nonlocal clock
        now = time.perf_counter()
        seconds, clock = now - clock, now
        return seconds

    scene = _load(job, variant)
    stages["load"] = lap()
    tracer = variant.tracer
    before: set[str] = set()
    builder = 0.0
    if tracer is not None and compiled:
        before = _kernel_files()
        if getattr(getattr(tracer, "options", None), "bvh", None) == "sah":
            # deferred: keeps ~85 ms (numba's loader) out of other variants' flame graphs
            from variants.numba.bvh import load_bvh_builder

            load_bvh_builder()  # loaded (built if missing) here, not inside the packing
        builder = lap()
    c, w = scene.camera, variant.world_for(scene)
    made = lap()  # the tracer's world: the book's shapes built, or the scene packed
    packed_early = getattr(w, "seconds", None)
    if packed_early is None:
        stages["load"] += made
    else:
        stages["pack"] = made
    if tracer is None:  # a learner's tracer: the book's render, whole
        image = variant.api["render"](c, w, settings)
        stages["render"] = lap()
    else:
        tracer.forget()
        frame = tracer.prepared(c, w, settings)
        prepare = lap()
        packed = getattr(getattr(frame, "packed", None), "seconds", None)
        if compiled and packed_early is not None:
            stages["compile"] = builder + prepare
        elif compiled and packed is not None:
            stages["pack"] = float(packed)
            stages["compile"] = builder + prepare - float(packed)
        else:
            stages["prepare"] = builder + prepare
        image = tracer.new_canvas(c)
        tracer.render_into(image, c, w, settings)
        stages["trace"] = lap()
    write_image(image, job["image"])
    stages["encode"] = lap()
    result["wall"] = time.perf_counter() - started
    result["stages"] = stages
    if tracer is not None and compiled:
        new = sorted(_kernel_files() - before)
        result["kernels"] = (
            f"built now ({', '.join(new)})" if new else "loaded from the kernel cache"
        )
        again = tracer.new_canvas(c)
        clock = time.perf_counter()
        tracer.render_into(again, c, w, settings)
        result["trace_again"] = lap()
    spent = stages.get("trace", 0.0) + stages.get("prepare", 0.0) + stages.get("render", 0.0)
    wanted = float(job.get("flame_seconds") or 0.0)
    result["renders"] = 1 + _renders_for_flame(variant, (c, w, settings), wanted - spent)
    return result


def _renders_for_flame(variant: Any, render: tuple[Any, Any, Any], seconds: float) -> int:
    """Untimed renders of ``render`` (camera, world, settings), again and again until they
    took ``seconds`` (what the flame graph still needs to sample): how many."""
    c, w, settings = render
    tracer = variant.tracer
    renders = 0
    while seconds > 0:
        start = time.perf_counter()
        if tracer is None:
            variant.api["render"](c, w, settings)
        else:
            tracer.forget()
            tracer.render_into(tracer.new_canvas(c), c, w, settings)
        seconds -= time.perf_counter() - start
        renders += 1
    if tracer is not None:
        tracer.forget()
    return renders


def cprofile_job(job: Mapping[str, Any]) -> dict[str, Any]:
    """The render (prepare and trace) under cProfile: ``summarize``'s figures, and the raw
    statistics written to ``job["pstats"]`` when given."""
    variant = load_variant(job["variant"])
    settings = _settings(job)
    scene = _load(job, variant)
    c, w, tracer = scene.camera, variant.world_for(scene), variant.tracer
    if tracer is not None:
        tracer.forget()
    profile = cProfile.Profile()
    started = time.perf_counter()
    profile.enable()
    try:
        if tracer is None:
            variant.api["render"](c, w, settings)
        else:
            tracer.prepared(c, w, settings)
            tracer.render_into(tracer.new_canvas(c), c, w, settings)
    finally:
        profile.disable()
    seconds = time.perf_counter() - started
    if tracer is not None:
        tracer.forget()
    table = collect(profile)
    if job.get("pstats"):  # for python -m pstats, snakeviz ...: marshal, as dump_stats writes
        Path(job["pstats"]).write_bytes(marshal.dumps(table))
        pstats.Stats(job["pstats"])  # it reads back
    return {"seconds": seconds, **summarize(table, int(job["top"]))}




def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.profile.jobs JOB.json``: a stages or a cProfile job."""
    def run(job: dict[str, Any], _: Path) -> dict[str, Any]:
        return stages_job(job) if job["kind"] == "stages" else cprofile_job(job)

    return job_main(run, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
