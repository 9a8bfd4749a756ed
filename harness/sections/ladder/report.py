"""The report's opening section, "Step by step" (``harness.sections.ladder.measure``'s rows and
anchor of a run): the optimizations in the seeds' order, each with what it changes, its own factor
over the step it builds on, the cumulative factor over naive, the error it adds and its allocations;
POV-Ray beside them when the run had it; one sentence of advice computed from the rows, in bold
under the ladder; the Go write-up's published figures as a citation; and lines for the terminal."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from harness.document import summary
from harness.document.model import Block, Bullets, Gallery, Heading, Para, Picture, Table
from harness.document.runinfo import part
from harness.engine import figures
from harness.sections.ladder import mesh
from harness.sections.ladder.measure import SECTION, point_busy

REPORT_DIR = "report"  # harness.report.build's: the plots' folder in the results
HEAT_SCALE_PNG = "heat-scale.png"  # ... and the heat maps' colour bar in it

Run = Mapping[str, Any]
Row = Mapping[str, Any]


# ------------------------------------------------------------------ the Go write-up, cited


@dataclass(frozen=True)
class Cited:
    """A published figure: a step of someone else's ladder and the time its author gave."""

    step: str
    seconds: float


GO_SOURCE = "github.com/eriklupander/rt"
GO_MACHINE = "its author's 4-core/8-thread machine"
GO_STEPS = (
    Cited("naive, single-threaded", 195.0),
    Cited("8 workers", 90.0),
    Cited("cached inverse", 4.5),
    Cited("preallocation", 1.9),
    Cited("arrays instead of slices", 1.1),
    Cited("pointers", 0.8),
    Cited("AVX2 assembly", 0.6),
)
"""The Go ray tracer's published times for the reference scene at 640x480 (Erik Lupander's
write-up of ``github.com/eriklupander/rt``), each step on top of the ones before. Quoted, not
measured: another language, another machine."""


def go_blocks() -> list[Block]:
    """The Go write-up's ladder as published, with the factors its own times give."""
    body = []
    first = GO_STEPS[0].seconds
    for before, step in zip((None, *GO_STEPS), GO_STEPS, strict=False):
        own = "-" if before is None else figures.speedup_text(before.seconds / step.seconds)
        body.append([
            step.step, _seconds(step.seconds), own, figures.speedup_text(first / step.seconds),
        ])  # fmt: skip
    return [
        Para(
            f"**Cited, not measured here:** the Go ray tracer of the reference scene "
            f"({GO_SOURCE}, Erik Lupander's optimization write-up), 640x480, on {GO_MACHINE}, "
            "as its author published it; each step on top of the ones before. Its factors "
            "are its own times' ratios: another language on another machine, so only the "
            "shape of its ladder compares with ours."
        ),
        Table(["Go step", "published time", "its own factor", "over its naive"], body, {1, 2, 3}),
    ]


def _seconds(value: float) -> str:
    minutes, seconds = divmod(value, 60)
    return f"{minutes:.0f} min {seconds:.0f} s" if minutes else f"{seconds:g} s"


# ------------------------------------------------------------------ the run's entries


def rows(run: Run) -> list[Row]:
    """The section's rows of ``run``, in the ladder's order."""
    return [r for r in run.get("rows", []) if r["section"] == SECTION]


