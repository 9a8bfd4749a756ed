"""``rtc report``: ``results/README.md`` and ``results/report.html`` from the run history.

Each section comes from the newest run that measured it: the tables (time; cost and
accuracy) and the pictures beside their heat maps, error against time, scaling, the C++
workload and the chapter progress, with the plots (``results/report/*.png``); every run is
summarized in the history. The machine and the settings are printed beside
every table. The HTML page holds the same content with the images inlined.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from harness import (
    cluster_report,
    figures,
    ladder_report,
    light_samples_report,
    pass_size_report,
    plots,
    profiling_report,
    scene_size_report,
    sharing,
    summary,
)
from harness.alloccount import FREE_LIST_NOTE, METHOD_NOTES
from harness.document import (
    Block,
    Bullets,
    Gallery,
    Heading,
    Para,
    Picture,
    Table,
    anchor,
    to_html,
    to_markdown,
)
from harness.results import ResultFileError, check_run, list_runs, load_run

REPORT_DIR = "report"
C_PLUS_PLUS_ANCHOR = "the C++ report reached 44.9 MRay/s on this workload, on a whole lab machine"

Run = Mapping[str, Any]


def _rows(run: Run, section: str) -> list[Mapping[str, Any]]:
    return [r for r in run["rows"] if r["section"] == section]


def _size(row: Mapping[str, Any]) -> str:
    return "x".join(str(v) for v in row["size"])


def _git(run: Run) -> str:
    m = run["machine"]
    commit = (m.get("commit") or "unknown")[:10]
    return f"{commit}{' (dirty tree)' if m.get('dirty') else ''}"


def machine_line(run: Run) -> str:
    m = run["machine"]
    load = m.get("load_average")
    load_text = f", load average {load[0]:.2f} at start" if load else ""
    return (
        f"Machine: `{m['hostname']}`, {m['cpu_model']}, {m['cores_available']} of "
        f"{m['cpu_count']} cores{load_text}; Python {m['python']}, numpy {m.get('numpy')}, "
        f"numba {m.get('numba')}; commit {_git(run)}; run `{run['stem']}` started "
        f"{run['started'][:19]} UTC, took {run['seconds']:.0f} s."
        + (f" **Shared machine:** {run['shared']}" if run.get("shared") else "")
    )


def context_line(run: Run) -> str:
    """The machine and run in one line, repeated beside every section's numbers."""
    m = run["machine"]
    load = m.get("load_average")
    load_text = f", load {load[0]:.1f} at start" if load else ""
    return (
        f"Measured on `{m['hostname']}` ({m['cpu_model']}, {m['cores_available']} cores"
        f"{load_text}), Python {m['python']}, numba {m.get('numba')}, commit {_git(run)}, "
        f"run `{run['stem']}`, budget {run['settings']['budget'] or 0:g} s per row "
        f"(naive: 3x), mode {run['settings']['mode']['name']}."
        + (f" **Shared machine** ({sharing.brief(run.get('load'))})." if run.get("shared") else "")
    )


def settings_line(run: Run, section: str = "table") -> str:
    s = run["settings"]
    threads = s["threads"] or "all"
    budget = f"{s['budget']:g} s" if s["budget"] else "none"
    if section == "preset":
        scene = s.get("preset", "cpp-spheres")
        return (
            f"Settings: scene `{scene}`, requested {s['mode']['preset_size'][0]}x"
            f"{s['mode']['preset_size'][1]}, 8 samples per pixel, depth 5, "
            f"{s['mode']['side_repeat']} timed render(s) per row, budget {budget} per row, "
            f"CPUs: {threads}."
        )
    return (
        f"Settings: scene `{s['scene']['name']}`, requested {s['size'][0]}x{s['size'][1]}, "
        f"{s['samples']} sample(s) per pixel, depth {s['depth']}, seed {s['seed']}, "
        f"epsilon {s.get('epsilon') or 'the book default (0.0001)'}, "
        f"{s['repeat']} timed renders per row, budget {budget} per row (naive: 3x), mode "
        f"{s['mode']['name']}, CPUs: {threads}."
    )


