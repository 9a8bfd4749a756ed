"""Where the time goes, shown (``harness.sections.profile.measure``'s entries): the text ``rtc
profile`` prints, the report's "Where the time goes" section and the lines ``rtc bench`` prints."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Bullets, Heading, Para, Table
from harness.engine import figures
from harness.sections.profile.measure import REPORT_TOP
from harness.sections.profile.profiler import FLAME_SECONDS, SECTION
from harness.sections.profile.stats import STAGE_NAMES, findings

Run = Mapping[str, Any]
Entry = Mapping[str, Any]


def _percent(part: float, whole: float) -> str:
    return f"{100 * part / whole:.1f}%" if whole > 0 else "-"


def _seconds(value: float) -> str:
    return figures.seconds_text(value)


def pooled_note(entry: Entry) -> str | None:
    """What a wrapper's profile is of: its parent process (``pooled``)."""
    if str(entry.get("name", "")).startswith("pooled"):
        return (
            "pooled: this is the parent process; its workers trace the image (the flame "
            "graph follows them, cProfile sees the parent waiting for their results; "
            "profile the inner variant to see the work of a pixel)"
        )
    return None


# ---------------------------------------------------------------------------- rtc profile


def stage_lines(entry: Entry) -> list[str]:
    stages: Mapping[str, float] = entry.get("stages") or {}
    wall = float(entry.get("wall") or 0.0)
    head = "stages, timed without a profiler in the process"
    if entry.get("flame"):
        head += f" (py-spy sampled it from outside, {entry.get('flame_rate')} times a second)"
    if entry.get("compiled"):
        head += "; the render is compiled code, so these are the figures"
    lines = [head + ":"]
    notes = {
        "compile": entry.get("kernels"),
        "trace": (
            f"a second trace of the same frame: {_seconds(entry['trace_again'])}"
            if "trace_again" in entry
            else None
        ),
    }
    for key, seconds in stages.items():
        note = notes.get(key)
        lines.append(
            f"  {STAGE_NAMES.get(key, key):<36} {_seconds(seconds):>10} "
            f"{_percent(seconds, wall):>7}" + (f"   {note}" if note else "")
        )
    lines.append(
        f"  {'the stages together':<36} {_seconds(sum(stages.values())):>10}   "
        f"(load to encode: {_seconds(wall)})"
    )
    return lines


def function_table(rows: list[Mapping[str, Any]], total: float, column: str) -> list[str]:
    """pstats' columns: calls, own and cumulative seconds, the share of ``column`` (own or
    cum) in ``total``, and the function."""
    share = "own %" if column == "own" else "cum %"
    lines = [f"  {'calls':>15} {'own s':>9} {'cum s':>9} {share:>7}  function"]
    for row in rows:
        lines.append(
            f"  {row['calls']:>15} {row['own']:>9.4f} {row['cum']:>9.4f} "
            f"{_percent(row[column], total):>7}  {row['function']}"
        )
    return lines


def text(entry: Entry, top: int) -> list[str]:
    """What ``rtc profile`` prints for a profile's entry
    (``harness.sections.profile.measure.profile``)."""
    lines = stage_lines(entry)
    profile = entry.get("cprofile")
    if profile:
        total = float(profile["total"])
        trace = float((entry.get("stages") or {}).get("trace") or 0.0)
        slower = f", {profile['seconds'] / trace:.1f}x the trace above" if trace > 0 else ""
        pixels = int(entry.get("pixels") or 1)
        lines += [
            "",
            f"the render (prepare and trace) under cProfile: {_seconds(profile['seconds'])}"
            f"{slower}; {profile['calls']:,} calls ({profile['calls'] / pixels:,.0f} per pixel) "
            f"of {profile['functions']} functions",
            f"top {min(top, len(profile['top_own']))} functions by own time (% of the render):",
            *function_table(profile["top_own"][:top], total, "own"),
            "",
            f"top {min(top, len(profile['top_cum']))} functions by cumulative time "
            "(the function and its callees):",
            *function_table(profile["top_cum"][:top], total, "cum"),
        ]
    elif entry.get("cprofile_skipped"):
        lines += ["", f"cProfile: not run: {entry['cprofile_skipped']}"]
    lines += ["", f"what it shows: {findings(entry)}"]
    note = pooled_note(entry)
    if note:
        lines.append(note)
    lines.append("")
    if entry.get("flame"):
        renders = int(entry.get("renders") or 1)
        repeated = (
            f"{renders} renders (repeated until {FLAME_SECONDS:g} s of rendering were sampled)"
            if renders > 1
            else "the render"
        )
        lines.append(
            f"flame graph: {entry['flame']} (py-spy, the whole process: start-up, the scene's "
            f"load and {repeated}; open it in a browser: click a frame to zoom, Search "
            "(top right) shows the share of a function's name)"
        )
    elif entry.get("flame_error"):
        lines.append(f"flame graph: none: {entry['flame_error']}")
    if entry.get("pstats"):
        lines.append(
            f"cProfile statistics: {entry['pstats']} (python -m pstats FILE, or snakeviz FILE)"
        )
    if entry.get("image"):
        lines.append(f"picture: {entry['image']}")
    return lines


# ---------------------------------------------------------------------------- the report