def anchor(run: Run) -> Mapping[str, Any] | None:
    """The run's C++ anchor entry (POV-Ray), if it has one."""
    return next(iter(part(run, SECTION, "anchor")), None)


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured this section, if any."""
    return next((run for run in reversed(runs) if rows(run)), None)


def _ok(row: Row) -> bool:
    return row.get("status") == "ok" and bool(row.get("wall"))


def per_pixel(row: Row) -> float:
    return figures.median_wall(row) / figures.pixels(row)


def own_factor(row: Row, found: Sequence[Row]) -> float | None:
    """``row``'s throughput over the step it builds on (None for the first, or when that
    step did not measure)."""
    over = next((r for r in found if r["name"] == row.get("over") and _ok(r)), None)
    if over is None or not _ok(row):
        return None
    return per_pixel(over) / per_pixel(row)


def cumulative(row: Row, found: Sequence[Row]) -> float | None:
    """``row``'s throughput over naive's."""
    naive = next((r for r in found if r["name"] == "naive" and _ok(r)), None)
    if naive is None or not _ok(row):
        return None
    return per_pixel(naive) / per_pixel(row)


def adds_exactly_nothing(row: Row) -> bool:
    """Whether ``row``'s picture is the step before's (within ``figures.EXACT``), or it is the
    first."""
    error = row.get("error_vs_over")
    if row.get("over") is None:
        return True
    return error is not None and error["max_abs"] <= figures.EXACT


def exact(row: Row, found: Sequence[Row]) -> bool:
    """Whether ``row``'s picture is naive's: every step from naive to it adds nothing."""
    by_name = {r["name"]: r for r in found}
    seen: set[str] = set()
    current: Row | None = row
    while current is not None and current["name"] not in seen:
        if not adds_exactly_nothing(current):
            return False
        seen.add(current["name"])
        over = current.get("over")
        if over is None:
            return True
        current = by_name.get(over)
    return False


def _error_cell(row: Row) -> str:
    if row.get("over") is None:
        return "(the reference)"
    error = row.get("error_vs_over")
    if not error:
        return "-"
    size = error["size"]
    if error["max_abs"] == 0:
        return f"identical ({size})"
    if error["max_abs"] <= figures.EXACT:
        return f"within {error['max_abs']:.0e} ({size})"
    off = error["pixels_over_one_step"]
    return f"PSNR {summary.psnr_text(error)}, {off:,} px off ({size})"


def spelled(name: str | None, found: Sequence[Row]) -> str | None:
    """A step as the ladder spells it (``pooled:prealloc``), from its canonical name."""
    row = next((r for r in found if r["name"] == name), None)
    return name if row is None else str(row.get("step") or name)


FIXED_SHARE = 0.25  # a row whose fixed costs are this share of its render or more is marked


def fixed_share(row: Row) -> float:
    """The share of the row's median render that its probes put down to fixed costs (a
    pool's start-up, a kernel's launch): their estimate of a render of no pixels."""
    fixed = (row.get("probe") or {}).get("fixed") or 0.0
    return min(1.0, float(fixed) / figures.median_wall(row))


def _time_cell(row: Row) -> str:
    text = f"{figures.per_pixel_text(per_pixel(row))} ({'x'.join(map(str, row['size']))})"
    if fixed_share(row) >= FIXED_SHARE:
        text += " †"
    if figures.is_busy(row):
        text += " **busy**"
    return summary._keep(text)


def _factor(value: float | None, over: str | None = None) -> str:
    if value is None:
        return "-"
    text = figures.speedup_text(value)
    return f"{text} (`{over}`)" if over else text


def short_version(found: Mapping[str, Any]) -> str:
    """``POV-Ray 3.7`` from the version line ``POV-Ray 3.7.0.10.unofficial``."""
    words = str(found.get("version") or "POV-Ray").split()
    if len(words) >= 2:
        return f"{words[0]} {'.'.join(words[1].split('.')[:2])}"
    return words[0]


def table_point(found: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The anchor's point the ladder shows: POV-Ray on the most threads it measured (as
    the compiled steps use every core); the others are in the notes and the plot."""
    points = [p for p in found.get("points", []) if "error" not in p and p.get("wall")]
    return max(points, key=lambda p: int(p["threads"]), default=None)


def povray_fixed_share(point: Mapping[str, Any]) -> float:
    """The share of POV-Ray's whole process that is not tracing (start-up, parsing, writing
    the picture): its fixed costs."""
    trace = point.get("trace")
    if not trace or not point.get("wall"):
        return 0.0
    return max(0.0, 1.0 - float(trace) / float(point["wall"]))


def _povray_time(point: Mapping[str, Any]) -> str:
    w, h = point["size"]
    text = f"{figures.per_pixel_text(point['wall'] / (w * h))} ({w}x{h}"
    if point.get("trace"):
        text += f"; trace {figures.per_pixel_text(point['trace'] / (w * h))}"
    text += ")"
    if povray_fixed_share(point) >= FIXED_SHARE:
        text += " †"
    if point_busy(point):
        text += " **busy**"
    return text


def _anchor_rows(found: Mapping[str, Any] | None, naive: Row | None) -> list[list[str]]:
    if found is None or found.get("status") != "ok":
        return []
    point = table_point(found)
    if point is None:
        return []
    difference = found.get("difference")
    picture = "-"
    if difference:
        picture = (
            f"PSNR {summary.psnr_text(difference)} vs `{difference['against']}` "
            f"({difference['size']})"
        )
    w, h = point["size"]
    over = (
        "-" if naive is None else figures.speedup_text(per_pixel(naive) / (point["wall"] / (w * h)))
    )
    threads = int(point["threads"])
    return [[
        f"{short_version(found)}, {threads} thread{'s' if threads > 1 else ''}",
        "C++: the scene as a `.pov` file, whole process", summary._keep(_povray_time(point)),
        "-", over, picture, "-",
    ]]  # fmt: skip


