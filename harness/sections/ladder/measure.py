"""The optimizations step by step, beside a C++ tracer (issue 29): ``rtc bench --sections
ladder``.

Both seeds told their result as a ladder: the Go write-up as cached inverses, then
preallocation, then a pool, each with the time and allocations it saved; the C++ report as a
table of changes with the MRay/s after each. ``STEPS`` is that ladder for this project, in
the seeds' order: each step names the one it is measured against (``over``) and says what it
changes. Every step is a row of the run file (section ``ladder``), measured as the table's
rows are (``Bench.measure_row``: a fresh process, warm-up, timed renders, allocations and
the picture at the comparison size), and:

- only the steps among the run's variants (``--variants``; all of them by default);
- at the table's size, except the steps whose fixed costs (a compiled kernel's launch, a
  NumPy pass's setup) would hide them there: those at ``LARGE`` or the table's size if
  larger. Factors compare throughput per pixel, so sizes may differ (as the table's do);
- a row the table measured in the same run at the same size is reused, not measured again
  (``reused: table``); its own rows count no rays (the section shows none, and counting
  would compile a second kernel per compiled step);
- its own factor is its throughput over its ``over`` step's; its cumulative factor, over
  naive's; the error it adds is its picture against its ``over`` step's, at the largest size
  both rendered (``error_vs_over``; compiled steps compare at ``LARGE``).

The anchors, in the same run: POV-Ray 3.7 (``harness.instruments.povray``) renders the reference
scene's ``.pov`` version (``scenes/reference.pov``) at ``LARGE`` on one thread and on every
core, the mode's ``side_repeat`` times each (quick: once; its trace alone outlasts the
quick bench's Python rows), timed as a whole process (and by its own trace time); its picture is
compared with the project's at the same size. Without POV-Ray the entry says so (``status:
unavailable``) and the report prints the note instead of the rows. When the run measures
``numba``, its mesh kernel beside Embree on the dragon's stand-in (``harness.sections.ladder.mesh``,
without ``embreex`` one line why).

``harness.sections.ladder.report`` draws the report's opening section from these entries.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.engine import figures
from harness.instruments import imagediff, povray
from harness.instruments.usage import available_cores
from harness.scenery import SCENES
from harness.sections.ladder import mesh
from variants.registry import load_variant

if TYPE_CHECKING:
    import numpy as np

    from harness.engine.bench import Bench

SECTION = "ladder"
LARGE = Size(640, 480)
POV_SCENES = {"reference": SCENES / "reference.pov"}
"""The scenes POV-Ray can render: the bench's scene name -> its ``.pov`` version."""


@dataclass(frozen=True)
class Step:
    """One rung: ``variant`` (the registry's grammar) measured against ``over`` (None: the
    first); ``change``: what it changes, in a line; ``runs_on``: what it needs beyond the
    standard library (``Python``, ``NumPy``, ``numba``); ``large``: measured at ``LARGE``
    at least; ``option``: an option of the step it is over rather than a step of its own."""

    variant: str
    over: str | None
    change: str
    runs_on: str
    large: bool = False
    option: bool = False


STEPS = (
    Step("naive", None, "the book's tracer: immutable values", "Python"),
    Step("cached", "naive", "inverse transforms computed once", "Python"),
    Step("prealloc", "cached", "buffers reused: no objects made per ray", "Python"),
    Step("pooled:prealloc", "prealloc", "rows on worker processes, one per core", "Python"),
    Step("numba", "pooled:prealloc", "compiled kernels, threads over rows", "numba",
         large=True),
    Step("wavefront", "prealloc", "no compiler: rays in passes, as NumPy arrays", "NumPy",
         large=True),
    Step("numba[float32]", "numba", "option: single-precision floats", "numba", large=True,
         option=True),
    Step("numba[fastmath]", "numba", "option: LLVM's fast-math", "numba", large=True,
         option=True),
)  # fmt: skip


def canonical(spelled: str) -> str | None:
    """The registry's canonical name of ``spelled`` (``pooled:prealloc`` ->
    ``pooled[workers=2]:prealloc`` on 2 cores), None where it is not available here."""
    try:
        return load_variant(spelled).name
    except LookupError:
        return None


