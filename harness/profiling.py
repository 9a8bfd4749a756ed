"""Where the time goes (issue 18, item 5): ``rtc profile`` and ``rtc bench --sections profile``.

One render of a scene (chapter 7's camera and world, from a scene file) through a variant,
taken apart two ways, each in a fresh process (``python -m harness.profiling JOB.json``):

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

import cProfile
import json
import marshal
import os
import pstats
import re
import shutil
import sys
import sysconfig
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.budget import scaled
from harness.figures import seconds_text

if TYPE_CHECKING:
    from harness.bench import Bench

SECTION = "profile"
BENCH_VARIANTS = ("naive", "cached", "prealloc", "numba")
DEFAULT_PIXELS = 768  # the default size: the camera scaled to at most this many (32x24 at 4:3)
FLAME_SECONDS = 2.0  # the flame graph samples at least this much rendering
FLAME_RATE = 200  # py-spy's samples per second
REPORT_TOP = 8  # functions per variant in the report
CONSTRUCTORS = ("__init__", "__new__", "__post_init__")
ROOT = Path(__file__).resolve().parent.parent  # the project: labels are relative to it
STDLIB = Path(sysconfig.get_paths()["stdlib"]).resolve()

Log = Callable[[str], None]
Row = dict[str, Any]


def profile_size(camera: Size) -> Size:
    """The default size of a profile: ``camera`` scaled down to ``DEFAULT_PIXELS``."""
    return scaled(camera, (DEFAULT_PIXELS / camera.pixels) ** 0.5)


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-")


def is_compiled(variant: Any) -> bool:
    """Whether ``variant``'s render is compiled code, where cProfile sees one call: its
    tracer (or, for a wrapper such as ``pooled``, none: the parent is Python) comes from
    ``variants.numba``."""
    tracer = getattr(variant, "tracer", None)
    return type(tracer).__module__.startswith("variants.numba")


# ---------------------------------------------------------------------------- labels


def short_file(filename: str) -> str:
    """``filename`` relative to the project, the standard library or site-packages."""
    if filename in ("~", "") or filename.startswith("<"):
        return filename
    path = Path(filename)
    for base in (ROOT, STDLIB):
        try:
            return path.resolve().relative_to(base).as_posix()
        except ValueError:
            continue
    parts = path.parts
    if "site-packages" in parts:
        return "/".join(parts[parts.index("site-packages") + 1 :])
    return filename


def label(func: tuple[str, int, str]) -> str:
    """pstats' key ``(file, line, name)`` as ``file:line name`` (a built-in: its name)."""
    filename, line, name = func
    if filename == "~":
        return name
    return f"{short_file(filename)}:{line} {name}"


# ---------------------------------------------------------------------------- figures


Key = tuple[str, int, str]  # pstats' key of a function: (file, first line, name)


def _code_name(code: Any) -> str:
    """A code object's qualified name; for code that ``dataclasses`` generates (file
    ``<string>``, every class's ``__init__`` on line 2), its function's ``__qualname__``
    (``Tuple.__init__``), found among the code's referrers."""
    if code.co_filename == "<string>":
        import gc
        import types

        for referrer in gc.get_referrers(code):
            if isinstance(referrer, types.FunctionType):
                return str(referrer.__qualname__)
    return str(getattr(code, "co_qualname", code.co_name))


def collect(profile: cProfile.Profile) -> dict[Key, tuple[Any, ...]]:
    """The profile as pstats' table ``{key: (cc, nc, tt, ct, callers)}`` (as
    ``Profile.snapshot_stats`` builds it), but keyed by qualified names: pstats keys a
    function by (file, line, name), under which every dataclass's generated ``__init__``
    is the same ``<string>:2 __init__``, and keeps one of them: the others' calls and time
    vanish from its figures. Functions with one key are added up."""
    entries = profile.getstats()
    keys: dict[int, Key] = {}
    for entry in entries:
        code = entry.code
        keys[id(code)] = (
            ("~", 0, code)
            if isinstance(code, str)
            else (code.co_filename, code.co_firstlineno, _code_name(code))
        )
    table: dict[Key, list[Any]] = {}
    for entry in entries:
        key = keys[id(entry.code)]
        nc, cc = entry.callcount, entry.callcount - entry.reccallcount
        row = table.setdefault(key, [0, 0, 0.0, 0.0, {}])
        row[0] += cc
        row[1] += nc
        row[2] += entry.inlinetime
        row[3] += entry.totaltime
    for entry in entries:
        caller = keys[id(entry.code)]
        for sub in entry.calls or ():
            callee = keys.get(id(sub.code))
            if callee is None:
                continue
            edges = table[callee][4]
            nc, cc = sub.callcount, sub.callcount - sub.reccallcount
            before = edges.get(caller, (0, 0, 0.0, 0.0))  # (nc, cc, tt, ct), as pstats has it
            edges[caller] = (
                before[0] + nc, before[1] + cc, before[2] + sub.inlinetime,
                before[3] + sub.totaltime,
            )  # fmt: skip
    return {key: tuple(row) for key, row in table.items()}


