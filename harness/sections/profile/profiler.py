"""Where the time goes (issue 18, item 5): ``rtc profile`` and ``rtc bench --sections profile``.

One render of a scene (chapter 7's camera and world, from a scene file) through a variant, taken
apart two ways, each in a fresh process (``python -m harness.sections.profile.jobs JOB.json``):

- ``stages``: the render timed stage by stage, without a profiler in the process: ``load``
  (the scene file, ``scene``), ``prepare`` (the tracer's per-frame state),
  ``trace`` (``render_into``), ``encode`` (the PNG). A compiled variant (``numba``) splits
  prepare into ``pack`` (the world packed into arrays, its hierarchy built: the frame's
  ``packed.seconds``) and ``compile`` (the rest of prepare: loading the compiled render,
  built first when missing, and the hierarchy builder, plus the threads' scratch), and
  traces a second time to show what the first one cost beyond the work. This process runs
  under py-spy, a sampling profiler outside the process (it reads the interpreter's stack
  ``FLAME_RATE`` times a second, pausing it briefly for each sample; nothing runs inside
  it), which writes the flame graph (an SVG); the render is repeated until
  ``FLAME_SECONDS`` of rendering are sampled, so that a fast variant is not drowned by the
  interpreter's start-up. py-spy rather than pyinstrument (in the process, an HTML page of
  megabytes per profile) or flameprof (unmaintained since 2018): small SVGs, no cost inside
  the process, and it follows ``pooled``'s workers. It needs the right to trace its own
  child, which Linux grants by default; without it the profile has no flame graph and says
  why.
- ``cprofile``: the render (prepare and trace) under cProfile, which counts every call of
  every function (and slows pure Python two to three times, more for small functions): the
  top functions by own and by cumulative time, and the figures the findings are read from
  (``findings``). Not run for a compiled variant: its render is one call into machine code.
  The table is built from the raw entries (``collect``), not pstats' own: pstats keys every
  dataclass's generated ``__init__`` as ``<string>:2 __init__`` and keeps one of them.

A ``pooled`` variant is profiled in its parent process: its workers do the tracing (py-spy
follows them into the flame graph; cProfile sees the parent waiting for them).
"""

from __future__ import annotations

import json
import math
import re
import shutil
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from groundwork.sizes import Size
from harness.engine.budget import scaled
from harness.engine.jobs import child_environment, start_child, wait_child
from raytracer.camera import WHITTED

SECTION = "profile"  # a profile is an entry of the bench's section of that name
DEFAULT_PIXELS = 768  # the default size: the camera scaled to at most this many (32x24 at 4:3)
FLAME_SECONDS = 2.0  # the flame graph samples at least this much rendering
FLAME_RATE = 200  # py-spy's samples per second

Log = Callable[[str], None]


TRACE_SECONDS = 0.5  # a fast variant's default size: a trace of about this long ...
MAX_PIXELS = 2_000_000  # ... but no larger than this


def profile_size(camera: Size, per_pixel: float | None = None) -> Size:
    """The default size of a profile: ``camera`` scaled down to ``DEFAULT_PIXELS`` (a Python
    tracer: about 10 s), or, for a variant that renders a pixel in ``per_pixel`` seconds (a
    probe), to the pixels a trace of ``TRACE_SECONDS`` takes when that is more (a compiled
    or NumPy variant, whose trace at ``DEFAULT_PIXELS`` lasts a millisecond), up to
    ``MAX_PIXELS``, the camera's aspect kept."""
    wanted = DEFAULT_PIXELS
    if per_pixel is not None and per_pixel > 0:
        wanted = max(wanted, min(MAX_PIXELS, round(TRACE_SECONDS / per_pixel)))
    if wanted <= DEFAULT_PIXELS or wanted <= camera.pixels:
        return scaled(camera, (wanted / camera.pixels) ** 0.5)
    common = math.gcd(camera.width, camera.height)
    step_w, step_h = camera.width // common, camera.height // common  # 4x3 for 640x480
    steps = int((wanted / (step_w * step_h)) ** 0.5)
    if steps >= camera.width // step_w:  # a multiple of the reduced ratio: the aspect exact
        return Size(step_w * steps, step_h * steps)
    factor = (wanted / camera.pixels) ** 0.5
    return Size(max(1, round(camera.width * factor)), max(1, round(camera.height * factor)))


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-")


def is_compiled(variant: Any) -> bool:
    """Whether ``variant``'s render is compiled code, where cProfile sees one call: its
    tracer (or, for a wrapper such as ``pooled``, none: the parent is Python) comes from
    ``variants.numba``."""
    tracer = getattr(variant, "tracer", None)
    return type(tracer).__module__.startswith("variants.numba")


# ---------------------------------------------------------------------------- the parent


def py_spy() -> str | None:
    """The py-spy program: beside this Python (a virtual environment's bin), else on PATH."""
    beside = Path(sys.executable).parent / "py-spy"
    return str(beside) if beside.is_file() else shutil.which("py-spy")