HEADER = [
    "step",
    "what it changes",
    "time per pixel (measured at)",
    "its own factor (over)",
    "over naive",
    "error it adds (vs the step before)",
    "allocs per pixel",
]


def table(run: Run) -> Table:
    found = rows(run)
    naive = next((r for r in found if r["name"] == "naive" and _ok(r)), None)
    body = []
    for row in found:
        name = f"`{row['name']}`"
        if row["status"] == "unavailable":
            continue
        if not _ok(row):
            body.append([name, str(row.get("change", "")), "failed: " +
                         str(row.get("error", ""))[:120], "-", "-", "-", "-"])  # fmt: skip
            continue
        body.append([
            f"`{spelled(row['name'], found)}`", str(row.get("change", "")), _time_cell(row),
            _factor(own_factor(row, found), spelled(row.get("over"), found)),
            _factor(cumulative(row, found)), _error_cell(row), summary.allocations_text(row),
        ])  # fmt: skip
    body += _anchor_rows(anchor(run), naive)
    return Table(HEADER, body, right={2, 3, 4, 6}, compact=True)


# ------------------------------------------------------------------ the advice


def _best(candidates: Sequence[Row], found: Sequence[Row]) -> Row | None:
    ranked = [r for r in candidates if cumulative(r, found) is not None]
    return max(ranked, key=lambda r: cumulative(r, found) or 0.0, default=None)


def advice(run: Run) -> str:
    """One sentence from the run's rows: the fastest step whose picture is naive's (for the
    book's scenes), the fastest exact one that needs no compiler (plain Python or NumPy),
    the pure-Python step that buys the most on its own (to learn from), and what the
    options buy."""
    found = [r for r in rows(run) if _ok(r)]
    exact_rows = [r for r in found if exact(r, found) and r["name"] != "naive"]
    use = _best(exact_rows, found)
    if use is None:
        return ""
    name = spelled(use["name"], found)
    parts = [
        f"use `{name}` for the book's scenes "
        f"({figures.speedup_text(cumulative(use, found) or 0)} naive's speed, the same picture)"
    ]
    plain = _best([r for r in exact_rows if r.get("runs_on") in ("Python", "NumPy")], found)
    if plain is not None and plain is not use:
        parts.append(
            f"without a compiler, `{spelled(plain['name'], found)}` "
            f"({figures.speedup_text(cumulative(plain, found) or 0)}, {plain.get('runs_on')} "
            "only)"
        )
    python = [r for r in exact_rows if r.get("runs_on") == "Python"]
    learn = max(python, key=lambda r: own_factor(r, found) or 0.0, default=None)
    if learn is not None and own_factor(learn, found):
        parts.append(
            f"to learn from, `{spelled(learn['name'], found)}`: one change, "
            f"{figures.speedup_text(own_factor(learn, found) or 0)} over "
            f"`{spelled(learn['over'], found)}` in plain Python"
        )
    options = [r for r in found if r.get("option") and own_factor(r, found) is not None]
    if options:
        speeds = " and ".join(
            f"`{spelled(r['name'], found)}` {figures.speedup_text(own_factor(r, found) or 0)} "
            f"`{spelled(r['over'], found)}`'s speed"
            for r in options
        )
        parts.append(f"the options run at {speeds}, with the error shown")
    return f"**Advice from this run: {'; '.join(parts)}.**"


# ------------------------------------------------------------------ blocks


def where_measured(run: Run) -> str:
    m = run["machine"]
    return f"{m['cpu_model']}, {m['cores_available']} cores, {run['started'][:10]}" + (
        " (**shared machine**)" if run.get("shared") else ""
    )


PLOT_ALT = "the ladder: time per pixel of each step (log scale)"


def blocks(run: Run, plot: str | None, context: str = "", runs: Sequence[Run] = ()) -> list[Block]:
    """The section: one lead line, the ladder (steps, then the anchors), the advice, the
    plot (alt text ``PLOT_ALT``), then the notes (``context``, the line naming the machine
    and the run, among them)."""
    found = rows(run)
    out: list[Block] = [
        Heading(2, "Step by step"),
        Para(
            "Each optimization in the order the Go and C++ write-ups took them, on the "
            f"reference scene; {where_measured(run)}."
        ),
        table(run),
    ]
    text = advice(run)
    if text:
        out.append(Para(text))
    if plot is not None:
        out.append(Picture(plot, PLOT_ALT))
    out += notes(run, found, context)
    return out