def _calls(nc: int, cc: int) -> str:
    """Calls as pstats prints them: ``total/primitive`` when some were recursive."""
    return str(nc) if nc == cc else f"{nc}/{cc}"


def _row(func: tuple[str, int, str], figures: tuple[Any, ...]) -> Row:
    cc, nc, tt, ct = figures[:4]
    return {"function": label(func), "calls": _calls(nc, cc), "own": tt, "cum": ct}


def _constructor_seconds(stats: Mapping[Any, Any]) -> float:
    """Own time in ``__init__``/``__new__``/``__post_init__`` plus what the built-ins they
    call directly (``object.__setattr__`` of a frozen dataclass ...) spent on their behalf."""

    def constructor(key: Key) -> bool:
        return key[0] != "~" and key[2].rsplit(".", 1)[-1] in CONSTRUCTORS

    total = 0.0
    for func, (_, _, tt, _, callers) in stats.items():
        if constructor(func):
            total += tt
        elif func[0] == "~":
            total += sum(edge[2] for caller, edge in callers.items() if constructor(caller))
    return total


def _hot_chain(stats: Mapping[Any, Any]) -> tuple[str, float] | None:
    """From the function with the most own time (a built-in: from its heaviest caller), up
    through its heaviest caller while that caller is in the same file: the function at the
    top of that chain and its cumulative seconds (what it and its callees cost)."""
    if not stats:
        return None
    current = max(stats, key=lambda f: stats[f][2])
    if current[0] == "~":
        callers = stats[current][4]
        known = [c for c in callers if c in stats]
        if not known:
            return label(current), float(stats[current][3])
        current = max(known, key=lambda c: callers[c][3])
    seen = {current}
    while True:
        callers = stats[current][4]
        same_file = [c for c in callers if c[0] == current[0] and c not in seen and c in stats]
        if not same_file:
            break
        heaviest = max(same_file, key=lambda c: callers[c][3])
        seen.add(heaviest)
        current = heaviest
    return label(current), float(stats[current][3])


def summarize(table: Mapping[Key, tuple[Any, ...]], top: int) -> dict[str, Any]:
    """What a cProfile run shows (``collect``'s table): totals, the ``top`` functions by
    own and by cumulative time, and the figures ``findings`` reads (the hot chain, the
    constructors, how spread the time is)."""
    total = float(sum(row[2] for row in table.values()))
    by_own = sorted(table.items(), key=lambda item: item[1][2], reverse=True)
    by_cum = sorted(table.items(), key=lambda item: item[1][3], reverse=True)
    covered, half = 0.0, 0
    for _, figures in by_own:
        if covered >= total / 2:
            break
        covered += figures[2]
        half += 1
    hot = _hot_chain(table)
    return {
        "total": total,
        "calls": int(sum(row[1] for row in table.values())),
        "functions": len(table),
        "top_own": [_row(f, v) for f, v in by_own[:top]],
        "top_cum": [_row(f, v) for f, v in by_cum[:top]],
        "hot": None if hot is None else {"function": hot[0], "cum": hot[1]},
        "constructors": _constructor_seconds(table),
        "half": half,
    }


def _share(part: float, whole: float) -> str:
    return f"{100 * part / whole:.0f}%" if whole > 0 else "-"


def _function_name(text: str) -> str:
    """``raytracer/matrices.py:139 inverse`` -> ```inverse()` (raytracer/matrices.py)``."""
    where, _, name = text.partition(" ")
    if not name:
        return f"`{text}`"
    file = where.rsplit(":", 1)[0]
    return f"`{name}()` ({'written by dataclasses' if file == '<string>' else file})"


STAGE_NAMES = {
    "load": "load (scene file)",
    "prepare": "prepare",
    "pack": "pack (world to arrays, hierarchy)",
    "compile": "compile or cache load",
    "trace": "trace (render_into)",
    "render": "render (the API's render)",
    "encode": "encode (PNG)",
}