def _unavailable(spelled: str) -> str:
    try:
        load_variant(spelled)
    except LookupError as error:
        return str(error.args[0] if error.args else error)
    return ""


def names() -> set[str]:
    """The canonical names of the steps available here (their pictures are kept)."""
    return {name for step in STEPS if (name := canonical(step.variant)) is not None}


def step_size(step: Step, table: Size) -> Size:
    """Where ``step`` is measured: the table's size, or ``LARGE`` for a large step when the
    table's is smaller."""
    if step.large and LARGE.pixels > table.pixels:
        return LARGE
    return table


def _key(size: Any) -> str:
    return "x".join(str(v) for v in size)


def before(bench: Bench) -> None:
    """Before any section is measured: keep the pictures of the steps (the table's rows of
    them are reused, their pictures compared), and compile the compiled steps' kernels in the
    background while the Python steps are timed (``Bench.warm``)."""
    bench.keep_pictures |= names()
    steps = [canonical(step.variant) for step in STEPS]
    wanted = [name for name in steps if name is not None and name in bench.settings.variants]
    bench.warm(wanted, rays=False)
    numba = canonical("numba")
    if numba is not None and numba in bench.settings.variants:  # the mesh row will run
        mesh.warm(bench)


def measure(bench: Bench) -> None:
    """The section (see the module): a row per step, then the anchors."""
    s = bench.settings
    spelled_to_name: dict[str, str] = {}
    for step in STEPS:
        name = canonical(step.variant)
        if name is not None and name not in s.variants:
            continue  # not asked for (--variants)
        over = _over(step, spelled_to_name)
        extra = {
            "step": step.variant, "over": over, "change": step.change,
            "runs_on": step.runs_on, "option": step.option,
        }  # fmt: skip
        if name is None:
            why = _unavailable(step.variant)
            bench.log(f"{SECTION}: {step.variant} not available: {why}")
            bench.rows.append({"section": SECTION, "name": step.variant, "scene": s.scene.name,
                               "status": "unavailable", "error": why, **extra})  # fmt: skip
            continue
        spelled_to_name[step.variant] = name
        size = step_size(step, s.size)
        if not _reuse(bench, name, size, extra):
            task = bench.row_task(
                name, size, s.samples, s.repeat, allocations=True, rays=False,
                compare=bench.compare_size,
            )  # fmt: skip
            bench.measure_row(SECTION, name, s.scene, task, extra)
    bench.finish_section(SECTION)
    rows = [r for r in bench.rows if r["section"] == SECTION]
    for row in rows:
        below = next((r for r in rows if r["name"] == row.get("over")), None)
        if row["status"] == "ok" and below is not None and below["status"] == "ok":
            _error_over(bench, row, below)
    bench.series.append(anchor(bench))
    numba = canonical("numba")
    if numba is not None and numba in s.variants:  # the compiled mesh kernel beside Embree
        bench.series.append(mesh.entry(bench, SECTION))


def _over(step: Step, measured: dict[str, str]) -> str | None:
    """The canonical name of the step ``step`` is measured against: its ``over``, or the
    nearest step below that one that this run measures (``--variants`` may leave some out)."""
    by_name = {s.variant: s for s in STEPS}
    spelled = step.over
    while spelled is not None and spelled not in measured:
        spelled = by_name[spelled].over
    return None if spelled is None else measured[spelled]


def _reuse(bench: Bench, name: str, size: Size, extra: dict[str, Any]) -> bool:
    """Copy the table's row of ``name`` into the section when the table measured it in this
    run at ``size`` (with its pictures, and naive's as the section's reference)."""
    found = next(
        (r for r in bench.rows if r["section"] == "table" and r["name"] == name
         and r["status"] == "ok" and r.get("requested_size") == [size.width, size.height]),
        None,
    )  # fmt: skip
    if found is None:
        return False
    bench.log(f"{SECTION}: {name}: the table's row, measured at {_key(found['size'])}")
    row = {**found, "section": SECTION, "reused": "table", **extra}
    bench.rows.append(row)
    pictures = bench.pictures.get(("table", name))
    if pictures is not None:
        bench.pictures[(SECTION, name)] = pictures
    key = _key(found.get("compare_size") or found["size"])
    if ("table", key) in bench.naive_images:
        bench.naive_images[(SECTION, key)] = bench.naive_images[("table", key)]
    return True