def mesh_anchor(run: Run) -> Mapping[str, Any] | None:
    """The run's mesh kernel beside Embree (``harness.sections.ladder.mesh``), if measured."""
    return next(iter(part(run, SECTION, mesh.PART)), None)


def mesh_text(found: Mapping[str, Any]) -> str:
    """The mesh row beside Embree in a sentence, or why there is none."""
    if found.get("status") != "ok":
        return f"**No Embree beside the mesh kernel in this run:** {found.get('error')}."
    ours, theirs, ratios = found["ours_median"], found["embree_median"], found["ratios"]
    w, h = found["size"]
    return (
        f"**The mesh kernel beside Embree:** `{found['variant']}` renders the bonus chapter's "
        f"dragon (its stand-in `{found['mesh']}`, {found['triangles']:,} triangles) at {w}x{h}, "
        f"primary rays only (no light), in {figures.seconds_text(ours)} CPU; "
        f"{found['version']} intersects the same {found['rays']:,} rays "
        f"({found['hits']:,} hit) in {figures.seconds_text(theirs)}: **{ours / theirs:.2f}x** "
        f"its time (pairs measured in turns in one process: {ratios[0]:.2f}-{ratios[-1]:.2f}x)."
        + _mesh_steps(found.get("steps", []), theirs)
    )


def _mesh_steps(steps: list[Mapping[str, Any]], theirs: float) -> str:
    """The mesh kernel's steps (``mesh.STEPS``) in a sentence: each variant's time and its
    factor over Embree's, measured in the same turns."""
    if not steps:
        return ""
    told = dict(mesh.STEPS)
    parts = [
        f"`{step['variant']}` ({told.get(step['variant'], 'a step')}) "
        f"{figures.seconds_text(step['median'])}, {step['median'] / theirs:.2f}x"
        for step in steps
    ]
    return " In the same turns: " + "; ".join(parts) + "."


def _anchor_notes(run: Run) -> list[Block]:
    found = anchor(run)
    if found is None:
        return []
    if found.get("status") != "ok":
        return [Para(f"**No C++ anchor in this run:** {found.get('error', 'not run')}.")]
    out: list[Block] = []
    points = [p for p in found.get("points", []) if "error" not in p and p.get("wall")]
    timed = "; ".join(
        f"on {p['threads']} thread{'s' if int(p['threads']) > 1 else ''} "
        f"{_povray_time(p)}, {figures.seconds_text(p['wall'])} a render"
        for p in points
    )
    failed = [f"on {p['threads']} thread(s): {p['error']}" for p in found.get("points", [])
              if "error" in p]  # fmt: skip
    out.append(
        Para(
            f"{found.get('version', 'POV-Ray')} (C++) renders `{found.get('file')}`, the "
            f"reference scene written for it, timed as a whole process (start, parse, trace, "
            f"write the PNG, exit) and by its own trace time: {timed or 'no render'}."
            + (f" Failed: {'; '.join(failed)}." if failed else "")
        )
    )
    difference, where = found.get("difference"), found.get("where")
    if difference and where:
        box = where.get("box")
        place = (
            f"; the middle 90% of them lie within x {box[0]}-{box[2]}, y {box[1]}-{box[3]}"
            if box
            else ""
        )
        out.append(
            Para(
                f"POV-Ray's picture against `{difference['against']}`'s at {difference['size']}, "
                "both as 8-bit PNGs: "
                f"PSNR {summary.psnr_text(difference)}, {where['pixels_off']:,} of "
                f"{where['pixels']:,} pixels off by more than 1/255{place}. The `.pov` file "
                f"(`scenes/{found.get('file', 'reference.pov')}`) names where the two "
                "models differ: the glass sphere's own colour and its Fresnel reflection."
            )
        )
    pictures = [
        Picture(f"runs/{found[key]}", alt, 320)
        for key, alt in (("image", "POV-Ray's picture"), ("heatmap", "difference"))
        if found.get(key)
    ]
    if pictures:
        caption = "POV-Ray's picture, and its difference from the project's (colour scale below)"
        out.append(Gallery(["", "POV-Ray", "difference"], [(caption, [*pictures])]))
        out.append(Picture(f"{REPORT_DIR}/{HEAT_SCALE_PNG}", "heat map colour scale", 480))
    return out


