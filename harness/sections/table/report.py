"""The report's table section (``harness.sections.table.measure``'s rows of a run): the summary at
its top (``harness.document.summary``), the time table, the cost and accuracy table and the pictures
beside their heat maps; the speed-up plot; the lines ``rtc bench`` prints."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from harness.document import summary
from harness.document.model import Block, Bullets, Gallery, Heading, Para, Picture, Table
from harness.document.runinfo import (
    HEAT_SCALE_PNG,
    REPORT_DIR,
    machine_line,
    rows,
    settings_line,
    size_text,
    speedup_cell,
)
from harness.engine import figures
from harness.instruments.alloccount import FREE_LIST_NOTE, METHOD_NOTES
from harness.sections.table.measure import SECTION

Run = Mapping[str, Any]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured the table, if any."""
    return next((run for run in reversed(runs) if rows(run, SECTION)), None)


def _error_cells(row: Mapping[str, Any]) -> list[str]:
    error = row.get("error_vs_naive")
    if row["name"] == "naive":
        return ["(the reference)", "", "", "", ""]
    if not error:
        return ["-"] * 5
    psnr = "∞ (identical)" if error["psnr"] is None else f"{error['psnr']:.1f} dB"
    return [
        f"{error['max_abs']:.3g}",
        f"{error['mean_abs']:.3g}",
        f"{error['rmse']:.3g}",
        psnr,
        f"{error['pixels_over_one_step']} of {error['pixels']}",
    ]


def _alloc_cells(row: Mapping[str, Any]) -> list[str]:
    found = row.get("allocations")
    if not found:
        return ["-", "-", "-"]
    count = figures.count_text(found["count"])
    size = figures.bytes_text(found["bytes"])
    method = found["method"]
    extra = []
    if found.get("workers"):
        n = found["workers"]["processes"]
        extra.append(f"incl. {n} worker process{'es' if n != 1 else ''}")
    if found.get("nrt") is not None:
        extra.append(f"+ {figures.count_text(found['nrt'])} numba NRT")
    if method == "tracemalloc":
        count, size = f"≥{count} (net)", f"≥{size}"
    return [count, size, method + (f" ({'; '.join(extra)})" if extra else "")]


def _peak_cell(row: Mapping[str, Any]) -> str:
    peak = row.get("peak_memory")
    if not peak:
        return "-"
    text = figures.bytes_text(peak["main"])
    if peak.get("workers"):
        text += f" + workers {figures.bytes_text(peak['workers'])}"
    return text


def _rays_cells(row: Mapping[str, Any]) -> list[str]:
    rays = row.get("rays")
    if not rays:
        return ["-", "-"]
    parts = ", ".join(
        f"{k} {figures.count_text(rays[k])}" for k in ("camera", "shadow", "secondary") if k in rays
    )
    camera = rays.get("camera")
    ratio = f"{rays['total'] / camera:.2f}" if camera else "-"
    return [f"{figures.count_text(rays['total'])} ({parts})", ratio]


def _notes(rows: list[Mapping[str, Any]]) -> tuple[dict[str, str], list[str]]:
    """Footnote marks per row name (rows the budget rule shrank), and the footnotes."""
    marks: dict[str, str] = {}
    notes: list[str] = []
    for row in rows:
        if row.get("reduced"):
            notes.append(f"[{len(notes) + 1}] `{row['name']}`: {row['budget_note']}")
            marks[row["name"]] = f" [{len(notes)}]"
    return marks, notes


def time_table(rows: list[Mapping[str, Any]]) -> Table:
    marks, _ = _notes(rows)
    body = []
    for row in rows:
        name = f"`{row['name']}`{marks.get(row['name'], '')}"
        if row["status"] != "ok":
            body.append([name, "failed", row.get("error", "")[:200], *["-"] * 7])
            continue
        w = row["wall"]
        warm = row.get("warmup", {})
        first = warm.get("first", 0.0) - warm.get("second", 0.0)
        body.append(
            [
                name,
                size_text(row),
                figures.seconds_text(figures.median_wall(row)),
                figures.seconds_text(min(w)),
                figures.seconds_text(max(w)),
                summary.cpu_text(row),
                speedup_cell(row),
                f"{figures.mrays(row):.3g}",
                _peak_cell(row),
                figures.seconds_text(max(first, 0.0)),
            ]
        )
    header = [
        "variant",
        "size",
        "median",
        "min",
        "max",
        "CPU: cores used of asked",
        "speed-up",
        "MRay/s",
        "peak memory (RSS)",
        "first-call extra (JIT)",
    ]
    return Table(header, body, right={2, 3, 4, 5, 6, 7, 8, 9})