# ----------------------------------------------------------------- the table's cells


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


def _speedup_cell(row: Mapping[str, Any]) -> str:
    found = row.get("speedup")
    if not found:
        return "-"
    mark = "" if found["basis"] == "same size" else " (per pixel)"
    return f"{figures.speedup_text(found['value'])}{mark}"


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
                _size(row),
                figures.seconds_text(figures.median_wall(row)),
                figures.seconds_text(min(w)),
                figures.seconds_text(max(w)),
                summary.cpu_text(row),
                _speedup_cell(row),
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


# ----------------------------------------------------------------- sections


def heat_visible(max_abs: float, full_scale: float) -> bool:
    """Whether a linear heat map (runs before the logarithmic scale) of a difference at most
    ``max_abs`` shows anything: its colour map gave the darkest of its N colours to
    differences below ``full_scale / N``, so a smaller one drew an all-black map."""
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
        return f"black: identical; brightest: {self.high * 255:.0f}/255 or more"


def heat_scale(run: Run) -> HeatScale:
    """The heat maps' scale of ``run`` (see ``HeatScale``)."""
    found = run.get("heat_scale")
    if found:
        return HeatScale(str(found["kind"]), float(found["low"]), float(found["high"]))
    return HeatScale("linear", 0.0, float(run.get("heat_full_scale", 16 / 255)))


HEAT_SCALE_PNG = ladder_report.HEAT_SCALE_PNG


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


def _skip_reason(points: list[Mapping[str, Any]]) -> str:
    """One reason for several skipped points: the first one's (the cheapest)."""
    reason = str(points[0]["skipped"])
    return reason if len(points) == 1 else f"{reason} (the cheapest of them)"


def _sweep_blocks(run: Run, plot: Path | None) -> list[Block]:
    truth = next((e for e in run["series"] if e["section"] == "truth"), None)
    sweeps = [e for e in run["series"] if e["section"] == "sweep"]
    if truth is None and not sweeps:
        return []
    blocks: list[Block] = [Heading(2, "Error against run time"), Para(context_line(run))]
    if truth is not None and truth.get("points") and "wall" in truth["points"][0]:
        p = truth["points"][0]
        blocks.append(
            Para(
                f"Ground truth: `{truth['name']}` (the fastest variant whose table picture equals "
                f"naive's) at {p['size'][0]}x{p['size'][1]} with {p['samples']} samples per pixel "
                f"({figures.seconds_text(p['wall'])}). Sample positions are a pure function of "
                "(seed, pixel, sample), so exact variants render the same pictures and differ only "
                "in time; float32 and fastmath options also differ in error. One render per point."
            )
        )
    if plot is not None:
        blocks.append(Picture(f"{REPORT_DIR}/{plot.name}", "error against time"))
    body = []
    for entry in sweeps:
        for p in entry.get("points", []):
            if "wall" in p and p.get("error"):
                e = p["error"]
                psnr = "∞" if e["psnr"] is None else f"{e['psnr']:.1f}"
                body.append(
                    [
                        f"`{entry['name']}`",
                        str(p["samples"]),
                        figures.seconds_text(p["wall"]),
                        f"{e['rmse']:.4g}",
                        psnr,
                        f"{e['max_abs']:.3g}",
                    ]
                )
        skipped = [p for p in entry.get("points", []) if p.get("skipped")]
        if skipped:
            spp = ", ".join(str(p["samples"]) for p in skipped)
            body.append(
                [f"`{entry['name']}`", spp, "skipped: " + _skip_reason(skipped), "-", "-", "-"]
            )
        if entry["status"] != "ok":
            body.append(
                [f"`{entry['name']}`", "-", "failed: " + entry.get("error", ""), "-", "-", "-"]
            )
    if body:
        blocks.append(
            Table(
                ["configuration", "samples/pixel", "time", "RMSE", "PSNR (dB)", "max abs error"],
                body,
                right={1, 2, 3, 4, 5},
            )
        )
    return blocks


