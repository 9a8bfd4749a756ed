"""The report's "Cost against scene size" section (``harness.sections.scene_size.measure``'s entries
of a run): whole ``rtc render`` commands beside POV-Ray's, tables of load, prepare and render time
per variant and mesh, the fitted log-log slopes, the OBJ readers' time and memory per mesh, and
lines for the terminal."""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Picture, Table
from harness.engine import figures
from harness.sections.scene_size import anchor
from harness.sections.scene_size.measure import (
    COMMAND_SECTION,
    COMMAND_VARIANT,
    PARSE_SECTION,
    SECTION,
    TRACEMALLOC_MAX,
    slope,
)

Run = Mapping[str, Any]
PHASES = ("render", "prepare", "load")  # the times a slope is fitted to, as the table names them


def entries(run: Run) -> list[Mapping[str, Any]]:
    """The section's variant entries of ``run``, in the order measured."""
    return [e for e in run.get("series", []) if e["section"] == SECTION]


def parse_entry(run: Run) -> Mapping[str, Any] | None:
    return next((e for e in run.get("series", []) if e["section"] == PARSE_SECTION), None)


def command_entry(run: Run) -> Mapping[str, Any] | None:
    return next((e for e in run.get("series", []) if e["section"] == COMMAND_SECTION), None)


def embree_entry(run: Run) -> Mapping[str, Any] | None:
    return next((e for e in run.get("series", []) if e["section"] == anchor.SECTION), None)


def has_section(run: Run) -> bool:
    return bool(entries(run)) or parse_entry(run) is not None or command_entry(run) is not None