def cost_table(rows: list[Mapping[str, Any]]) -> Table:
    marks, _ = _notes(rows)
    body = []
    for row in rows:
        if row["status"] != "ok":
            continue
        name = f"`{row['name']}`{marks.get(row['name'], '')}"
        body.append([name, *_rays_cells(row), *_alloc_cells(row), *_error_cells(row)])
    header = [
        "variant",
        "rays cast (all kinds)",
        "rays per camera ray",
        "allocations",
        "bytes allocated",
        "counted by",
        "max abs error",
        "mean abs error",
        "RMSE",
        "PSNR",
        "pixels off > 1/255",
    ]
    return Table(header, body, right={2, 3, 4, 6, 7, 8, 9, 10})


def heat_visible(max_abs: float, full_scale: float) -> bool:
    """Whether a linear heat map (runs before the logarithmic scale) of a difference at most
    ``max_abs`` shows anything: its colour map gave the darkest of its N colours to
    differences below ``full_scale / N``, so a smaller one drew an all-black map."""
    # deferred: saves ~500 ms (matplotlib) of rtc bench's lines after a run
    from matplotlib import colormaps

    return max_abs > 0 and max_abs * colormaps["inferno"].N >= full_scale


@dataclass(frozen=True)
class HeatScale:
    """How a run drew its heat maps: ``log`` (``imagediff.heat_map``: ``low`` and below
    black, each tenfold larger difference a step brighter up to ``high``) or ``linear``
    (older runs: 0 black, ``high`` and above brightest)."""

    kind: str
    low: float
    high: float

    def visible(self, max_abs: float) -> bool:
        if self.kind == "log":
            return max_abs > self.low
        return heat_visible(max_abs, self.high)

    def text(self) -> str:
        if self.kind == "log":
            return (
                f"a logarithmic colour scale: black {self.low:.0e} or less, then a step "
                f"brighter for each tenfold difference, up to {self.high:g} (the scale below)"
            )
        return f"black: identical; brightest: {self.high * 255:.0f}/255 or more in some channel"


def heat_scale(run: Run) -> HeatScale:
    """The heat maps' scale of ``run`` (see ``HeatScale``)."""
    found = run.get("heat_scale")
    if found:
        return HeatScale(str(found["kind"]), float(found["low"]), float(found["high"]))
    return HeatScale("linear", 0.0, float(run.get("heat_full_scale", 16 / 255)))


def heat_scale_picture(scale: HeatScale) -> Picture | None:
    """The colour bar under the heat maps of a logarithmic scale (``plots.heat_scale_plot``
    draws it into the report folder)."""
    if scale.kind != "log":
        return None
    return Picture(f"{REPORT_DIR}/{HEAT_SCALE_PNG}", "heat map colour scale", 480)


def _picture_of(row: Mapping[str, Any]) -> tuple[str, str] | None:
    """The row's largest picture (measured or comparison size) as (path, size)."""
    found = []
    if row.get("image"):
        found.append((str(row["image"]), list(row["size"])))
    compare = row.get("compare_image")
    if compare and str(compare).endswith(".png") and row.get("compare_size"):
        found.append((str(compare), list(row["compare_size"])))
    if not found:
        return None
    path, size = max(found, key=lambda item: item[1][0] * item[1][1])
    return path, "x".join(map(str, size))


