"""The report's "Soft shadows: light samples against pixel samples" section
(``harness.sections.light_samples.measure``'s entries of a run): the time-error table with the
Pareto front marked, the plot, the pictures, and lines for the terminal."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Bullets, Gallery, Heading, Para, Picture, Table
from harness.document.runinfo import part
from harness.engine import figures
from harness.sections.light_samples.measure import PICTURE_PART, SECTION, TRUTH_PART

Run = Mapping[str, Any]


def entries(run: Run) -> list[Mapping[str, Any]]:
    """The configurations' entries of ``run``, in the order measured."""
    return part(run, SECTION)


def truth_entry(run: Run) -> Mapping[str, Any] | None:
    return next(iter(part(run, SECTION, TRUTH_PART)), None)


def has_section(run: Run) -> bool:
    return truth_entry(run) is not None


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured this section, if any."""
    return next((run for run in reversed(runs) if has_section(run)), None)


def measured(entry: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """The points of ``entry`` that rendered and were compared with the truth."""
    return [p for p in entry.get("points", []) if "wall" in p and p.get("error")]


def front(run: Run) -> set[tuple[str, int]]:
    """(configuration, samples) of the points on the time-error Pareto front."""
    keyed = [(e["name"], p) for e in entries(run) for p in measured(e)]
    points = [(p["wall"], p["error"]["rmse"]) for _, p in keyed]
    return {(keyed[i][0], keyed[i][1]["samples"]) for i in figures.pareto_front(points)}


def _cheapest_under(run: Run, rmse: float) -> tuple[str, Mapping[str, Any]] | None:
    """The fastest point whose RMSE is at most ``rmse``."""
    found = [(e["name"], p) for e in entries(run) for p in measured(e)]
    found = [(name, p) for name, p in found if p["error"]["rmse"] <= rmse]
    return min(found, key=lambda item: item[1]["wall"], default=None)


def _findings(run: Run) -> list[str]:
    """Plain statements read off the measured points (none when too few were measured)."""
    lines: list[str] = []
    on_front = front(run)
    if on_front:
        names = sorted({name for name, _ in on_front})
        lines.append(f"On the Pareto front: {', '.join(names)}.")
    for target in (0.02, 0.01, 0.005):
        cheapest = _cheapest_under(run, target)
        if cheapest is not None:
            name, p = cheapest
            lines.append(
                f"Cheapest render within RMSE {target:g} of the truth: {name} at "
                f"{p['samples']} spp, {figures.seconds_text(p['wall'])}."
            )
    return lines


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    truth = truth_entry(run)
    if truth is None:
        return []
    out: list[Block] = [
        Heading(2, "Soft shadows: light samples against pixel samples"),
        Para(context),
    ]
    if truth.get("status") != "ok":
        out.append(Para(f"Not measured: `{truth['name']}`: {truth.get('error', '')}"))
        return out
    t = truth["points"][0]
    w, h = t["size"]
    measured_entries = [e for e in entries(run) if e.get("points")]
    cells = sorted({int(e["cells"]) for e in measured_entries if "cells" in e})
    counts = sorted({int(p["samples"]) for e in measured_entries for p in e["points"]})
    renders = max((len(p.get("walls", [1])) for e in measured_entries for p in measured(e)),
                  default=1)  # fmt: skip
    out.append(
        Para(
            f"Scene `{truth['scene']}` at {w}x{h} through `{truth['variant']}`, its area lights "
            f"sampled with {', '.join(map(str, cells))} cells, at their centres or jittered "
            "(new jitter for every pixel sample, from the (seed, pixel, sample, light, cell) "
            f"function), at {', '.join(map(str, counts))} samples per pixel. Ground truth: "
            f"{truth['name']} at {t['samples']} spp ({figures.seconds_text(t['wall'])}). "
            f"Time: the median of up to {renders} renders per point, compilation excluded (a "
            "warm-up render first); CPU: the cores the renders got."
        )
    )
    if plot is not None:
        out.append(Picture(plot, "RMSE against render time for each light sampling"))
    on_front = front(run)
    body: list[list[str]] = []
    for entry in entries(run):
        name = entry["name"]
        if entry.get("status") != "ok":
            body.append([name, "-", "failed: " + str(entry.get("error", ""))[:160], *["-"] * 4])
            continue
        for p in entry.get("points", []):
            if p.get("skipped"):
                body.append([name, str(p["samples"]), "skipped: " + p["skipped"], *["-"] * 4])
                continue
            if not p.get("error"):
                continue
            e = p["error"]
            psnr = "∞" if e["psnr"] is None else f"{e['psnr']:.1f}"
            mark = "yes" if (name, p["samples"]) in on_front else ""
            body.append(
                [name, str(p["samples"]), figures.seconds_text(p["wall"]), f"{p['cpu']:.2f}",
                 f"{e['rmse']:.4f}", psnr, mark]
            )  # fmt: skip
    header = ["light cells", "samples/pixel", "time", "CPU (cores)", "RMSE", "PSNR (dB)",
              "Pareto front"]  # fmt: skip
    out.append(Table(header, body, right={1, 2, 3, 4, 5}))
    findings = _findings(run)
    if findings:
        out.append(Bullets(findings))
    out += _gallery(run, truth)
    return out + _picture_blocks(run)


def _gallery(run: Run, truth: Mapping[str, Any]) -> list[Block]:
    """The truth, then one row per cell count: its picture centred and jittered (the
    pictures of the fewest samples per pixel, where the two differ most)."""
    t = truth["points"][0]
    rows: list[tuple[str, list[Picture | None]]] = []
    if t.get("image"):
        truth_picture = Picture(f"runs/{t['image']}", "ground truth", 240)
        rows.append((f"ground truth: {truth['name']}, {t['samples']} spp", [truth_picture, None]))
    by_cells: dict[int, dict[bool, tuple[str, Picture]]] = {}
    for entry in entries(run):
        for p in entry.get("points", []):
            if p.get("image") and "cells" in entry:
                caption = f"{entry['name']}, {p['samples']} spp"
                picture = Picture(f"runs/{p['image']}", caption, 240)
                by_cells.setdefault(int(entry["cells"]), {})[bool(entry.get("jitter"))] = (
                    caption, picture
                )  # fmt: skip
    for cells in sorted(by_cells):
        pair = by_cells[cells]
        spp = next(iter(pair.values()))[0].rsplit(", ", 1)[1]
        rows.append(
            (f"{cells} cell{'s' if cells > 1 else ''} per light, {spp}",
             [pair[False][1] if False in pair else None, pair[True][1] if True in pair else None])
        )  # fmt: skip
    if not rows:
        return []
    return [Gallery(["light sampling", "cell centres", "jittered cells"], rows)]


def _picture_blocks(run: Run) -> list[Block]:
    """The bonus chapters' other scenes, rendered once each (the texture maps)."""
    found = part(run, SECTION, PICTURE_PART)
    rows: list[tuple[str, list[Picture | None]]] = []
    for entry in found:
        if entry.get("status") != "ok":
            rows.append((f"`{entry['name']}`: failed: {entry.get('error', '')}"[:200], [None]))
            continue
        p = entry["points"][0]
        caption = (
            f"`{entry['name']}` through `{entry['variant']}`, {p['size'][0]}x{p['size'][1]}, "
            f"{figures.seconds_text(p['wall'])}"
        )
        rows.append((caption, [Picture(f"runs/{p['image']}", entry["name"], 320)]))
    if not rows:
        return []
    return [
        Heading(3, "The texture-mapping scene"),
        Gallery(["scene", "picture"], rows),
    ]


def console_lines(run: Run) -> list[str]:
    """One line per measured point, for the terminal after ``rtc bench``."""
    lines: list[str] = []
    for entry in entries(run):
        for p in measured(entry):
            lines.append(
                f"light-samples {entry['name']:<14} {p['samples']:>3} spp "
                f"{figures.seconds_text(p['wall']):>9}  RMSE {p['error']['rmse']:.4f}"
            )
    return lines