def _scaling_blocks(run: Run, pixels_png: Path | None, threads_png: Path | None) -> list[Block]:
    sizes = [e for e in run["series"] if e["section"] == "sizes"]
    threads = _rows(run, "threads")
    if not sizes and not threads:
        return []
    blocks: list[Block] = [Heading(2, "Scaling"), Para(context_line(run))]
    if pixels_png is not None:
        blocks.append(Picture(f"{REPORT_DIR}/{pixels_png.name}", "time against pixel count"))
    body = []
    for entry in sizes:
        for p in entry.get("points", []):
            w, h = p["size"]
            if "wall" in p:
                per_pixel = p["wall"] / (w * h)
                body.append(
                    [
                        f"`{entry['name']}`",
                        f"{w}x{h}",
                        figures.seconds_text(p["wall"]),
                        figures.per_pixel_text(per_pixel),
                        summary.point_cpu_text(entry, p),
                    ]
                )
        skipped = [p for p in entry.get("points", []) if p.get("skipped")]
        if skipped:
            sizes_text = ", ".join("x".join(map(str, p["size"])) for p in skipped)
            body.append(
                [f"`{entry['name']}`", sizes_text, "skipped: " + _skip_reason(skipped), "-", "-"]
            )
    if body:
        header = ["variant", "size", "time", "time per pixel", "CPU: cores used of asked"]
        blocks.append(Table(header, body, right={2, 3, 4}))
        busy_points = [f"`{e['name']}` at {'x'.join(map(str, p['size']))}" for e in sizes
                       for p in e.get("points", []) if summary.point_busy(e, p)]  # fmt: skip
        if busy_points:
            blocks.append(Para(summary.busy_points_text(run, busy_points)))
    if threads_png is not None:
        blocks.append(Picture(f"{REPORT_DIR}/{threads_png.name}", "throughput against workers"))
    if threads:
        body = []
        ones = {r["group"]: r for r in threads if r["count"] == 1 and r["status"] == "ok"}
        for row in threads:
            if row["status"] != "ok":
                body.append(
                    [row["group"], str(row["count"]), f"`{row['name']}`", "failed", "-", "-", "-"]
                )
                continue
            one = ones.get(row["group"])
            gain = f"{figures.mrays(row) / figures.mrays(one):.2f}x" if one else "-"
            body.append(
                [
                    row["group"],
                    str(row["count"]),
                    f"`{row['name']}`",
                    _size(row),
                    f"{figures.mrays(row):.3g}",
                    gain,
                    summary.cpu_text(row),
                ]
            )
        blocks.append(
            Table(
                [
                    "variant (option)",
                    "count",
                    "name",
                    "size",
                    "MRay/s",
                    "over 1",
                    "CPU: cores used of asked",
                ],
                body,
                right={1, 4, 5, 6},
            )
        )
        busy_threads = summary.busy_text(run, threads)
        if busy_threads:
            blocks.append(Para(busy_threads + " On the plot: hollow markers."))
    return blocks


def _preset_blocks(run: Run) -> list[Block]:
    rows = _rows(run, "preset")
    if not rows:
        return []
    body = []
    for row in rows:
        if row["status"] != "ok":
            body.append([f"`{row['name']}`", "failed", row.get("error", "")[:120], "-", "-", "-"])
            continue
        note = row["budget_note"] if row.get("reduced") else ""
        body.append(
            [
                f"`{row['name']}`",
                _size(row),
                figures.seconds_text(figures.median_wall(row)),
                f"{figures.mrays(row):.3g}",
                _speedup_cell(row),
                note,
            ]
        )
    return [
        Heading(2, "The C++ report's workload (cpp-spheres)"),
        Para(context_line(run)),
        Para(settings_line(run, "preset") + f" For scale: {C_PLUS_PLUS_ANCHOR}."),
        Table(["variant", "size", "median", "MRay/s", "speed-up", "note"], body, right={2, 3, 4}),
    ]