def _gallery(rows: list[Mapping[str, Any]], scale: HeatScale, compare: str) -> list[Block]:
    entries = []
    for row in rows:
        picture = _picture_of(row) if row["status"] == "ok" else None
        if picture is None:
            continue
        path, size = picture
        error = row.get("error_vs_naive")
        heat = row.get("heatmap")
        if row["name"] == "naive":
            note = "the reference"
        elif not error:
            note = "not compared"
        elif error["max_abs"] == 0:
            note = f"identical to naive's at {compare}"
        elif not scale.visible(error["max_abs"]):
            note = f"within {error['max_abs']:.2g} of naive's at {compare}: no visible map"
        else:
            note = (
                f"differs from naive's at {compare}: max {error['max_abs']:.3g} "
                f"({error['max_abs'] * 255:.2g}/255)"
            )
        show_heat = bool(heat) and error and scale.visible(error["max_abs"])
        heat_pic = (
            Picture(f"runs/{heat}", f"difference {row['name']} - naive", 160) if show_heat else None
        )
        caption = f"`{row['name']}` ({size}): {note}"
        entries.append((caption, [Picture(f"runs/{path}", row["name"], 160), heat_pic]))
    if not entries:
        return []
    blocks: list[Block] = [
        Para(
            "Each variant's picture once, at the larger of its measured and comparison sizes, "
            f"and a heat map of its difference from naive's picture at {compare} only where "
            f"the map is not all black ({scale.text()})."
        ),
        Gallery(["variant", "picture", "difference from naive"], entries),
    ]
    bar = heat_scale_picture(scale)
    if bar is not None:
        blocks.append(bar)
    return blocks


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run]) -> list[Block]:
    """The machine line, the summary (with the speed-up ``plot``), the time table, the cost
    and accuracy table, the pictures and the variants not available; ``runs``: every run,
    oldest first (the summary quotes an earlier run's image error where it compared at a
    larger size)."""
    table_rows = summary.fastest_first(rows(run, SECTION))
    out: list[Block] = [Para(machine_line(run))]
    out += summary.blocks(run, runs, plot)
    if table_rows:
        _, notes = _notes(table_rows)
        methods = sorted(
            {str(r["allocations"]["method"]) for r in table_rows if r.get("allocations")}
        )
        compare = "x".join(str(v) for v in run["compare_size"])
        out += [
            Heading(2, "Time"),
            Para(settings_line(run) + " Fastest first."),
            time_table(table_rows),
        ]
        busy = summary.busy_text(run, table_rows)
        if busy:
            out.append(Para(busy))
        out += [
            Heading(2, "Cost and accuracy"),
            Para(
                f"One untimed render per variant at the comparison size {compare} (the same "
                "for every row, so the figures compare): the rays it cast, the allocations it "
                "made, and its picture's error against naive's picture at the same size and "
                "settings (colors clamped to [0, 1])."
            ),
            cost_table(table_rows),
            Bullets(
                [
                    *notes,
                    "Speed-up: throughput (pixels x samples per second) over naive's, measured in "
                    "this run; '(per pixel)' where the two were measured at different sizes.",
                    "MRay/s: width x height x samples per second / 1e6 (camera samples, as the C++ "
                    "report counts).",
                    "Rays cast: every ray, camera, shadow and secondary (reflected and refracted), "
                    "counted in a separate untimed render where the variant can be counted "
                    "(its tracer's own count_rays, or a counting subclass of its tracer when "
                    "its render goes through the pipeline's steps); '-' where it cannot.",
                    "CPU: cores used (CPU seconds of the process and its workers per wall second "
                    "of the timed renders) of the cores the variant asks for; **busy** where "
                    f"under {figures.BUSY_SHARE:.0%} of them: it did not get them.",
                    "First-call extra: first tiny render minus the second (JIT compilation and "
                    "first-use costs), excluded from the timings.",
                    *[f"Allocations counted by {m}: {METHOD_NOTES.get(m, m)}." for m in methods],
                    "Worker processes count their own allocations (they are included, and named "
                    "in the 'counted by' column); allocations made while a worker's interpreter "
                    "starts, before the counters are installed, are not.",
                    f"Not counted: {FREE_LIST_NOTE}.",
                    "Peak memory: the resident-set high-water mark of the measuring process during "
                    "the timed renders, and the largest of its worker processes'.",
                ]
            ),
        ]
        out += [Heading(2, "Pictures")]
        out += _gallery(table_rows, heat_scale(run), compare)
    unavailable = run.get("unavailable") or {}
    if unavailable:
        out += [
            Heading(3, "Variants not available on this machine"),
            Bullets([f"`{name}`: {why}" for name, why in unavailable.items()]),
        ]
    return out


def console_lines(run: Run) -> list[str]:
    """The table's main figures as plain text, for the terminal after ``rtc bench``."""
    found = rows(run, SECTION)
    if not found:
        return []
    lines = [
        f"{'variant':<44} {'size':>9} {'median':>9} {'speed-up':>14} {'MRay/s':>8} "
        f"{'allocs':>8} {'RMSE':>9}"
    ]
    for row in found:
        if row["status"] != "ok":
            lines.append(f"{row['name']:<44} failed: {row.get('error', '')[:60]}")
            continue
        error = row.get("error_vs_naive")
        rmse = "-" if not error else f"{error['rmse']:.3g}"
        allocs = figures.count_text((row.get("allocations") or {}).get("count"))
        lines.append(
            f"{row['name']:<44} {size_text(row):>9} "
            f"{figures.seconds_text(figures.median_wall(row)):>9} {speedup_cell(row):>14} "
            f"{figures.mrays(row):>8.3g} {allocs:>8} {rmse:>9}"
        )
    return lines