def notes(run: Run, found: Sequence[Row], context: str = "") -> list[Block]:
    items = [
        "Its own factor: the step's throughput over the step it builds on, named in brackets.",
        "Time per pixel: the median timed render over its pixels, 1 sample per pixel. Steps "
        "whose fixed costs hide them at small sizes (a kernel's launch, a NumPy pass's set-up) "
        "are measured at 640x480 or more; factors compare throughput per pixel across sizes.",
        "Error it adds: the step's picture against the step before's, at the largest size both "
        "rendered. Allocations per pixel: counted in one untimed render at the comparison "
        "size, set-up included.",
    ]
    fixed = [f"`{spelled(r['name'], found)}`" for r in found if _ok(r)
             and fixed_share(r) >= FIXED_SHARE]  # fmt: skip
    found_anchor = anchor(run)
    point = table_point(found_anchor) if found_anchor is not None else None
    if point is not None and povray_fixed_share(point) >= FIXED_SHARE:
        fixed.append(f"POV-Ray (its start-up, parsing and writing: "
                     f"{povray_fixed_share(point):.0%} of its whole process)")  # fmt: skip
    if fixed:
        items.append(
            f"† {', '.join(fixed)}: fixed costs (a pool's start-up, a kernel's launch; the "
            f"probes' estimate of a render of no pixels) are over {FIXED_SHARE:.0%} of the "
            "render measured: its time per pixel overstates what another pixel costs."
        )
    reused = [f"`{r['name']}`" for r in found if r.get("reused")]
    if reused:
        items.append(f"The table's rows of this run stand for {', '.join(reused)}.")
    unavailable = [r for r in found if r.get("status") == "unavailable"]
    items += [f"`{r['name']}` not available here: {r.get('error', '')}" for r in unavailable]
    again = [r for r in found if r.get("attempts")]
    for row in again:
        stayed = "stayed busy" if figures.is_busy(row) else "got its cores"
        items.append(
            f"`{row['name']}` was busy and was measured {len(row['attempts'])} times: it "
            f"{stayed} (the least busy measurement is shown)."
        )
    out: list[Block] = [Para(context)] if context else []
    out.append(Bullets(items))
    busy = summary.busy_text(run, [r for r in found if _ok(r)])
    if busy:
        out.append(Para(busy))
    out += _anchor_notes(run)
    found_mesh = mesh_anchor(run)
    if found_mesh is not None:
        out.append(Para(mesh_text(found_mesh)))
    out += _step_maps(found)
    out += go_blocks()
    return out


def _step_maps(found: Sequence[Row]) -> list[Block]:
    """Where a step's picture differs from the step before's, for the steps that add
    error (the heat maps on the logarithmic colour scale above)."""
    entries: list[tuple[str, list[Picture | None]]] = []
    for row in found:
        error = row.get("error_vs_over")
        if not _ok(row) or not row.get("heatmap_over") or not error:
            continue
        caption = (
            f"`{spelled(row['name'], found)}` against `{spelled(error['against'], found)}` "
            f"({error['size']}): {_error_cell(row)}"
        )
        entries.append((caption, [Picture(f"runs/{row['heatmap_over']}", "difference", 320)]))
    if not entries:
        return []
    return [Gallery(["where a step adds error", "difference from the step before"], entries)]


def console_lines(run: Run) -> list[str]:
    found = rows(run)
    measured = [r for r in found if _ok(r)]
    if not measured:
        return []
    lines = ["", "step by step:"]
    for row in measured:
        lines.append(
            f"  {row['name']:<32} {'x'.join(map(str, row['size'])):>9} "
            f"{figures.per_pixel_text(per_pixel(row)):>10} per pixel "
            f"{_factor(own_factor(row, found)):>9} own {_factor(cumulative(row, found)):>10}"
        )
    found_anchor = anchor(run)
    if found_anchor is not None and found_anchor.get("status") == "ok":
        for point in found_anchor.get("points", []):
            if point.get("wall"):
                w, h = point["size"]
                lines.append(
                    f"  {'POV-Ray, ' + str(point['threads']) + ' thread(s)':<32} {w}x{h:<5} "
                    f"{figures.per_pixel_text(point['wall'] / (w * h)):>10} per pixel "
                    "(whole process)"
                )
    elif found_anchor is not None:
        lines.append(f"  POV-Ray: {found_anchor.get('error')}")
    found_mesh = mesh_anchor(run)
    if found_mesh is not None:
        lines.append("  " + mesh_text(found_mesh).replace("**", ""))
    text = advice(run)
    if text:
        lines.append("  " + text.replace("**", ""))
    return lines