def _kata_blocks(run: Run) -> list[Block]:
    kata = run.get("kata")
    if not kata or not kata.get("summary"):
        return []
    variants = list(kata.get("variants") or [])
    chapters: dict[Any, dict[str, Mapping[str, Any]]] = {}
    titles: dict[Any, str] = {}
    for entry in kata["summary"]:
        chapters.setdefault(entry["chapter"], {})[entry["variant"]] = entry
        titles[entry["chapter"]] = entry["title"]
    body = []
    for chapter, by_variant in chapters.items():
        cells = []
        for variant in variants:
            e = by_variant.get(variant)
            if e is None:
                cells.append("-")
                continue
            total = e["passed"] + e["failed"] + e["undefined"] + e.get("skipped", 0)
            total += e.get("todo", 0)  # stubs not written yet (rtc new)
            mark = "✓" if e["passed"] == total else "✗"
            cells.append(f"{mark} {e['passed']}/{total}")
        body.append([f"{chapter or '?'} {titles[chapter]}", *cells])
    return [
        Heading(2, "Chapter progress"),
        Para(
            "Scenarios passed per chapter and variant (`rtc kata --variant all`), "
            "at the commit of the latest run."
        ),
        Table(["chapter", *[f"`{v}`" for v in variants]], body),
    ]


def _changes_by_run(runs: list[Run]) -> dict[int, list[Any]]:
    """Per run index, the variants whose time changed significantly from their previous run
    (``harness.compare.history``)."""
    from harness import compare

    found: dict[int, list[compare.HistoryPoint]] = {}
    for series in compare.history(runs):
        for point in series.points:
            if point.change is not None and point.change.test.significant:
                found.setdefault(point.run, []).append(point)
    return found


def _history_blocks(runs: list[Run], plot: Path | None = None) -> list[Block]:
    from harness import compare

    changes = _changes_by_run(runs)
    body = []
    for index in reversed(range(len(runs))):
        run = runs[index]
        table = [r for r in _rows(run, "table") if r["status"] == "ok"]
        naive = next((r for r in table if r["name"] == "naive"), None)
        best = max(
            (r for r in table if r.get("speedup")),
            key=lambda r: r["speedup"]["value"],
            default=None,
        )
        s = run["settings"]
        m = run["machine"]
        verdicts = [p.change.verdict for p in changes.get(index, []) if p.change is not None]
        moved = (
            f"{verdicts.count('slower')} slower, {verdicts.count('faster')} faster"
            if verdicts
            else "-"
        )
        body.append(
            [
                run["started"][:16].replace("T", " "),
                f"`{run['stem']}`",
                s["mode"]["name"],
                f"{s['size'][0]}x{s['size'][1]}, {s['samples']} spp",
                f"{m['hostname']}, {m.get('cpu_model', '?')}, {m['cores_available']} cores",
                _git(run),
                f"{figures.median_wall(naive) / figures.pixels(naive) * 1e3:.3g} ms"
                if naive
                else "-",
                f"`{best['name']}` {figures.speedup_text(best['speedup']['value'])}"
                if best
                else "-",
                moved,
            ]
        )
    blocks: list[Block] = [
        Heading(2, "History"),
        Para(
            f"Every run kept in `runs/` ({len(runs)}), newest first. Each variant's time is "
            "tested against its previous run where both measured it at the same size (the "
            "budget rule can size a slow variant differently per run: those points are not "
            f"tested). The test: {compare.TEST_NAME}. A change between two CPUs or with a busy "
            "row says as much about the machine as about the code. `rtc compare RUN_A RUN_B` "
            "prints any two runs side by side."
        ),
    ]
    if plot is not None:
        blocks.append(Picture(f"{REPORT_DIR}/{plot.name}", "time per pixel across runs"))
    blocks.append(
        Table(
            [
                "started (UTC)",
                "run",
                "mode",
                "table size",
                "machine",
                "commit",
                "naive per pixel",
                "fastest (speed-up)",
                "significant changes",
            ],
            body,
        )
    )
    items = []
    for index in sorted(changes, reverse=True):
        run = runs[index]
        cpu = run["machine"].get("cpu_model")
        parts = []
        other_cpus = set()
        for point in changes[index]:
            change = point.change
            assert change is not None
            marks = ", busy" if change.a.busy or change.b.busy else ""
            before = runs[point.previous] if point.previous is not None else run
            if before["machine"].get("cpu_model") != cpu:
                other_cpus.add(str(before["machine"].get("cpu_model")))
                marks += ", other CPU"
            parts.append(
                f"`{point.measured.key.name}` {change.ratio_text()} ({change.test_text()}{marks})"
            )
        where = f"commit {_git(run)}"
        if other_cpus:
            where += f"; on {cpu}, the runs before on {', '.join(sorted(other_cpus))}"
        items.append(f"`{run['stem']}` ({where}): " + "; ".join(parts) + ".")
    if items:
        blocks += [
            Para("Significant changes from each variant's previous run, newest first:"),
            Bullets(items),
        ]
    return blocks