def findings(entry: Mapping[str, Any]) -> str:
    """One sentence read off a profile's figures: for a profiled render, where its time
    went (the hot chain, constructors, how spread the time is, calls per pixel); for a
    compiled one, its stages."""
    name = entry.get("name", "?")
    profile = entry.get("cprofile")
    if profile and profile.get("total"):
        total = profile["total"]
        parts: list[str] = []
        hot = profile.get("hot")
        if hot:
            parts.append(
                f"{_share(hot['cum'], total)} of the render in {_function_name(hot['function'])} "
                "and its callees"
            )
        top_own = profile.get("top_own") or []
        if top_own:
            first = top_own[0]
            parts.append(
                f"the top function by own time, `{first['function']}`, holds "
                f"{_share(first['own'], total)}, and {profile['half']} of "
                f"{profile['functions']} functions make{'s' if profile['half'] == 1 else ''} up "
                "half of it"
            )
        built = _share(profile["constructors"], total)
        parts.append(f"{built} building objects (`__init__`, `__new__`)")
        pixels = entry.get("pixels") or 0
        if pixels:
            parts.append(f"{profile['calls'] / pixels:,.0f} function calls per pixel")
        return f"{name}: " + "; ".join(parts) + "."
    stages = entry.get("stages")
    if stages:
        wall = entry.get("wall") or sum(stages.values())
        order = sorted(stages.items(), key=lambda item: item[1], reverse=True)
        spelled = ", ".join(f"{STAGE_NAMES.get(k, k)} {_share(v, wall)}" for k, v in order)
        text = f"{name}: of {seconds_text(wall)}, {spelled}"
        if "trace_again" in entry and "trace" in stages:
            text += f"; a second trace took {seconds_text(entry['trace_again'])}"
        if entry.get("kernels"):
            text += f"; compiled code {entry['kernels']}"
        return text + "."
    return f"{name}: no figures ({entry.get('error', 'not measured')})."


# ---------------------------------------------------------------------------- the jobs


def _load(job: Mapping[str, Any], variant: Any) -> Any:
    from harness.make_meshes import provide
    from scene import load_scene

    scene = load_scene(job["scene"], variant.api, variant=variant.name, provide_mesh=provide)
    return scene.resized(*job["size"])


def _settings(job: Mapping[str, Any]) -> Any:
    from raytracer.camera import RenderSettings

    return RenderSettings(depth=job["depth"], samples=job["samples"], seed=job["seed"])


def _kernel_files() -> set[str]:
    from variants.numba.specialize import kernel_folder

    return {p.name for p in kernel_folder().glob("*.so")}


def stages_job(job: Mapping[str, Any]) -> dict[str, Any]:
    """The render timed stage by stage (see the module), then repeated (untimed) until the
    flame graph has ``flame_seconds`` of rendering to sample."""
    from groundwork.images import write_image
    from variants.registry import load_variant

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
            from variants.numba.specialize import load_bvh_builder

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
    renders = 1
    while spent < float(job.get("flame_seconds") or 0.0):
        clock = time.perf_counter()
        if tracer is None:
            variant.api["render"](c, w, settings)
        else:
            tracer.forget()
            tracer.render_into(tracer.new_canvas(c), c, w, settings)
        spent += lap()
        renders += 1
    if tracer is not None:
        tracer.forget()
    result["renders"] = renders
    return result


def cprofile_job(job: Mapping[str, Any]) -> dict[str, Any]:
    """The render (prepare and trace) under cProfile: ``summarize``'s figures, and the raw
    statistics written to ``job["pstats"]`` when given."""
    from variants.registry import load_variant

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


def _watch_parent() -> None:
    """Exit when the parent dies (an interrupted ``rtc profile`` or bench leaves no render
    running); ``harness.child``'s, without that module's imports, which the flame graph
    would show as start-up."""
    import threading

    parent = os.getppid()

    def watch() -> None:
        while True:
            time.sleep(0.5)
            if os.getppid() != parent:
                os._exit(3)

    threading.Thread(target=watch, daemon=True, name="watch-parent").start()


