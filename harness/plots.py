"""The report's plots (matplotlib, Agg backend): error against time with the Pareto front,
time against pixel count, throughput against worker or thread count, speed-ups."""

from __future__ import annotations

import io
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import matplotlib

from groundwork.files import write_atomically

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from harness import figures, summary


def _save(figure: Figure, path: Path) -> Path:
    """Write ``figure`` as a PNG atomically."""
    buffer = io.BytesIO()
    try:
        figure.savefig(buffer, format="png", dpi=110, bbox_inches="tight")
    finally:
        plt.close(figure)
    return write_atomically(path, buffer.getvalue())


def _caption(run: Mapping[str, Any]) -> str:
    m = run["machine"]
    return f"{m['cpu_model']}, {m['cores_available']} cores, Python {m['python']}"


def sweep_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Each (configuration, samples) as a point of time against RMSE from the ground truth;
    the Pareto front (nothing both faster and more accurate) joined by a line."""
    from harness.runinfo import part

    entries = [e for e in part(run, "sweep") if e["status"] == "ok"]
    points: list[tuple[float, float]] = []
    labels: list[str] = []
    figure, axes = plt.subplots(figsize=(7.5, 5))
    for entry in entries:
        measured = [p for p in entry["points"] if "wall" in p and p.get("error")]
        if not measured:
            continue
        xs = [p["wall"] for p in measured]
        ys = [max(p["error"]["rmse"], 1e-7) for p in measured]
        axes.plot(xs, ys, marker="o", label=entry["name"])
        for p, x, y in zip(measured, xs, ys, strict=True):
            axes.annotate(
                str(p["samples"]), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7
            )
            points.append((x, y))
            labels.append(f"{entry['name']} {p['samples']} spp")
    if not points:
        plt.close(figure)
        return None
    front = sorted((points[i] for i in figures.pareto_front(points)), key=lambda p: p[0])
    axes.plot(
        [p[0] for p in front],
        [p[1] for p in front],
        color="black",
        linestyle="--",
        linewidth=1.2,
        label="Pareto front",
        zorder=0,
    )
    axes.scatter(
        [p[0] for p in front],
        [p[1] for p in front],
        s=120,
        facecolors="none",
        edgecolors="black",
        zorder=3,
    )
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("render time (s)")
    axes.set_ylabel("RMSE against the ground truth")
    truth = next(iter(part(run, "sweep", "truth")), None)
    if truth is not None:
        w, h = truth["points"][0]["size"]
        axes.set_title(
            f"Error against time, {w}x{h}, labels = samples per pixel\n"
            f"ground truth: {truth['name']} at {truth['points'][0]['samples']} spp; "
            f"{_caption(run)}",
            fontsize=9,
        )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return _save(figure, path)


def scaling_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The scaling section's two panels, side by side where the run has both: time against
    pixel count (``_pixels_axes``) and throughput against workers or threads
    (``_threads_axes``)."""
    from harness.runinfo import part, rows

    sizes = [e for e in part(run, "scaling", "sizes") if e["status"] == "ok"]
    sizes = [e for e in sizes if any("wall" in p for p in e["points"])]
    threads = [r for r in rows(run, "scaling") if r["status"] == "ok"]
    groups: dict[str, list[Mapping[str, Any]]] = {}
    for row in threads:
        groups.setdefault(row["group"], []).append(row)
    groups = {k: v for k, v in groups.items() if any(r["count"] == 1 for r in v)}
    panels = int(bool(sizes)) + int(bool(groups))
    if not panels:
        return None
    figure, found = plt.subplots(1, panels, figsize=(7.5 * panels, 5), squeeze=False)
    axes = list(found[0])
    if sizes:
        _pixels_axes(run, sizes, axes.pop(0))
    if groups:
        _threads_axes(run, groups, axes.pop(0))
    return _save(figure, path)