def largest_common(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> str | None:
    """The largest size (``WxH``) both sets of pictures hold, or None."""
    common = set(a) & set(b)
    if not common:
        return None
    return max(common, key=lambda key: a[key].shape[0] * a[key].shape[1])


def _error_over(bench: Bench, row: dict[str, Any], over: dict[str, Any]) -> None:
    """``row``'s picture against its ``over`` step's, at the largest size both rendered; a
    heat map of the difference where there is one."""
    mine = bench.pictures.get((SECTION, row["name"]), {})
    theirs = bench.pictures.get((SECTION, over["name"]), {})
    key = largest_common(mine, theirs)
    if key is None:
        return
    error = imagediff.image_error(mine[key], theirs[key])
    row["error_vs_over"] = {**error.as_dict(), "size": key, "against": over["name"]}
    if error.max_abs > imagediff.HEAT_LOW:  # a map that shows something
        heat = imagediff.heat_map(mine[key], theirs[key])
        name = bench.image_name(SECTION, row["name"], "-over-diff")
        row["heatmap_over"] = bench.save_image(heat, name)


# ---------------------------------------------------------------------------- the anchors


def _exact_picture(bench: Bench, size: Size) -> tuple[str, np.ndarray] | None:
    """The project's picture at ``size`` that equals naive's: a step measured there whose
    picture was naive's at the comparison size (the fastest first), else naive's own."""

    key = _key([size.width, size.height])
    candidates = [
        r for r in bench.rows
        if r["section"] == SECTION and r["status"] == "ok" and _key(r["size"]) == key
        and (r["name"] == "naive"
             or (r.get("error_vs_naive") or {}).get("max_abs", 1) <= figures.EXACT)
    ]  # fmt: skip
    for row in sorted(candidates, key=lambda r: figures.median_wall(r)):
        picture = bench.pictures.get((SECTION, row["name"]), {}).get(key)
        if picture is not None:
            return str(row["name"]), picture
    return None


def anchor(bench: Bench) -> dict[str, Any]:
    """POV-Ray's entry (see the module): a point per thread count, its picture against the
    project's, or ``status: unavailable`` and why."""
    s = bench.settings
    entry: dict[str, Any] = {"section": SECTION, "part": "anchor", "name": "POV-Ray",
                             "anchor": "povray", "scene": s.scene.name}  # fmt: skip
    source = POV_SCENES.get(s.scene.name)
    found = povray.find()
    if found is None or source is None:
        why = (
            povray.missing()
            if found is None
            else (
                f"no .pov version of the scene {s.scene.name!r} (POV-Ray renders "
                f"{', '.join(POV_SCENES)})"
            )
        )
        bench.log(f"{SECTION}: POV-Ray not run: {why}")
        entry.update(status="unavailable", error=why, points=[])
        return entry
    entry.update(status="ok", version=found.version, points=[], file=source.name)
    size = LARGE if LARGE.pixels > s.size.pixels else s.size
    cores = s.threads or available_cores()
    picture = None
    for threads in sorted({1, cores}):
        try:
            point, picture = _povray_point(bench, found, source, size, threads)
        except povray.PovrayError as error:
            entry["points"].append({"threads": threads, "error": str(error)})
            continue
        entry["points"].append(point)
    if picture is not None:
        _anchor_picture(bench, entry, source, size, picture)
    return entry


def _povray_point(
    bench: Bench, found: Any, source: Any, size: Size, threads: int
) -> tuple[dict[str, Any], np.ndarray]:
    """``side_repeat`` renders by POV-Ray on ``threads`` threads; timed again (as a busy row is,
    ``Bench.measure_row``) while its trace threads did not get their cores."""
    attempts: list[dict[str, Any]] = []
    best: dict[str, Any] | None = None
    picture = None
    for attempt in range(1 + bench.settings.again):
        if attempt:
            quiet = bench.wait_for_quiet(threads, f"{SECTION}: POV-Ray was busy")
            if quiet is None:
                break
            bench.log(f"{SECTION}: POV-Ray on {threads} thread(s) again: it was busy ({quiet})")
        else:
            bench.log(f"{SECTION}: POV-Ray at {size}, {threads} thread(s)")
        start = bench.clock()
        renders = [
            povray.render(found, source, size, threads, timeout=600)
            for _ in range(bench.settings.mode.side_repeat)
        ]
        if attempt:
            bench.spend(bench.clock() - start)
        picture = renders[0].image if picture is None else picture
        point = _point(renders, threads)
        attempts.append({"wall": point["wall"], "trace": point["trace"], "busy": point_busy(point)})
        if best is None or _trace_share(point) > _trace_share(best):
            best = point
        if not point_busy(best):
            break
    assert best is not None and picture is not None
    bench.log(f"{SECTION}: POV-Ray on {threads} thread(s): {best['wall']:.3f} s at {size}"
              + (" (busy)" if point_busy(best) else ""))  # fmt: skip
    if len(attempts) > 1:
        best["attempts"] = attempts
    return best, picture


def _trace_share(point: dict[str, Any]) -> float:
    trace, cpu = point.get("trace"), point.get("trace_cpu")
    return float(cpu) / float(trace) if trace and cpu is not None else 0.0


def _point(renders: list[Any], threads: int) -> dict[str, Any]:
    """One thread count's renders as a point: medians, and every render's figures."""
    traces = [r.trace for r in renders if r.trace is not None]
    trace_cpu = [r.trace_cpu for r in renders if r.trace_cpu is not None]
    first = renders[0]
    return {
        "size": [first.size.width, first.size.height], "samples": 1, "threads": threads,
        "wall": statistics.median(r.wall for r in renders), "walls": [r.wall for r in renders],
        "cpu": statistics.median(r.cpu for r in renders),
        "trace": statistics.median(traces) if traces else None, "traces": traces,
        "trace_cpu": statistics.median(trace_cpu) if trace_cpu else None,
        "parse": statistics.median(r.parse for r in renders if r.parse is not None)
        if any(r.parse is not None for r in renders) else None,
    }  # fmt: skip


def _anchor_picture(
    bench: Bench, entry: dict[str, Any], source: Any, size: Size, picture: np.ndarray
) -> None:
    """POV-Ray's picture kept, and compared with the project's exact picture at its size (or
    naive's at the comparison size, rendered by POV-Ray there too), both in bytes as their
    PNGs hold them (so that rounding to bytes is no difference)."""
    entry["image"] = bench.save_image(picture, f"{SECTION}-povray.png")
    ours = _exact_picture(bench, size)
    if ours is None:
        compare = bench.compare_size
        reference = bench.naive_images.get((SECTION, _key([compare.width, compare.height])))
        found = povray.find()
        if reference is None or found is None:
            return
        try:
            picture = povray.render(found, source, compare, 1, timeout=600).image
        except povray.PovrayError:
            return
        ours = ("naive", reference)
        size = compare
    name, exact = ours
    reference = imagediff.to_rgb8(exact) / 255.0  # as our PNG has it: POV-Ray writes bytes too
    error = imagediff.image_error(picture, reference)
    entry["difference"] = {**error.as_dict(), "size": str(size), "against": name}
    heat = imagediff.heat_map(picture, reference)
    entry["heatmap"] = bench.save_image(heat, f"{SECTION}-povray-diff.png")
    entry["where"] = imagediff.where_different(picture, reference)


def point_busy(point: Mapping[str, Any]) -> bool:
    """Whether POV-Ray's trace threads got under ``figures.BUSY_SHARE`` of the cores they
    asked for (its own CPU seconds over its own trace time)."""
    trace, cpu = point.get("trace"), point.get("trace_cpu")
    if not trace or cpu is None:
        return False
    return float(cpu) / float(trace) < figures.BUSY_SHARE * int(point["threads"])
