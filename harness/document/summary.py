"""The report's summary: one table at the top of ``results/README.md`` and ``report.html``
saying, per variant of the newest table run, what it changes, how much faster than naive it
renders, what it costs in image error and allocations, and whether it got the cores it asked
for; fastest first, with a lead sentence naming the fastest. Every figure is read from the
run files (``rtc bench``); the one-line descriptions are the variants' own summaries from the
registry, recorded in each row.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from harness.document.model import Block, Bullets, Heading, Para, Picture, Table
from harness.engine import figures
from variants.registry import VariantError, parse_variant_name

Run = Mapping[str, Any]
Row = Mapping[str, Any]

# image error is quoted from a comparison of at least this many pixels where a run has one
MEANINGFUL_SIZE = (160, 120)
MEANINGFUL_PIXELS = MEANINGFUL_SIZE[0] * MEANINGFUL_SIZE[1]
# the settings two runs must share for one's image error to stand for the other's
SAME_PICTURE = ("samples", "depth", "seed", "epsilon")


def _table_rows(run: Run) -> list[Row]:
    return [r for r in run["rows"] if r["section"] == "table"]


def _keep(text: str) -> str:
    """``text`` with no-break spaces, so that a figure and its unit stay on one line."""
    return text.replace(" ", "\u00a0")


def _size(row: Row) -> str:
    return "x".join(str(v) for v in row["size"])


def speed_key(row: Row) -> float:
    """Sort key, fastest first: minus the speed-up (rows without one, and failed rows, last)."""
    found = row.get("speedup") if row.get("status") == "ok" else None
    return -found["value"] if found else math.inf


def fastest_first(rows: Sequence[Row]) -> list[Row]:
    """``rows`` by speed-up over naive, fastest first (a stable sort: ties keep run order)."""
    return sorted(rows, key=speed_key)


def per_pixel(row: Row) -> float:
    """Median seconds per pixel (at the row's samples per pixel)."""
    return figures.median_wall(row) / figures.pixels(row)


def _pixel_range(row: Row) -> tuple[float, float]:
    return min(row["wall"]) / figures.pixels(row), max(row["wall"]) / figures.pixels(row)


def tied_with(fastest: Row, others: Sequence[Row]) -> list[Row]:
    """The rows whose range of timed renders (fastest to slowest, per pixel) overlaps the
    fastest row's: the timings do not tell them apart."""
    low, high = _pixel_range(fastest)
    tied = []
    for row in others:
        if row is fastest or row.get("status") != "ok" or not row.get("wall"):
            continue
        other_low, other_high = _pixel_range(row)
        if other_low <= high and low <= other_high:
            tied.append(row)
    return tied


def _same_picture(a: Run, b: Run) -> bool:
    sa, sb = a["settings"], b["settings"]
    if sa["scene"]["name"] != sb["scene"]["name"]:
        return False
    return all(sa.get(key) == sb.get(key) for key in SAME_PICTURE)


@dataclass(frozen=True, slots=True)
class ErrorFound:
    """A row's image error against naive's picture, and the run that measured it."""

    error: Mapping[str, Any]
    run: Run

    @property
    def size(self) -> str:
        return str(self.error.get("size") or "")


def _newest_errors(run: Run, runs: Sequence[Run]) -> dict[str, ErrorFound]:
    """By variant name, the image error at ``MEANINGFUL_PIXELS`` or more of the newest other
    run of ``run``'s scene and settings that has one: one pass over the runs."""
    found: dict[str, ErrorFound] = {}
    for other in reversed(runs):
        if other is run or not _same_picture(run, other):
            continue
        for candidate in _table_rows(other):
            error = candidate.get("error_vs_naive")
            if candidate["status"] == "ok" and error and error["pixels"] >= MEANINGFUL_PIXELS:
                found.setdefault(str(candidate["name"]), ErrorFound(error, other))
    return found


def error_found(
    row: Row, run: Run, runs: Sequence[Run], newest: Mapping[str, ErrorFound] | None = None
) -> ErrorFound | None:
    """The row's image error at ``MEANINGFUL_PIXELS`` or more: its own if its run compared
    at such a size, else that of the newest run of the same scene and settings that did (for
    a row of the same name), else its own at the run's comparison size. ``newest``:
    ``_newest_errors(run, runs)`` when the caller has it (one pass over the runs for every
    row of a run: the report's cost grows with the number of runs, not its square)."""
    own = row.get("error_vs_naive")
    if own and own["pixels"] >= MEANINGFUL_PIXELS:
        return ErrorFound(own, run)
    if newest is None:
        newest = _newest_errors(run, runs)
    quoted = newest.get(str(row["name"]))
    if quoted is not None:
        return quoted
    return ErrorFound(own, run) if own else None


def psnr_text(error: Mapping[str, Any]) -> str:
    return "∞ (identical)" if error["psnr"] is None else f"{error['psnr']:.1f} dB"


def pixels_off_text(error: Mapping[str, Any]) -> str:
    return f"{error['pixels_over_one_step']:,} of {error['pixels']:,}"


def changes_text(row: Row, rows: Sequence[Row]) -> str:
    """The variant's own summary; where several rows share it (one variant's options), the
    options that tell this row apart."""
    summary = str(row.get("summary") or "")
    shared = sum(1 for other in rows if other.get("summary") == summary) > 1
    try:
        options = parse_variant_name(str(row["name"])).options
    except VariantError:
        options = ()
    if shared and options:
        spelled = ", ".join(key if value == "true" else f"{key}={value}" for key, value in options)
        summary += f"; option {spelled}"
    return summary


def cpu_text(row: Row) -> str:
    """``1.50 of 2``: cores busy of the cores asked for, with **busy** where under 80%."""
    asked = figures.cores_asked(str(row["name"]), int(row.get("cores") or 1))
    text = f"{figures.cpu_share(row):.2f} of {asked}"
    return f"{text} **busy**" if figures.is_busy(row) else text


def allocations_text(row: Row) -> str:
    found = row.get("allocations")
    size = row.get("compare_size")
    if not found or not size or found.get("count") is None:
        return "-"
    per = found["count"] / (int(size[0]) * int(size[1]))
    return figures.count_text(per) if per >= 10 else f"{per:.2g}"


def other_runs(run: Run, runs: Sequence[Run]) -> dict[str, str]:
    """The earlier runs whose image errors the summary quotes, by stem, with their marks
    (``a``, ``b`` ...), oldest first."""
    quoted = set()
    newest = _newest_errors(run, runs)
    for row in _table_rows(run):
        found = error_found(row, run, runs, newest) if row["status"] == "ok" else None
        if found is not None and found.run is not run:
            quoted.add(id(found.run))
    stems = [str(other["stem"]) for other in runs if other is not run and id(other) in quoted]
    return {stem: chr(ord("a") + i) for i, stem in enumerate(stems)}


def _error_cells(
    row: Row, found: ErrorFound | None, run: Run, marks: Mapping[str, str]
) -> tuple[str, str]:
    if row["name"] == "naive":
        return "(the reference)", "-"
    if found is None:
        return "-", "-"
    size = f" ({found.size})" if found.size else ""
    elsewhere = "" if found.run is run else f" [{marks[str(found.run['stem'])]}]"
    return _keep(psnr_text(found.error)), _keep(pixels_off_text(found.error)) + size + elsewhere


def table(run: Run, runs: Sequence[Run]) -> Table:
    """The summary table of ``run``'s table rows, fastest first."""
    rows = _table_rows(run)
    marks = other_runs(run, runs)
    newest = _newest_errors(run, runs)
    body = []
    for row in fastest_first(rows):
        name = f"`{row['name']}`"
        if row["status"] != "ok":
            body.append([name, changes_text(row, rows), "failed", *["-"] * 6])
            continue
        speedup = row.get("speedup")
        psnr, off = _error_cells(row, error_found(row, run, runs, newest), run, marks)
        body.append(
            [
                name,
                changes_text(row, rows),
                figures.speedup_text(speedup["value"]) if speedup else "-",
                _keep(figures.per_pixel_text(per_pixel(row))),
                _keep(figures.seconds_text(figures.median_wall(row))) + f" at {_size(row)}",
                psnr,
                off,
                allocations_text(row),
                _keep(cpu_text(row)),
            ]
        )
    header = [
        "variant",
        "what it changes",
        "speed-up over naive (per pixel, at the size measured)",
        "time per pixel",
        "median frame (size measured)",
        "PSNR vs naive",
        "pixels off > 1/255 (size compared)",
        "allocations per pixel",
        "CPU: cores used of asked",
    ]
    return Table(header, body, right={2, 3, 4, 5, 6, 7, 8})


def lead(run: Run, runs: Sequence[Run]) -> str:
    """One or two sentences answering: which variant is fastest, by how much, at what cost
    in image error (all read off the run's rows)."""
    rows = [r for r in fastest_first(_table_rows(run)) if r["status"] == "ok"]
    ranked = [r for r in rows if r.get("speedup")]
    naive = next((r for r in rows if r["name"] == "naive"), None)
    if not ranked:
        return ""
    best = ranked[0]
    against = (
        f" against naive's {figures.per_pixel_text(per_pixel(naive))}" if naive is not None else ""
    )
    text = (
        f"**Fastest: `{best['name']}`, {figures.speedup_text(best['speedup']['value'])} "
        f"naive's speed** ({figures.per_pixel_text(per_pixel(best))} per pixel at "
        f"{_size(best)}{against}; the step-by-step ladder measures compiled steps at its own "
        "size, so its factors differ)."
    )
    newest = _newest_errors(run, runs)
    found = error_found(best, run, runs, newest)
    if best["name"] != "naive" and found is not None:
        text += (
            f" Its picture against naive's: PSNR {psnr_text(found.error)}, "
            f"{pixels_off_text(found.error)} pixels off by more than 1/255 "
            f"(at {found.size})."
        )
    tied = tied_with(best, ranked)
    if tied:
        names = ", ".join(f"`{r['name']}`" for r in tied)
        text += (
            f" Not told apart from it by these timings (their fastest and slowest renders "
            f"overlap): {names}."
        )
    exact = next(
        (
            r
            for r in ranked
            if r["name"] != "naive"
            and (e := error_found(r, run, runs, newest)) is not None
            and e.error["pixels_over_one_step"] == 0
        ),
        None,
    )
    if exact is not None and exact is not best:
        text += (
            f" Fastest with no pixel off: `{exact['name']}`, "
            f"{figures.speedup_text(exact['speedup']['value'])}."
        )
    return text


def point_busy(entry: Mapping[str, Any], point: Mapping[str, Any]) -> bool:
    """Whether one measured point of a series (one render) was busy (see ``figures``)."""
    if not point.get("wall") or point.get("cpu") is None:
        return False
    share = float(point["cpu"]) / float(point["wall"])
    return figures.share_busy(str(entry["name"]), share, int(entry.get("cores") or 1))


def point_cpu_text(entry: Mapping[str, Any], point: Mapping[str, Any]) -> str:
    """A series point's ``cores used of asked``, flagged **busy** like a row's."""
    if not point.get("wall") or point.get("cpu") is None:
        return "-"
    asked = figures.cores_asked(str(entry["name"]), int(entry.get("cores") or 1))
    text = f"{float(point['cpu']) / float(point['wall']):.2f} of {asked}"
    return _keep(f"{text} **busy**" if point_busy(entry, point) else text)


def busy_points_text(run: Run, names: Sequence[str]) -> str:
    """What the busy flag means for the named points of a series."""
    load = run["machine"].get("load_average")
    load_text = f" (load average {load[0]:.2f} at the start of the run)" if load else ""
    return (
        f"**Busy:** {', '.join(names)} used under {figures.BUSY_SHARE:.0%} of the cores asked "
        f"for: the machine was busy{load_text}, or the render kept cores idle (a serial part "
        "such as a short frame's setup). One render per point."
    )


def busy_rows(rows: Sequence[Row]) -> list[Row]:
    return [r for r in rows if figures.is_busy(r)]


def busy_text(run: Run, rows: Sequence[Row]) -> str:
    """What the busy flag means, naming the flagged rows (empty when none is)."""
    flagged = busy_rows(rows)
    if not flagged:
        return ""
    load = run["machine"].get("load_average")
    load_text = f" (load average {load[0]:.2f} at the start of the run)" if load else ""
    names = ", ".join(
        f"`{r['name']}` ({figures.cpu_share(r):.2f} of "
        f"{figures.cores_asked(str(r['name']), int(r.get('cores') or 1))})"
        for r in flagged
    )
    they, them, their = ("it", "it", "Its") if len(flagged) == 1 else ("they", "them", "Their")
    return (
        f"**Busy:** {names} used under {figures.BUSY_SHARE:.0%} of the cores {they} asked for: "
        f"the machine was busy for {them}{load_text}, or the render kept cores idle (a serial "
        "part such as a short frame's setup, or fewer jobs than workers). "
        f"{their} times understate what the variant does with the cores to itself."
    )


def notes(run: Run, runs: Sequence[Run]) -> list[str]:
    compare = "x".join(str(v) for v in run["compare_size"])
    marks = other_runs(run, runs)
    by_stem = {str(r["stem"]): r for r in runs}
    quoted = "; ".join(
        f"[{mark}] run `{stem}` ({by_stem[stem]['started'][:10]}, commit "
        f"{(by_stem[stem]['machine'].get('commit') or 'unknown')[:10]})"
        for stem, mark in marks.items()
    )
    sources = (
        f"; where an earlier run of the same scene and settings compared a variant at "
        f"{MEANINGFUL_SIZE[0]}x{MEANINGFUL_SIZE[1]} or more, its figures are quoted, marked "
        f"with that run: {quoted}"
        if marks
        else ""
    )
    samples = run["settings"]["samples"]
    return [
        "Speed-up: throughput (pixels x samples per second) over naive's in this run; rows "
        "measured at different sizes (the budget rule shrinks slow rows) compare per pixel. "
        f"Time per pixel: the median timed render over its pixels, at {samples} sample(s) "
        "per pixel.",
        "Image error: PSNR and the pixels whose largest channel differs by more than 1/255, "
        f"against naive's picture at the size in brackets: this run compared at {compare}"
        + sources
        + ".",
        f"Allocations per pixel: counted in the one untimed render at {compare}, setup "
        "included, over its pixels.",
        "CPU: CPU seconds of the process and its workers per wall second, of the cores the "
        "variant asks for (N for `pooled[workers=N]` and `numba[threads=N]`, every available "
        "core for plain `numba`, 1 otherwise); **busy** where under "
        f"{figures.BUSY_SHARE:.0%} of them.",
    ]


def blocks(run: Run, runs: Sequence[Run], plot: str | None = None) -> list[Block]:
    """The summary section: lead, table, busy note, notes and (if given) the speed-up plot."""
    rows = _table_rows(run)
    if not rows:
        return []
    out: list[Block] = [Heading(2, "Summary")]
    text = lead(run, runs)
    if text:
        out.append(Para(text))
    out.append(table(run, runs))
    busy = busy_text(run, rows)
    if busy:
        out.append(Para(busy))
    out.append(Bullets(notes(run, runs)))
    if plot is not None:
        out.append(Picture(plot, "speed-up over naive"))
    return out