SECTION_TESTS: dict[str, Any] = {
    "table": lambda run: bool(_rows(run, "table")),
    "sweep": lambda run: any(e["section"] in ("truth", "sweep") for e in run["series"]),
    "scaling": lambda run: (
        any(e["section"] == "sizes" for e in run["series"]) or bool(_rows(run, "threads"))
    ),
    "preset": lambda run: bool(_rows(run, "preset")),
    "kata": lambda run: bool((run.get("kata") or {}).get("summary")),
}


def pick_runs(runs: list[Run]) -> dict[str, Run]:
    """For each section of the report, the newest run that measured it (``rtc bench
    --sections`` runs only some), falling back to the newest run."""
    return {
        section: next((run for run in reversed(runs) if has(run)), runs[-1])
        for section, has in SECTION_TESTS.items()
    }


@dataclass(frozen=True)
class SideSection:
    """A section beside the table (``rtc bench --sections NAME``), in the report: its
    ``_report`` module (``newest(runs)``, ``blocks(run, [plot,] context)``) and its plot
    (``plot(run, path)`` drawn into ``plot_file``; None: no plot)."""

    name: str
    report: Any
    plot: Callable[[Run, Path], Path | None] | None = None
    plot_file: str = ""


SIDE_SECTIONS = (
    SideSection("scene-size", scene_size_report, plots.scene_size_plot, "time-vs-triangles.png"),
    SideSection(
        "light-samples",
        light_samples_report,
        plots.light_samples_plot,
        "soft-shadows-error-vs-time.png",
    ),
    SideSection("profile", profiling_report),
    SideSection("cluster", cluster_report, plots.cluster_plot, "cluster.png"),
    SideSection("pass-size", pass_size_report, plots.pass_size_plot, "pass-size.png"),
)
"""The sections beside the table, in the report's order."""


LINKS = (
    ("every variant", "Summary"),
    ("error against time", "Error against run time"),
    ("numerical stability", "Numerical stability"),
    ("pictures", "Pictures"),
    ("history", "History"),
)
"""The sections linked from the top of the report (text, heading), where the report has them."""


def _links(blocks: list[Block]) -> list[tuple[str, str]]:
    headings = {block.text for block in blocks if isinstance(block, Heading)}
    return [(text, anchor(heading)) for text, heading in LINKS if heading in headings]