def _pixels_axes(run: Mapping[str, Any], entries: list[Mapping[str, Any]], axes: Any) -> None:
    """Render time against pixel count, one line per variant (log-log)."""
    any_busy = False
    for entry in entries:
        measured = [p for p in entry["points"] if "wall" in p]
        xs = [p["size"][0] * p["size"][1] for p in measured]
        ys = [p["wall"] for p in measured]
        (line,) = axes.plot(xs, ys, marker="o", label=entry["name"])
        for x, y, p in zip(xs, ys, measured, strict=True):
            if summary.point_busy(entry, p):  # hollow, drawn over the filled marker
                any_busy = True
                axes.plot([x], [y], marker="o", markersize=8, color=line.get_color(),
                          markerfacecolor="white")  # fmt: skip
    if any_busy:
        note = f"hollow: busy (CPU under {figures.BUSY_SHARE:.0%} of the cores asked)"
        axes.plot([], [], marker="o", linestyle="none", color="gray", markerfacecolor="white",
                  label=note)  # fmt: skip
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("pixels")
    axes.set_ylabel("render time (s)")
    axes.set_title(
        f"Time against pixel count (points over the budget skipped)\n{_caption(run)}", fontsize=9
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)


def _threads_axes(
    run: Mapping[str, Any], groups: dict[str, list[Mapping[str, Any]]], axes: Any
) -> None:
    """Throughput relative to one worker or thread against the count, one line per variant
    option, with the linear ideal dotted (absolute MRay/s are in the report's table)."""
    counts = sorted({r["count"] for members in groups.values() for r in members})
    axes.plot(counts, counts, linestyle=":", color="gray", label="linear (ideal)")
    any_busy = False
    for label, members in groups.items():
        members = sorted(members, key=lambda r: r["count"])
        one = figures.mrays(next(r for r in members if r["count"] == 1))
        xs = [r["count"] for r in members]
        ys = [figures.mrays(r) / one for r in members]
        (line,) = axes.plot(xs, ys, marker="o", label=f"{label}: {one:.3g} MRay/s with 1")
        busy = [figures.is_busy(r) for r in members]
        any_busy = any_busy or any(busy)
        for x, y, hollow in zip(xs, ys, busy, strict=True):
            if hollow:  # drawn over the filled marker
                axes.plot([x], [y], marker="o", markersize=8, color=line.get_color(),
                          markerfacecolor="white")  # fmt: skip
                axes.annotate("busy", (x, y), textcoords="offset points", xytext=(6, -10),
                              fontsize=7, color=line.get_color())  # fmt: skip
    if any_busy:
        note = f"hollow: busy (CPU under {figures.BUSY_SHARE:.0%} of the count)"
        axes.plot([], [], marker="o", linestyle="none", color="gray", markerfacecolor="white",
                  label=note)  # fmt: skip
    axes.set_xlabel("workers / threads")
    axes.set_ylabel("throughput relative to 1 worker / thread")
    axes.set_xticks(counts)
    axes.set_title(
        f"Throughput against parallelism (sizes may differ: per-pixel ratios)\n{_caption(run)}",
        fontsize=9,
    )
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=7)