def measure(bench: Bench) -> None:
    """The section in a bench run (``harness.bench.Bench``): ``plan_for`` its settings, its
    entries into the run's series, the flame graphs into the run's folder."""
    plan = plan_for(bench.settings)
    staging, stem = bench.writer.staging, bench.writer.stem
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, staging, stem))


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.profiling JOB.json``: a stages or a cProfile job."""
    from harness.jobs import job_main

    def run(job: dict[str, Any], _: Path) -> dict[str, Any]:
        return stages_job(job) if job["kind"] == "stages" else cprofile_job(job)

    return job_main(run, sys.argv[1:] if argv is None else argv)


# ---------------------------------------------------------------------------- the parent


def py_spy() -> str | None:
    """The py-spy program: beside this Python (a virtual environment's bin), else on PATH."""
    beside = Path(sys.executable).parent / "py-spy"
    return str(beside) if beside.is_file() else shutil.which("py-spy")


@dataclass(frozen=True)
class Request:
    """One profile: ``variant`` (a canonical name), ``scene`` (a scene file) at ``size``;
    samples, depth, seed: the render's settings; top: functions per table; folder: where
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
    top: int = 15
    flame: bool = True
    compiled: bool = False
    threads: int | None = None
    flame_seconds: float = FLAME_SECONDS

    def job(self, kind: str) -> dict[str, Any]:
        return {
            "kind": kind, "variant": self.variant, "scene": str(self.scene),
            "size": [self.size.width, self.size.height], "samples": self.samples,
            "depth": self.depth, "seed": self.seed, "top": self.top,
            "image": str(self.folder / f"{self.stem}.png"),
            "pstats": str(self.folder / f"{self.stem}.pstats"),
            "flame_seconds": self.flame_seconds if self.flame else 0.0,
        }  # fmt: skip


def _run_child(
    command: list[str], folder: Path, job: Mapping[str, Any], threads: int | None, quiet: bool
) -> tuple[dict[str, Any] | None, str]:
    """Run ``command`` (ending in the job file's path, added here) on ``job`` written into
    ``folder``; (its result.json or None, the last line it printed when ``quiet``)."""
    from harness.jobs import child_environment, start_child, wait_child

    folder.mkdir(parents=True, exist_ok=True)
    job_path = folder / "job.json"
    job_path.write_text(json.dumps(job))
    log_path = folder / "output.txt"
    with open(log_path, "w") as output:
        sink = output if quiet else None
        process = start_child(
            [*command, str(job_path)], child_environment(threads), stdout=sink, stderr=sink
        )
        wait_child(process)  # an interrupt stops its process group (harness.jobs)
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
    module = [sys.executable, "-m", "harness.profiling"]
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


# ---------------------------------------------------------------------------- the bench


@dataclass(frozen=True)
class Plan:
    """The bench section: ``variants`` on ``scene`` at ``size`` (see ``profile_size``)."""

    scene: Path
    size: Size
    variants: tuple[str, ...] = BENCH_VARIANTS
    samples: int = 1
    depth: int = 5
    seed: int = 0
    threads: int | None = None


def plan_for(settings: Any) -> Plan:
    """The section's plan in a bench run (``harness.plan.BenchSettings``): its scene (the
    reference scene when the run's has no file), scaled to ``DEFAULT_PIXELS``, one sample
    per pixel, the run's depth, seed and threads."""
    from harness.presets import PRESETS

    scene = settings.scene.path
    if scene is None:
        scene = PRESETS["reference"].path
    return Plan(
        scene=Path(scene), size=profile_size(settings.size), depth=settings.depth,
        seed=settings.seed, threads=settings.threads,
    )  # fmt: skip


def run(plan: Plan, jobs: Path, log: Log, images: Path, stem: str) -> list[dict[str, Any]]:
    """The ``profile`` section: one entry per variant of ``plan``; the flame graphs go into
    ``images`` (the run's folder), named in the entry as ``STEM/profile-VARIANT.svg``."""
    from variants.registry import load_variant

    entries: list[dict[str, Any]] = []
    for name in plan.variants:
        try:
            variant = load_variant(name)
        except LookupError as error:
            reason = str(error.args[0] if error.args else error)
            log(f"{SECTION}: {name} not run: {reason}")
            entries.append({"section": SECTION, "name": name, "status": "unavailable",
                            "error": reason})  # fmt: skip
            continue
        work = jobs / slug(variant.name) / "out"
        work.mkdir(parents=True, exist_ok=True)
        request = Request(
            variant=variant.name, scene=plan.scene, size=plan.size, folder=work,
            stem=f"{SECTION}-{slug(variant.name)}", samples=plan.samples, depth=plan.depth,
            seed=plan.seed, top=REPORT_TOP * 2, compiled=is_compiled(variant),
            threads=plan.threads,
        )  # fmt: skip
        entry = profile(request, work.parent, lambda m: log(f"{SECTION}: {m}"))
        for key in ("image", "pstats"):
            entry.pop(key, None)
        flame = entry.pop("flame", None)
        if flame:
            target = images / Path(flame).name
            shutil.move(flame, target)
            entry["flame"] = f"{stem}/{target.name}"
        entry["finding"] = findings(entry)
        log(entry["finding"])
        entries.append(entry)
    return entries


if __name__ == "__main__":
    sys.exit(main())