def build_blocks(
    runs: list[Run], plot_files: Mapping[str, Path | None], tail: Sequence[Block] = ()
) -> list[Block]:
    """The report's blocks from ``runs`` (oldest first), ``tail`` (the stability section)
    last; the top links to the sections it has (``LINKS``)."""
    chosen = pick_runs(runs)
    latest = chosen["table"]
    table_rows = summary.fastest_first(_rows(latest, "table"))
    blocks: list[Block] = [Heading(1, "Benchmark results")]
    measured = ladder_report.newest(runs)
    links_at = None
    if measured is not None:
        png = plot_files.get("ladder")
        plot = None if png is None else f"{REPORT_DIR}/{png.name}"
        blocks += ladder_report.blocks(measured, plot)
        links_at = next(
            (i + 1 for i, b in enumerate(blocks)
             if isinstance(b, Picture) and b.alt == ladder_report.PLOT_ALT),
            len(blocks),
        )  # fmt: skip
    blocks += [
        Para(
            "Generated by `rtc report` from the run files in `results/runs/` (one per "
            "`rtc bench`, never overwritten). Each section shows the newest run that measured "
            "it, named beside it; every run is summarized under History. Timings are "
            "wall-clock seconds of whole renders in a fresh process per variant; treat them "
            "as valid for the machine named."
        ),
        Para(machine_line(latest)),
    ]
    speedup_png = plot_files.get("speedup")
    blocks += summary.blocks(
        latest, runs, None if speedup_png is None else f"{REPORT_DIR}/{speedup_png.name}"
    )
    if table_rows:
        _, notes = _notes(table_rows)
        methods = sorted(
            {str(r["allocations"]["method"]) for r in table_rows if r.get("allocations")}
        )
        compare = "x".join(str(v) for v in latest["compare_size"])
        blocks += [
            Heading(2, "Time"),
            Para(settings_line(latest) + " Fastest first."),
            time_table(table_rows),
        ]
        busy = summary.busy_text(latest, table_rows)
        if busy:
            blocks.append(Para(busy))
        blocks += [
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
        blocks += [Heading(2, "Pictures")]
        blocks += _gallery(table_rows, heat_scale(latest), compare)
    unavailable = latest.get("unavailable") or {}
    if unavailable:
        blocks += [
            Heading(3, "Variants not available on this machine"),
            Bullets([f"`{name}`: {why}" for name, why in unavailable.items()]),
        ]
    blocks += _sweep_blocks(chosen["sweep"], plot_files.get("sweep"))
    blocks += _scaling_blocks(
        chosen["scaling"], plot_files.get("pixels"), plot_files.get("threads")
    )
    blocks += _preset_blocks(chosen["preset"])
    for side in SIDE_SECTIONS:
        measured = side.report.newest(runs)
        if measured is None:
            continue
        if side.plot is None:
            blocks += side.report.blocks(measured, context_line(measured))
            continue
        png = plot_files.get(side.name)
        plot = None if png is None else f"{REPORT_DIR}/{png.name}"
        blocks += side.report.blocks(measured, plot, context_line(measured))
    blocks += _kata_blocks(chosen["kata"])
    if latest.get("notes"):
        blocks += [Heading(2, "Notes"), Bullets(list(latest["notes"]))]
    blocks += _history_blocks(runs, plot_files.get("history"))
    blocks += tail
    links = _links(blocks)
    if links:
        line = Para("See also: " + " · ".join(f"[{t}](#{a})" for t, a in links) + ".")
        blocks.insert(2 if links_at is None else links_at, line)
    return blocks


def _write_text(path: Path, text: str) -> None:
    fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    finally:
        Path(temporary).unlink(missing_ok=True)


def load_history(results: Path) -> tuple[list[Run], list[str]]:
    """Every run the report can use, oldest first, and one line for each it cannot (the
    file and the field: ``harness.results.check_run``, then a trial report of the run
    alone, which names what the checks missed)."""
    runs: list[Run] = []
    problems: list[str] = []
    for path in list_runs(results):
        try:
            run = load_run(path)["rtc"]
            check_run(run, str(path))
        except ResultFileError as error:
            problems.append(" ".join(str(error).split()))
            continue
        why = _unusable(run)
        if why:
            problems.append(f"{path}: {why}")
            continue
        runs.append(run)
    return runs, problems


def _unusable(run: Run) -> str | None:
    """Why the report cannot be built from ``run`` alone (a field the checks do not cover),
    or None: the run's blocks and console table are built and thrown away."""
    try:
        to_markdown(build_blocks([run], {}))
        console_table(run)
    except (LookupError, TypeError, ValueError, AttributeError, ArithmeticError) as error:
        return " ".join(f"the report cannot use it: {type(error).__name__}: {error}".split())
    return None


def build_report(
    results: Path, warn: Callable[[str], None] | None = None
) -> tuple[Path, Path, list[str]]:
    """Write README.md, report.html and the plots; returns their paths and any problems
    (each also passed to ``warn`` as soon as it is found, before the report is built)."""
    from harness.stability import runfile as stability_runs
    from harness.stability import table as stability_table

    runs, problems = load_history(results)
    stability, stability_problems = stability_runs.latest_run(results)
    problems += stability_problems
    for problem in problems:
        if warn is not None:
            warn(problem)
    if not runs and stability is None:
        skipped = f" ({len(problems)} skipped: see above)" if problems else ""
        raise FileNotFoundError(
            f"no usable bench or stability results in {results / 'runs'}{skipped}; run "
            "`rtc bench` first (or `rtc stability`)"
        )
    folder = results / REPORT_DIR
    folder.mkdir(parents=True, exist_ok=True)
    tail: list[Block] = []
    if stability is not None:
        tail += stability_table.report_blocks(stability)
    if runs:
        chosen = pick_runs(runs)
        plot_files = {
            "speedup": plots.speedup_plot(chosen["table"], folder / "speedup.png"),
            "sweep": plots.sweep_plot(chosen["sweep"], folder / "error-vs-time.png"),
            "pixels": plots.pixels_plot(chosen["scaling"], folder / "time-vs-pixels.png"),
            "threads": plots.threads_plot(chosen["scaling"], folder / "throughput-vs-workers.png"),
            "history": plots.history_plot(runs, folder / "history.png"),
        }
        for side in SIDE_SECTIONS:
            measured = side.report.newest(runs)
            if measured is not None and side.plot is not None:
                plot_files[side.name] = side.plot(measured, folder / side.plot_file)
        ladder = ladder_report.newest(runs)
        if ladder is not None:
            plot_files["ladder"] = plots.ladder_plot(ladder, folder / "ladder.png")
        plots.heat_scale_plot(folder / HEAT_SCALE_PNG)
        blocks = build_blocks(runs, plot_files, tail)
    else:
        blocks = [Heading(1, "Benchmark results"), Para("No bench run yet (`rtc bench`).")]
        blocks += tail
    if problems:
        blocks += [Heading(2, "Unreadable result files"), Bullets(problems)]
    readme, page = results / "README.md", results / "report.html"
    _write_text(readme, to_markdown(blocks))
    _write_text(page, to_html(blocks, results, "Benchmark results"))
    return readme, page, problems


def console_table(run: Run) -> str:
    """The table's main figures as plain text, for the terminal after ``rtc bench``."""
    lines = [
        f"{'variant':<44} {'size':>9} {'median':>9} {'speed-up':>14} {'MRay/s':>8} "
        f"{'allocs':>8} {'RMSE':>9}"
    ]
    if not _rows(run, "table") and not _rows(run, "preset"):
        lines = []  # a run of other sections only (scene-size)
    for row in _rows(run, "table"):
        if row["status"] != "ok":
            lines.append(f"{row['name']:<44} failed: {row.get('error', '')[:60]}")
            continue
        error = row.get("error_vs_naive")
        rmse = "-" if not error else f"{error['rmse']:.3g}"
        allocs = figures.count_text((row.get("allocations") or {}).get("count"))
        lines.append(
            f"{row['name']:<44} {_size(row):>9} "
            f"{figures.seconds_text(figures.median_wall(row)):>9} {_speedup_cell(row):>14} "
            f"{figures.mrays(row):>8.3g} {allocs:>8} {rmse:>9}"
        )
    for row in _rows(run, "preset"):
        if row["status"] == "ok":
            lines.append(
                f"cpp-spheres {row['name']:<32} {_size(row):>9} "
                f"{figures.seconds_text(figures.median_wall(row)):>9} {'':>14} "
                f"{figures.mrays(row):>8.3g}"
            )
    lines += scene_size_report.console_lines(run)
    lines += light_samples_report.console_lines(run)
    lines += pass_size_report.console_lines(run)
    lines += cluster_report.console_lines(run)
    lines += profiling_report.console_lines(run)
    if math.isfinite(run["seconds"]):
        lines.append(f"(the run took {run['seconds']:.0f} s)")
    return "\n".join(lines)