def newest(runs: list[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured this section, if any."""
    return next((run for run in reversed(runs) if has_section(run)), None)


def measured(entry: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """The points of ``entry`` that rendered (not skipped, not failed)."""
    return [p for p in entry.get("points", []) if p.get("render") and "error" not in p]


def phase_seconds(point: Mapping[str, Any], phase: str) -> float:
    return float(point["render_median"] if phase == "render" else point[phase])


def slopes(entry: Mapping[str, Any]) -> dict[str, float | None]:
    """The log-log slope of each phase's seconds against the triangle count."""
    points = measured(entry)
    return {
        phase: slope([(p["triangles"], phase_seconds(p, phase)) for p in points])
        for phase in PHASES
    }


def slope_text(value: float | None) -> str:
    return "-" if value is None else f"{value:.2f}"


def _count(value: int) -> str:
    return f"{value:,}"


def _per_triangle(value: float | None, triangles: int) -> str:
    if value is None:
        return "-"
    return f"{figures.bytes_text(value)} ({value / triangles:.0f} B/tri)"


def _render_cells(point: Mapping[str, Any]) -> list[str]:
    walls = point["render"]
    spread = (
        f" ({figures.seconds_text(min(walls))}-{figures.seconds_text(max(walls))}, "
        f"{len(walls)} renders)"
        if len(walls) > 1
        else " (1 render)"
    )
    return [
        figures.seconds_text(point["render_median"]) + spread,
        f"{statistics.median(point.get('cpu') or [0.0]):.2f}",
    ]


def _difference_cell(point: Mapping[str, Any]) -> str:
    found = point.get("difference")
    if not found:
        return "(the reference)" if point.get("render") else "-"
    if found["max_abs"] == 0:
        return f"identical to `{found['against']}`"
    return (
        f"max {found['max_abs']:.2g}, {found['pixels_over_one_step']} px > 1/255 "
        f"vs `{found['against']}`"
    )


def variant_table(run: Run) -> Table:
    body: list[list[str]] = []
    for entry in entries(run):
        name = f"`{entry['name']}`"
        if entry.get("status") != "ok":
            body.append([name, "-", "-", "not run: " + str(entry.get("error", ""))[:160],
                         *["-"] * 6])  # fmt: skip
            continue
        for p in entry.get("points", []):
            mesh, triangles = p["mesh"], _count(p["triangles"])
            if p.get("skipped"):
                body.append([name, mesh, triangles, "skipped: " + p["skipped"], *["-"] * 6])
                continue
            if "error" in p or not p.get("render"):
                body.append([name, mesh, triangles, "failed: " + str(p.get("error"))[:160],
                             *["-"] * 6])  # fmt: skip
                continue
            hierarchy = p.get("hierarchy") or {}
            bvh = (
                f"{figures.seconds_text(hierarchy['seconds'])} ({hierarchy.get('structure')}, "
                f"depth {hierarchy.get('depth')})"
                if hierarchy.get("structure") == "sah" and "seconds" in hierarchy
                else hierarchy.get("structure", "-")
            )
            body.append(
                [
                    name,
                    mesh,
                    triangles,
                    figures.seconds_text(p["load"]),
                    figures.bytes_text(p.get("load_rss")),
                    figures.seconds_text(p["prepare"]),
                    bvh,
                    *_render_cells(p),
                    _difference_cell(p),
                ]
            )
    header = [
        "variant", "mesh", "triangles", "load (parse, group, materials)", "load memory (RSS)",
        "prepare (pack, hierarchy)", "of it the hierarchy", "render (median)", "CPU (cores)",
        "picture",
    ]  # fmt: skip
    return Table(header, body, right={2, 3, 4, 5, 7, 8})


def slope_table(run: Run) -> Table:
    body = []
    for entry in entries(run):
        if entry.get("status") != "ok":
            continue
        points = measured(entry)
        found = slopes(entry)
        span = (
            f"{_count(points[0]['triangles'])} to {_count(points[-1]['triangles'])} "
            f"({len(points)} meshes)"
            if points
            else "-"
        )
        body.append([f"`{entry['name']}`", span, *(slope_text(found[p]) for p in PHASES)])
    return Table(
        ["variant", "triangles", "render slope", "prepare slope", "load slope"],
        body,
        right={2, 3, 4},
    )


def parse_table(entry: Mapping[str, Any]) -> Table:
    body = []
    for p in entry.get("points", []):
        triangles = int(p["triangles"])
        if "error" in p:
            body.append([p["mesh"], _count(triangles), "failed: " + str(p["error"])[:160],
                         *["-"] * 7])  # fmt: skip
            continue
        traced = p.get("tracemalloc") or {}
        arrays = p.get("arrays_median")
        body.append(
            [
                p["mesh"],
                _count(triangles),
                figures.bytes_text(p.get("bytes")),
                "-" if arrays is None else figures.seconds_text(arrays),
                _per_triangle(p.get("arrays_rss_growth"), triangles),
                figures.seconds_text(p["parse_median"])
                + f" ({len(p['parse'])} parse{'s' if len(p['parse']) > 1 else ''})",
                f"{p['parse_median'] / triangles * 1e6:.2f}",
                _per_triangle(p.get("rss_growth"), triangles),
                _per_triangle(traced.get("current"), triangles),
                _per_triangle(traced.get("peak"), triangles),
            ]
        )
    return Table(
        [
            "mesh", "triangles", "file", "read_mesh (median)", "its RSS growth",
            "parse_obj_file (median)", "µs per triangle", "RSS growth (peak)",
            "tracemalloc: kept", "tracemalloc: peak",
        ],
        body,
        right={1, 2, 3, 4, 5, 6, 7, 8, 9},
    )  # fmt: skip


def _seconds(value: float | None) -> str:
    return "-" if value is None else figures.seconds_text(value)


def _ratio(ours: Mapping[str, Any], theirs: Mapping[str, Any], key: str) -> str:
    a, b = ours.get(key), theirs.get(key)
    return f"{float(a) / float(b):.2f}x" if a and b else "-"


def command_table(entry: Mapping[str, Any]) -> Table:
    """Per mesh: our whole command and POV-Ray's, their ratios."""
    body = []
    for p in entry.get("points", []):
        head = [p["mesh"], _count(int(p["triangles"]))]
        if "error" in p:
            body.append([*head, "failed: " + str(p["error"])[:160], *["-"] * 6])
            continue
        ours, theirs = p.get("ours") or {}, p.get("povray") or {}
        if "error" in ours:
            body.append([*head, "failed: " + str(ours["error"])[:160], *["-"] * 6])
            continue
        pov = (
            f"{_seconds(theirs['wall'])} (parse {_seconds(theirs.get('parse'))}, trace "
            f"{_seconds(theirs.get('trace'))})"
            if theirs.get("wall")
            else str(theirs.get("error", "-"))[:160]
        )
        body.append(
            [
                *head,
                _seconds(ours.get("wall")),
                figures.bytes_text(ours.get("peak")),
                pov,
                figures.bytes_text(theirs.get("peak")),
                _ratio(ours, theirs, "wall"),
                _ratio(ours, theirs, "peak"),
            ]
        )
    return Table(
        [
            "mesh", "triangles", f"rtc render ({COMMAND_VARIANT}), median", "its peak memory",
            "POV-Ray, median", "its peak memory", "time: ours / POV-Ray",
            "memory: ours / POV-Ray",
        ],
        body,
        right={1, 2, 3, 5, 6, 7},
    )  # fmt: skip


def _rate(rays: float, seconds: float | None) -> str:
    return "-" if not seconds else f"{rays / seconds / 1e6:.2f} M/s"


def embree_table(run: Run, found: Mapping[str, Any]) -> Table:
    """Per mesh: Embree's primary rays (intersection only) and each variant's whole render
    of the same mesh and camera, as rays per second and as a time per ray over Embree's."""
    s = run["settings"]
    pixels = int(s["size"][0]) * int(s["size"][1])
    renders = {
        (e["name"], p["mesh"]): p for e in entries(run) if e.get("status") == "ok"
        for p in measured(e)
    }  # fmt: skip
    body = []
    for p in found.get("points", []):
        head = [p["mesh"], _count(int(p["triangles"]))]
        if "error" in p:
            body.append([*head, "failed: " + str(p["error"])[:160], "-", "-", "-"])
            continue
        seconds = float(p["cpu_median"])
        ours = [
            f"`{variant}` {_rate(pixels * int(s['samples']), point['render_median'])} "
            f"({float(point['render_median']) / (seconds * int(s['samples'])):.1f}x)"
            for (variant, mesh), point in renders.items() if mesh == p["mesh"]
        ]  # fmt: skip
        body.append([
            *head, f"{_seconds(seconds)} ({_rate(int(p['rays']), seconds)})",
            f"{int(p['hits']):,} of {int(p['rays']):,}", "; ".join(ours) or "-",
        ])  # fmt: skip
    return Table(
        ["mesh", "triangles", "Embree: primary rays, CPU (rays/s)", "rays that hit",
         "our whole renders: rays/s (time per ray over Embree's)"],
        body, right={1, 2, 3},
    )  # fmt: skip


def embree_blocks(run: Run) -> list[Block]:
    """The anchor's paragraph and table, or the line saying why there is none."""
    found = embree_entry(run)
    if found is None:
        return []
    out: list[Block] = [Heading(3, "Beside Embree")]
    if found.get("status") != "ok":
        out.append(Para(f"**No Embree in this run:** {found.get('error', 'not run')}."))
        return out
    out += [
        Para(
            f"{found.get('version')} (Intel's ray-intersection library, C++ and SIMD) on the "
            "same mesh and camera, in the same run, one thread, a fresh process per mesh: "
            "every pixel's primary ray, the nearest hit only (no shading, no shadow rays), "
            "its hierarchy built before the clock starts; median CPU seconds. Our renders "
            "beside it are whole renders (shading, the floor, shadow rays), so the factor "
            "is an upper bound on the gap between the two kernels."
        ),
        embree_table(run, found),
    ]
    return out


def blocks(run: Run, plot: Any, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The report's section for ``run`` (nothing if it has none); ``plot``: the plot's path
    relative to the results folder, or None; ``context``: the machine and run line."""
    if not has_section(run):
        return []
    s = run["settings"]
    threads = s.get("threads") or "all the process may use"
    out: list[Block] = [Heading(2, "Cost against scene size"), Para(context)]
    out.append(
        Para(
            f"One scene (a floor, a light, a noisy torus of flat triangles written by "
            f"`harness/scenery/make_meshes.py`) at {s['size'][0]}x{s['size'][1]}, {s['samples']} "
            f"sample(s) per pixel, depth {s['depth']}, CPUs: {threads}; each (variant, mesh) in "
            f"a fresh process, after a warm-up render of the smallest mesh at 8x6 (compilation "
            f"excluded). Render: `render_into` of a prepared frame, median of up to "
            f"{s['repeat']} renders; prepare: the frame's packing and hierarchy, once; load: "
            f"`load_scene` (the OBJ parser, the group, the material given to every triangle). "
            f"A point whose render the previous one predicts (linearly) to exceed the budget "
            f"({s['budget'] or 0:g} s) is skipped. Load memory: the resident set's high-water "
            f"mark after the load less the resident set before it (a small mesh may fit in "
            f"memory the warm-up freed). Timings on a shared machine are noisy: medians."
        )
    )
    command = command_entry(run)
    if command is not None:
        povray = command.get("povray")
        out += [
            Heading(3, "Whole commands beside POV-Ray"),
            Para(
                f"`rtc render --variant {COMMAND_VARIANT}` as a user runs it, a fresh process "
                "from start to exit (reading the scene and the OBJ file, packing, building the "
                "hierarchy, rendering, writing the PNG), after one warm-up command that "
                "compiles what the scene needs; "
                + (
                    f"{povray} on the same scene (the mesh as a `mesh2`, the same camera, "
                    f"light, floor and colours), {command.get('threads')} threads each, in "
                    "turns; medians. Peak memory: the kernel's accounting of each process."
                    if povray
                    else f"no POV-Ray in this run: {command.get('povray_missing')}."
                )
            ),
            command_table(command),
        ]
    if plot is not None:
        out.append(Picture(str(plot), "render time against triangle count"))
    out += embree_blocks(run)
    if entries(run):
        out += [
            variant_table(run),
            Para(
                "Slopes of log(seconds) against log(triangles), least squares over the meshes "
                "measured: about 1 means the cost grows linearly with the triangles (every "
                "ray meets every triangle), 0 to 0.2 that it barely grows (a hierarchy: "
                "logarithmic, on top of a cost per pixel that does not change)."
            ),
            slope_table(run),
        ]
    parse = parse_entry(run)
    if parse is not None:
        out += [
            Heading(3, "Reading the OBJ files"),
            Para(
                "Each OBJ file alone, one fresh process per mesh: `read_mesh`, which the scene "
                "loader uses (the model as arrays, read by compiled code), and chapter 15's "
                "`parse_obj_file` (the book's parser: an object per triangle). RSS growth: the "
                "resident set's high-water mark during the first read less the resident set "
                "before it (VmHWM reset before it). tracemalloc: the bytes of Python objects "
                "the book's parse left (the parser and its triangles) and its peak, measured "
                f"in a second parse, up to {TRACEMALLOC_MAX:,} triangles (it slows the parse "
                "about 6x)."
            ),
            parse_table(parse),
        ]
    return out


def console_lines(run: Run) -> list[str]:
    """A few lines for the terminal after ``rtc bench``."""
    lines: list[str] = []
    command = command_entry(run)
    for p in (command or {}).get("points", []):
        ours, theirs = p.get("ours") or {}, p.get("povray") or {}
        lines.append(
            f"rtc render {p['mesh']:<14} {_seconds(ours.get('wall')):>9} "
            f"peak {figures.bytes_text(ours.get('peak'))}"
            + (
                f"; POV-Ray {_seconds(theirs.get('wall'))} peak "
                f"{figures.bytes_text(theirs.get('peak'))}"
                if theirs.get("wall")
                else ""
            )
        )
    found = embree_entry(run)
    if found is not None and found.get("status") != "ok":
        lines.append(f"Embree: not run: {found.get('error')}")
    for p in (found or {}).get("points", []):
        lines.append(
            f"Embree {p['mesh']:<14} primary rays "
            + (f"failed: {p['error']}" if "error" in p else f"{_seconds(p['cpu_median']):>9}")
        )
    parse = parse_entry(run)
    if parse is not None:
        for p in parse.get("points", []):
            if "error" in p:
                lines.append(f"parse {p['mesh']}: failed: {p['error']}")
                continue
            lines.append(
                f"parse {p['mesh']:<14} {p['triangles']:>9,} triangles "
                f"{figures.seconds_text(p['parse_median']):>9}  RSS +"
                f"{figures.bytes_text(p.get('rss_growth'))}"
            )
    for entry in entries(run):
        if entry.get("status") != "ok":
            lines.append(f"{entry['name']}: not run: {entry.get('error')}")
            continue
        for p in entry.get("points", []):
            head = f"{entry['name']:<24} {p['mesh']:<14}"
            if p.get("skipped"):
                lines.append(f"{head} skipped (over the budget)")
            elif "error" in p or not p.get("render"):
                lines.append(f"{head} failed: {p.get('error')}")
            else:
                lines.append(
                    f"{head} load {figures.seconds_text(p['load']):>8}  prepare "
                    f"{figures.seconds_text(p['prepare']):>8}  render "
                    f"{figures.seconds_text(p['render_median']):>8}"
                )
        found = slopes(entry)
        lines.append(
            f"{entry['name']:<24} slopes: render {slope_text(found['render'])}, prepare "
            f"{slope_text(found['prepare'])}, load {slope_text(found['load'])}"
        )
    return lines