def entries(run: Run) -> list[Entry]:
    """The section's entries of ``run``, in the order measured."""
    return [e for e in run.get("series", []) if e["section"] == SECTION]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that profiled, if any."""
    return next((run for run in reversed(runs) if entries(run)), None)


def _link(entry: Entry) -> str:
    flame = entry.get("flame")
    if flame:
        return f"Flame graph (py-spy, SVG): [runs/{flame}](runs/{flame})."
    return f"No flame graph: {entry.get('flame_error', 'not sampled')}."


def _variant_blocks(entry: Entry) -> list[Block]:
    name = entry["name"]
    out: list[Block] = [Heading(3, f"`{name}`")]
    if entry.get("status") != "ok":
        return [*out, Para(f"Not profiled: {entry.get('error', entry.get('status'))}")]
    stages: Mapping[str, float] = entry.get("stages") or {}
    wall = float(entry.get("wall") or 0.0)
    stage_text = ", ".join(
        f"{STAGE_NAMES.get(k, k)} {_seconds(v)} ({_percent(v, wall)})" for k, v in stages.items()
    )
    out.append(Para(f"Stages, without a profiler: {stage_text}. {_link(entry)}"))
    profile = entry.get("cprofile")
    if profile:
        total = float(profile["total"])
        body = [
            [
                f"`{row['function']}`",
                row["calls"],
                f"{row['own']:.4f}",
                _percent(row["own"], total),
                f"{row['cum']:.4f}",
                _percent(row["cum"], total),
            ]
            for row in profile["top_own"][:REPORT_TOP]
        ]
        header = ["function", "calls", "own s", "own % of the render", "cum s", "cum %"]
        out.append(Table(header, body, right={1, 2, 3, 4, 5}))
    elif entry.get("cprofile_skipped"):
        out.append(Para(f"No cProfile table: {entry['cprofile_skipped']}."))
    return out


def _prepare_seconds(stages: Mapping[str, float]) -> float:
    return float(stages.get("prepare", 0.0) + stages.get("pack", 0.0) + stages.get("compile", 0.0))


def overview(found: list[Entry]) -> Table:
    """One row per variant: its stages (trace against the first variant's) and what its
    profile shows in figures."""
    ok = [e for e in found if e.get("status") == "ok" and e.get("stages")]
    first = next((float(e["stages"].get("trace", 0.0)) for e in ok), 0.0)
    body = []
    for entry in ok:
        stages = entry["stages"]
        trace = float(stages.get("trace", stages.get("render", 0.0)))
        profile = entry.get("cprofile") or {}
        total = float(profile.get("total") or 0.0)
        hot = profile.get("hot")
        pixels = int(entry.get("pixels") or 1)
        body.append(
            [
                f"`{entry['name']}`",
                _seconds(float(stages.get("load", 0.0))),
                _seconds(_prepare_seconds(stages)),
                _seconds(trace),
                f"{first / trace:,.0f}x" if trace > 0 and first > 0 else "-",
                _seconds(float(stages.get("encode", 0.0))),
                f"{profile['calls'] / pixels:,.0f}" if profile else "-",
                _percent(float(profile.get("constructors", 0.0)), total) if total else "-",
                (
                    f"{_percent(float(hot['cum']), total)} in `{hot['function']}`"
                    if hot and total
                    else "-"
                ),
            ]
        )
    header = [
        "variant", "load", "prepare (pack, compile)", "trace",
        f"trace: speed-up over `{ok[0]['name']}`" if ok else "trace: speed-up",
        "encode", "calls per pixel", "building objects", "the hottest chain (with callees)",
    ]  # fmt: skip
    return Table(header, body, right={1, 2, 3, 4, 5, 6, 7})


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The report's "Where the time goes" section for ``run`` (nothing if it has none);
    ``context``: the machine and run line."""
    found = entries(run)
    if not found:
        return []
    first = next((e for e in found if e.get("size")), found[0])
    size = first.get("size") or ["?", "?"]
    out: list[Block] = [
        Heading(2, "Where the time goes"),
        Para(context),
        Para(
            f"Each variant renders the `{first.get('scene', '?')}` scene once at "
            f"{size[0]}x{size[1]} ({first.get('samples', 1)} sample per pixel), in fresh "
            "processes (`rtc profile` does the same for any scene and variant). Stages: "
            "the render timed stage by stage, without a profiler in the process, sampled from "
            "outside by py-spy for the flame graph. Functions: the render (prepare and trace) "
            f"again under cProfile, the top {REPORT_TOP} by own time, as a share of the "
            "render's time under cProfile. cProfile pays for every call, so it makes code of "
            "many small calls look costlier than it is; the flame graph, sampled, does not. "
            "A compiled render (`numba`) is one call for cProfile: its stages are the figures."
        ),
        overview(found),
        Para("What the figures show, per variant:"),
        Bullets(console_lines(run)),
    ]
    for entry in found:
        out += _variant_blocks(entry)
    return out


def console_lines(run: Run) -> list[str]:
    """One line per profiled variant, for the terminal after ``rtc bench``."""
    return [
        findings(e) if e.get("status") == "ok" else f"{e['name']}: not profiled: {e.get('error')}"
        for e in entries(run)
    ]
