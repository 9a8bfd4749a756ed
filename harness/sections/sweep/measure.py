"""Error against run time (``rtc bench --sections sweep``). Sample positions are a pure
function of (seed, pixel, sample), so every exact variant renders the same picture: each
variant's default and every option set that changed the picture in the table (float32,
fastmath) renders with 1, 2, 4 ... samples per pixel, and each picture is compared with a
ground truth of many samples (part ``truth``) rendered by the fastest exact variant of the
table. With ``--sweep-on`` the configurations run as tasks on a Dask cluster
(``harness.engine.cluster_jobs``). ``harness.sections.sweep.report`` reports it."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.engine import figures
from harness.engine.bench import series_entry, series_task
from harness.engine.cluster_jobs import cluster_jobs
from harness.engine.jobs import JobOutcome
from harness.engine.plan import BASELINE, default_names
from harness.instruments import imagediff
from variants.registry import RenderError

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "sweep"
TABLE = "table"  # the section whose rows choose the ground truth's variant and the configs


def truth_variant(bench: Bench) -> tuple[str, float]:
    """The fastest variant whose table picture equals naive's, and its time per sample."""
    best = (BASELINE, math.inf)
    for row in bench.rows:
        if row["section"] != TABLE or row["status"] != "ok":
            continue
        error = row.get("error_vs_naive")
        if row["name"] != BASELINE and (error is None or error["max_abs"] > figures.EXACT):
            continue
        per_sample = 1 / figures.samples_per_second(row)
        if per_sample < best[1]:
            best = (row["name"], per_sample)
    return best


def configs(bench: Bench) -> list[str]:
    """Each variant's default, and every option set whose table picture was not naive's."""
    names = default_names(bench.settings.variants)
    for row in bench.rows:
        error = row.get("error_vs_naive") if row["section"] == TABLE else None
        if error is not None and error["max_abs"] > figures.EXACT and row["name"] not in names:
            names.append(row["name"])
    return names


def _jobs(
    bench: Bench, measured: list[tuple[str, list[tuple[Size, int]]]], truth: str
) -> list[tuple[dict[str, Any], JobOutcome]]:
    """The configurations, one after the other here, or all at once on the cluster
    ``--sweep-on`` names (``harness.engine.cluster_jobs``)."""
    s = bench.settings
    extra = {"truth": truth}
    if s.sweep_on is None:
        return [
            bench.series_job(SECTION, name, s.scene, points, s.budget, extra)
            for name, points in measured
        ]

    specs = [
        bench.job_spec(name, s.scene, [series_task(points, s.budget)]) for name, points in measured
    ]
    bench.log(f"{SECTION}: {len(specs)} configurations as tasks on {s.sweep_on}")
    bench.notes.append(
        f"The error sweep's {len(specs)} configurations ran as tasks on {s.sweep_on}, "
        "side by side: their timings shared the workers' machines (each point's CPU "
        "share says what it got)."
    )
    with cluster_jobs(s.sweep_on) as run:
        outcomes = run(specs)
    return [
        (series_entry(SECTION, name, s.scene, extra, outcome), outcome)
        for (name, _), outcome in zip(measured, outcomes, strict=True)
    ]


def measure(bench: Bench) -> None:
    s = bench.settings
    size = s.mode.sweep_size
    truth_name, per_sample = truth_variant(bench)
    budget = s.budget
    truth = s.mode.truth_samples
    if budget is not None and math.isfinite(per_sample):
        while truth > 4 and per_sample * size.pixels * truth > 4 * budget:
            truth //= 2
    if truth < 4:
        bench.notes.append("sweep skipped: no variant renders a ground truth within budget")
        return
    entry, outcome = bench.series_job(
        SECTION,
        truth_name,
        s.scene,
        [(size, truth)],
        None if budget is None else 4 * budget,
        {"part": "truth", "samples": truth},
    )
    point = entry["points"][0] if entry.get("points") else {}
    if not outcome.ok or "image" not in point or point.get("image") is None:
        bench.notes.append(f"sweep skipped: the ground truth failed ({entry.get('error')})")
        outcome.discard()
        bench.series.append(entry)
        return
    reference = outcome.image(point["image"])
    point["image"] = bench.save_image(reference, "sweep-truth.png")
    outcome.discard()
    bench.series.append(entry)
    counts = [n for n in s.mode.sweep_samples if n * 4 <= truth]
    points = [(size, n) for n in counts]
    measured = [
        (name, points) for name in configs(bench) if not bench.hopeless(SECTION, name, points)
    ]
    try:
        done = _jobs(bench, measured, truth_name)
    except RenderError as error:  # the cluster: no scheduler there, or none started
        bench.log(f"{SECTION}: {error}")
        bench.notes.append(f"sweep not run: {error}")
        return
    for entry, outcome in done:
        for point in entry.get("points", []):
            if point.get("image"):
                image = outcome.image(point["image"])
                point["error"] = imagediff.image_error(image, reference).as_dict()
                point["image"] = None
        outcome.discard()
        bench.series.append(entry)