@dataclass(frozen=True)
class Request:
    """One profile: ``variant`` (a canonical name), ``scene`` (a scene file) at ``size``;
    samples, depth, seed, integrator, light_sampling: the render's settings; top: functions
    per table; folder: where
    the flame graph (``STEM.svg``), the cProfile statistics (``STEM.pstats``) and the
    picture (``STEM.png``) go; flame: whether to sample the flame graph; threads: CPUs for
    a numba render (None: all); flame_seconds: how much rendering the flame graph samples
    at least (the render is repeated)."""

    variant: str
    scene: Path
    size: Size
    folder: Path
    stem: str
    samples: int = 1
    depth: int = 5
    seed: int = 0
    integrator: str = WHITTED
    light_sampling: bool = True
    top: int = 15
    flame: bool = True
    compiled: bool = False
    threads: int | None = None
    flame_seconds: float = FLAME_SECONDS

    def job(self, kind: str) -> dict[str, Any]:
        return {
            "kind": kind, "variant": self.variant, "scene": str(self.scene),
            "size": [self.size.width, self.size.height], "samples": self.samples,
            "depth": self.depth, "seed": self.seed, "integrator": self.integrator,
            "light_sampling": self.light_sampling, "top": self.top,
            "image": str(self.folder / f"{self.stem}.png"),
            "pstats": str(self.folder / f"{self.stem}.pstats"),
            "flame_seconds": self.flame_seconds if self.flame else 0.0,
        }  # fmt: skip


def _run_child(
    command: list[str], folder: Path, job: Mapping[str, Any], threads: int | None, quiet: bool
) -> tuple[dict[str, Any] | None, str]:
    """Run ``command`` (ending in the job file's path, added here) on ``job`` written into
    ``folder``; (its result.json or None, the last line it printed when ``quiet``)."""
    folder.mkdir(parents=True, exist_ok=True)
    job_path = folder / "job.json"
    job_path.write_text(json.dumps(job))
    log_path = folder / "output.txt"
    with open(log_path, "w") as output:
        sink = output if quiet else None
        process = start_child(
            [*command, str(job_path)], child_environment(threads), stdout=sink, stderr=sink
        )
        wait_child(process)  # an interrupt stops its process group (harness.engine.jobs)
    lines = [ln.strip() for ln in log_path.read_text(errors="replace").splitlines() if ln.strip()]
    last = lines[-1] if lines else f"exit code {process.returncode}"
    result_path = folder / "result.json"
    if not result_path.exists():
        return None, last
    found: dict[str, Any] = json.loads(result_path.read_text())
    return found, last


def profile(request: Request, jobs: Path, log: Log) -> dict[str, Any]:
    """Both runs of ``request`` (the stages under py-spy, then cProfile unless the render
    is compiled), each in a fresh process: an entry of the ``profile`` section."""
    entry: dict[str, Any] = {
        "section": SECTION, "name": request.variant, "status": "ok",
        "scene": request.scene.stem, "size": [request.size.width, request.size.height],
        "samples": request.samples, "pixels": request.size.pixels,
        "compiled": request.compiled,
    }  # fmt: skip
    module = [sys.executable, "-m", "harness.sections.profile.jobs"]
    first_time = (
        " (numba compiles its kernels for this scene's features the first time: a minute)"
        if request.compiled
        else ""
    )
    flame = request.folder / f"{request.stem}.svg"
    spy = py_spy() if request.flame else None
    stages: dict[str, Any] | None = None
    if request.flame and spy is None:
        entry["flame_error"] = "py-spy is not installed (pip install py-spy)"
    if spy is not None:
        spied = "sampled by py-spy for the flame graph"
        log(f"{request.variant}: timing the stages, {spied}{first_time}")
        command = [
            spy, "record", "--rate", str(FLAME_RATE), "--function", "--subprocesses",
            "--format", "flamegraph", "--output", str(flame), "--", *module,
        ]  # fmt: skip
        flame.unlink(missing_ok=True)
        stages, said = _run_child(command, jobs / "stages-spy", request.job("stages"),
                                  request.threads, quiet=True)  # fmt: skip
        if flame.is_file() and flame.stat().st_size > 0:
            entry["flame"] = str(flame)
            entry["flame_rate"] = FLAME_RATE
        else:
            entry["flame_error"] = f"py-spy could not sample the render: {said}"
    if stages is None:  # no py-spy, or it could not run the job
        log(f"{request.variant}: timing the stages{first_time}")
        job = {**request.job("stages"), "flame_seconds": 0.0}
        stages, said = _run_child(module, jobs / "stages", job, request.threads, quiet=False)
    if stages is None or "error" in stages:
        entry.update(status="failed", error=_error(stages, said))
        return entry
    entry.update(stages)
    if request.compiled:
        entry["cprofile_skipped"] = (
            "the render is compiled code: cProfile sees one call into it; the stages above "
            "are the figures"
        )
        return entry
    log(f"{request.variant}: the render under cProfile (two to three times slower)")
    profiled, said = _run_child(
        module, jobs / "cprofile", request.job("cprofile"), request.threads, quiet=False
    )
    if profiled is None or "error" in profiled:
        entry.update(status="failed", error=_error(profiled, said))
        return entry
    entry["cprofile"] = profiled
    entry["pstats"] = request.job("cprofile")["pstats"]
    return entry


def _error(result: Mapping[str, Any] | None, said: str) -> str:
    if result is None:
        return f"the profiling process ended without a result ({said})"
    return str(result["error"])