def speedup_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The table's speed-ups over naive as horizontal bars (log scale)."""
    rows = [r for r in run["rows"] if r["section"] == "table" and r.get("speedup")]
    if not rows:
        return None
    rows.sort(key=lambda r: -r["speedup"]["value"])  # fastest first (at the top)
    figure, axes = plt.subplots(figsize=(7.5, 0.4 * len(rows) + 1.2))
    names = [r["name"] for r in rows]
    values = [r["speedup"]["value"] for r in rows]
    busy = [figures.is_busy(r) for r in rows]
    axes.barh(
        names, values, color=["white" if b else "#4477aa" for b in busy],
        edgecolor="#4477aa", hatch=["//" if b else "" for b in busy],
    )  # fmt: skip
    axes.set_xscale("log")
    axes.invert_yaxis()
    axes.set_xlabel("speed-up over naive (throughput ratio, log scale)")
    for i, (row, value, hollow) in enumerate(zip(rows, values, busy, strict=True)):
        mark = "" if row["speedup"]["basis"] == "same size" else " *"
        axes.annotate(
            f"{figures.speedup_text(value)}{mark}{' busy' if hollow else ''}",
            (value, i),
            xytext=(3, -3),
            textcoords="offset points",
            fontsize=7,
        )
    hollow_note = (
        f"\nhollow bars: busy (CPU under {figures.BUSY_SHARE:.0%} of the cores asked)"
        if any(busy)
        else ""
    )
    axes.set_title(
        "Speed-up over naive, same run (* measured at another size than naive: per pixel)"
        f"{hollow_note}\n" + _caption(run),
        fontsize=9,
    )
    axes.grid(True, axis="x", which="both", alpha=0.3)
    return _save(figure, path)


def scene_size_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Render time against triangle count (log-log), one line per variant with its fitted
    slope in the legend, and a dotted line of slope 1 (linear) for comparison."""
    from harness import scene_size_report as ssr

    lines = [(e["name"], ssr.measured(e), ssr.slopes(e)["render"]) for e in ssr.entries(run)]
    lines = [(name, points, found) for name, points, found in lines if points]
    if not lines:
        return None
    figure, axes = plt.subplots(figsize=(7.5, 5))
    for name, points, found in lines:
        xs = [p["triangles"] for p in points]
        ys = [p["render_median"] for p in points]
        axes.plot(xs, ys, marker="o", label=f"{name} (slope {ssr.slope_text(found)})")
    _, first, _ = max(lines, key=lambda line: len(line[1]))
    x0, y0 = first[0]["triangles"], first[0]["render_median"]
    x1 = max(p["triangles"] for _, points, _ in lines for p in points)
    axes.plot([x0, x1], [y0, y0 * x1 / x0], linestyle=":", color="gray", label="slope 1 (linear)")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("triangles")
    axes.set_ylabel("render time (s), frame prepared")
    w, h = run["settings"]["size"]
    axes.set_title(
        f"Render time against scene size, {w}x{h}, {run['settings']['samples']} spp "
        f"(points over the budget skipped)\n{_caption(run)}",
        fontsize=9,
    )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return _save(figure, path)


def light_samples_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Soft shadows: RMSE against render time, one line per light sampling (cells, jitter)
    through its samples per pixel, the Pareto front circled (log-log)."""
    from harness import light_samples_report as lsr

    entries = [(e, lsr.measured(e)) for e in lsr.entries(run)]
    entries = [(e, points) for e, points in entries if points]
    if not entries:
        return None
    on_front = lsr.front(run)
    figure, axes = plt.subplots(figsize=(7.5, 5))
    front_points: list[tuple[float, float]] = []
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    cell_counts = sorted({int(e.get("cells", 0)) for e, _ in entries})
    for entry, points in entries:
        xs = [p["wall"] for p in points]
        ys = [max(p["error"]["rmse"], 1e-7) for p in points]
        jittered = bool(entry.get("jitter"))
        color = palette[cell_counts.index(int(entry.get("cells", 0))) % len(palette)]
        axes.plot(
            xs, ys, marker="o" if jittered else "s", linestyle="-" if jittered else "--",
            color=color, label=entry["name"],
        )  # fmt: skip
        for p, x, y in zip(points, xs, ys, strict=True):
            axes.annotate(
                str(p["samples"]), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7
            )
            if (entry["name"], p["samples"]) in on_front:
                front_points.append((x, y))
    front_points.sort()
    axes.plot(
        [x for x, _ in front_points], [y for _, y in front_points], color="black",
        linestyle=":", linewidth=1.2, label="Pareto front", zorder=0,
    )  # fmt: skip
    axes.scatter(
        [x for x, _ in front_points], [y for _, y in front_points], s=120,
        facecolors="none", edgecolors="black", zorder=3,
    )  # fmt: skip
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("render time (s)")
    axes.set_ylabel("RMSE against the ground truth")
    truth = lsr.truth_entry(run)
    if truth is not None and truth.get("points"):
        t = truth["points"][0]
        axes.set_title(
            f"Soft shadows: light cells (colour; dashed: centred, solid: jittered) against "
            f"samples per pixel (labels), {t['size'][0]}x{t['size'][1]}\n"
            f"ground truth {truth['name']} at {t['samples']} spp through {truth['variant']}; "
            f"{_caption(run)}",
            fontsize=9,
        )
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    return _save(figure, path)


def history_plot(runs: list[Mapping[str, Any]], path: Path) -> Path | None:
    """Each table variant's mean time per pixel across the runs (oldest left, labelled by
    short commit), log scale; a ring where the change against the variant's previous run is
    significant (``harness.compare``: Student's t-test, 95%, the same size in both): red and
    solid when slower, green and dashed when faster; hollow markers: busy (the row did not
    get the cores it asked for)."""
    from harness import compare

    series = [s for s in compare.history(runs) if s.points]
    if not series:
        return None
    used = sorted({p.run for s in series for p in s.points})
    column = {run: i for i, run in enumerate(used)}
    figure, axes = plt.subplots(figsize=(9.5, 5.5))
    colours = [plt.get_cmap("tab10")(k) for k in range(10)]
    markers = "osD^v<>ph*"
    rings: dict[str, list[tuple[float, float]]] = {"slower": [], "faster": []}
    for i, found in enumerate(series):
        xs = [column[p.run] for p in found.points]
        ys = [p.measured.per_pixel for p in found.points]
        colour = colours[i % len(colours)]
        marker = markers[(i + 3 * (i // len(colours))) % len(markers)]
        label = found.name + (f" ({found.scene})" if found.scene != "reference" else "")
        axes.plot(xs, ys, linestyle="-" if i < len(colours) else "--", linewidth=1,
                  label=label, color=colour, marker=marker, markersize=5)  # fmt: skip
        busy = [(x, y) for x, y, p in zip(xs, ys, found.points, strict=True) if p.measured.busy]
        if busy:
            axes.plot([x for x, _ in busy], [y for _, y in busy], linestyle="none",
                      markerfacecolor="white", color=colour, marker=marker,
                      markersize=5)  # fmt: skip
        for x, y, point in zip(xs, ys, found.points, strict=True):
            change = point.change
            if change is not None and change.test.significant:
                rings[change.verdict].append((x, y))
    for verdict, edge, line in (("slower", "#cc3311", "-"), ("faster", "#228833", "--")):
        if rings[verdict]:
            axes.scatter(
                [x for x, _ in rings[verdict]], [y for _, y in rings[verdict]], s=190,
                facecolors="none", edgecolors=edge, linewidths=1.4, linestyle=line,
                zorder=4, label=f"significantly {verdict} than its previous run",
            )  # fmt: skip
    axes.set_yscale("log")
    axes.set_xticks(range(len(used)))
    labels = []
    for r in used:
        started = str(runs[r].get("started", ""))[5:16].replace("T", " ")
        labels.append(f"{compare.commit_label(runs[r])}\n{started}")
    axes.set_xticklabels(labels, fontsize=7)
    axes.set_xlim(-0.5, len(used) - 0.5)
    axes.set_xlabel("run (short commit, * dirty tree; start time UTC), oldest first")
    axes.set_ylabel("mean time per pixel (s, log scale)")
    axes.set_title(
        "Time per pixel of each variant across runs; rings: a significant change from the "
        "variant's previous run\n(Student's t-test on the timed renders, 95%, where both runs "
        "measured it at one size); hollow markers: busy",
        fontsize=9,
    )
    axes.grid(True, which="major", alpha=0.3)
    axes.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    return _save(figure, path)


def pass_size_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The wavefront variant's render time (left) and peak memory (right: tracemalloc's
    peak, the resident set's growth) against ``max_mb`` (log scale), the knee marked."""
    from harness import pass_size_report as psr

    found = psr.entries(run)
    points = psr.sweep(found[-1]) if found else []
    if not points:
        return None
    figure, axes = plt.subplots(figsize=(7.5, 5))
    xs = [p["max_mb"] for p in points]
    axes.plot(xs, [p["render_median"] for p in points], marker="o", color="C0", label="render time")
    bend = psr.knee(points)
    if bend is not None:
        axes.axvline(
            bend["max_mb"], color="gray", linestyle=":", label=f"knee: max_mb={bend['max_mb']}"
        )
    axes.set_xscale("log", base=2)
    axes.set_xticks(xs, [str(x) for x in xs])
    axes.set_xlabel("max_mb (MiB per pass)")
    axes.set_ylabel("render time (s), median")
    axes.set_ylim(bottom=0)
    memory = axes.twinx()
    for key, label, color in (
        ("tracemalloc_peak", "tracemalloc peak", "C1"),
        ("rss_growth", "RSS growth (canvas included)", "C2"),
    ):
        ys = [(p.get(key) or 0) / psr.MIB for p in points]
        memory.plot(xs, ys, marker="s", linestyle="--", color=color, label=label)
    memory.plot(xs, xs, linestyle=":", color="C3", label="max_mb")
    memory.set_ylabel("MiB")
    memory.set_yscale("log", base=2)
    handles = axes.get_legend_handles_labels()
    more = memory.get_legend_handles_labels()
    axes.legend(handles[0] + more[0], handles[1] + more[1], fontsize=7, loc="upper center")
    entry = found[-1]
    w, h = entry["size"]
    axes.set_title(
        f"Pass size against time and memory: {entry['name']}, {entry['scene']} at {w}x{h}, "
        f"{entry['samples']} spp\n{_caption(run)}",
        fontsize=9,
    )
    axes.grid(True, which="both", alpha=0.3)
    return _save(figure, path)


def cluster_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """Throughput (million rays per second) of each configuration of the cluster section
    as a bar, split into what it took to start (left, seconds) and to render (right)."""
    from harness import cluster_report

    found = cluster_report.entries(run)
    points = [p for p in found[-1].get("points", []) if cluster_report.usable(p)] if found else []
    if not points:
        return None
    names = [p["variant"] for p in points][::-1]
    figure, (start, speed) = plt.subplots(
        1, 2, figsize=(8.5, 0.6 * len(points) + 1.6), sharey=True, width_ratios=(1, 2)
    )
    colors = ["C1" if name.startswith("dask") else "C0" for name in names]
    starts = [p["startup"] for p in points][::-1]
    rates = [p["rays_per_second"] / 1e6 for p in points][::-1]
    start.barh(names, starts, color=colors)
    start.set_xlabel("start-up (s), first render included")
    start.invert_xaxis()
    speed.barh(names, rates, color=colors)
    speed.set_xlabel("million rays per second (median render)")
    for y, rate in enumerate(rates):
        speed.annotate(f"{rate:.2f}", (rate, y), xytext=(3, 0), textcoords="offset points",
                       va="center", fontsize=8)  # fmt: skip
    entry = found[-1]
    w, h = entry["size"]
    figure.suptitle(
        f"On a cluster: {entry['scene']} at {w}x{h}, {entry.get('samples')} spp\n{_caption(run)}",
        fontsize=9,
    )
    for axes in (start, speed):
        axes.grid(True, axis="x", alpha=0.3)
    return _save(figure, path)


def ladder_plot(run: Mapping[str, Any], path: Path) -> Path | None:
    """The ladder (``harness.ladder_report``): each step's time per pixel as a bar (log
    scale), labelled with its factor over naive and its own over the step before; POV-Ray's
    points as dashed lines across (whole process), when the run had them."""
    from harness import ladder_report as lr

    found = lr.rows(run)
    steps = [r for r in found if r.get("status") == "ok" and r.get("wall")]
    if not steps:
        return None
    figure, axes = plt.subplots(figsize=(10, 2.1))
    names = [str(r.get("step") or r["name"]).replace("[", "\n[") for r in steps]
    values = [lr.per_pixel(r) for r in steps]
    busy = [figures.is_busy(r) for r in steps]
    colours = ["#cc6677" if r.get("option") else "#4477aa" for r in steps]
    axes.bar(
        range(len(steps)), values, color=["white" if b else c for b, c in zip(busy, colours,
        strict=True)], edgecolor=colours, hatch=["//" if b else "" for b in busy],
    )  # fmt: skip
    for i, row in enumerate(steps):
        total = lr.cumulative(row, found)
        own = lr.own_factor(row, found)
        label = "naive" if total is None else figures.speedup_text(total)
        if own is not None:
            label += f"\n({figures.speedup_text(own)} own)"
        axes.annotate(label, (i, values[i]), xytext=(0, 2), textcoords="offset points",
                      ha="center", va="bottom", fontsize=7)  # fmt: skip
    anchor = lr.anchor(run)
    for point in (anchor or {}).get("points", []) if (anchor or {}).get("status") == "ok" else []:
        if not point.get("wall"):
            continue
        w, h = point["size"]
        dashes = "--" if point["threads"] > 1 else ":"
        axes.axhline(
            point["wall"] / (w * h), color="#228833", linestyle=dashes, linewidth=1, zorder=0,
            label=f"POV-Ray (C++), {point['threads']} thread(s), whole process",
        )  # fmt: skip
        axes.legend(fontsize=6, loc="upper right")
    axes.set_yscale("log")
    axes.set_xticks(range(len(steps)), names, fontsize=7)
    axes.set_ylabel("time per pixel (s, log)", fontsize=8)
    axes.tick_params(axis="y", labelsize=7)
    top = max(values)
    axes.set_ylim(min(values) / 3, top * 12)
    axes.set_title(
        "Step by step: time per pixel; labels: factor over naive (own factor over the step "
        f"before); red: options; hatched: busy. {_caption(run)}",
        fontsize=8,
    )
    axes.grid(True, axis="y", which="major", alpha=0.3)
    return _save(figure, path)


def heat_scale_plot(path: Path) -> Path:
    """The colour bar of the heat maps (``imagediff.heat_map``: logarithmic, black at
    ``HEAT_LOW`` and below)."""
    import numpy as np
    from matplotlib import colormaps

    from harness import imagediff

    figure, axes = plt.subplots(figsize=(5.5, 0.75))
    ramp = np.linspace(0.0, 1.0, 256)[np.newaxis, :]
    axes.imshow(ramp, aspect="auto", cmap=colormaps[imagediff.HEAT_MAP],
                extent=(0.0, 1.0, 0.0, 1.0))  # fmt: skip
    low, high = imagediff.HEAT_LOW, imagediff.HEAT_HIGH
    decades = round(float(np.log10(high / low)))
    ticks = [low * 10**k for k in range(decades + 1)]
    axes.set_xticks([float(imagediff.heat_level(v)) for v in ticks],
                    [f"{v:.0e}" if v < 1 else f"{v:g}" for v in ticks], fontsize=7)  # fmt: skip
    step = float(imagediff.heat_level(imagediff.ONE_STEP))
    axes.axvline(step, color="white", linewidth=1)
    axes.annotate("1/255", (step, 0.5), xytext=(3, 0), textcoords="offset points",
                  color="white", fontsize=7, va="center")  # fmt: skip
    axes.set_yticks([])
    axes.set_title("difference in the largest channel (log scale)", fontsize=7)
    return _save(figure, path)
