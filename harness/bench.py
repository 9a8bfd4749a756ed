"""``rtc bench``: measure every variant on a scene and keep the result as one new file.

Sections (``--sections``, all by default):

- ``table``: one row per variant and option set (``harness.plan``): time (median, min, max of
  the repeats), CPU share, speed-up over naive, MRay/s, rays cast, allocations, peak memory,
  and the image error against naive at the comparison size.
- ``sweep``: error against run time. Sample positions are a pure function of (seed, pixel,
  sample), so every exact variant renders the same picture; each variant's default and every
  option set that changed the picture in the table (float32, fastmath) renders with 1, 2, 4
  ... samples per pixel, and each picture is compared with a ground truth of many samples
  rendered by the fastest exact variant.
- ``scaling``: time against pixel count (several sizes of the same aspect), and throughput
  against the worker or thread count for variants that advertise such an option.
- ``preset``: the C++ report's workload (``cpp-spheres``: 500x500, 8 samples, depth 5) for
  each variant's default, in MRay/s.
- ``kata``: the chapter progress of every variant (``rtc kata --variant all --json``).
- ``profile`` (only when asked for): where the time goes (``harness.profiling``).

Every measurement runs in a fresh process (``harness.jobs``, ``harness.child``). Pictures are
kept as PNG beside the run file, with heat maps of their difference from naive.

Before anything is measured the scene file is loaded once with naive: a scene that does not
load stops the bench there (a ``SceneError`` naming the file and line; no run file), since
every variant would fail on it alike. While it runs, ``harness.sharing`` watches the load
average and other benches; the run file notes when the machine was shared (``"shared"``).
"""

from __future__ import annotations

import json
import math
import re
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from harness import figures, imagediff
from harness.jobs import JobOutcome, run_job
from harness.machine import describe_machine
from harness.plan import BASELINE, BenchSettings, default_names, parallel_configs
from harness.presets import PRESETS, SceneRef
from harness.results import RunWriter, pyperf_document
from harness.sharing import Watch
from harness.sizes import Size, scaled
from harness.usage import available_cores
from variants.registry import RenderError

BASELINE_BUDGET_FACTOR = 3.0  # naive's rows get three budgets: every speed-up depends on them
EXACT = 1e-6  # a picture within this of naive's (max abs) counts as the same picture
QUIET_WAIT = 20.0  # seconds to wait for a quieter machine before measuring a busy row again
TIMING_FIELDS = (
    "requested_size", "size", "budget", "budget_estimate", "reduced", "budget_note", "warmup",
    "probe", "wall", "cpu", "cores", "cpu_source", "peak_memory",
)  # fmt: skip
"""A row's fields that a measurement again replaces (its picture, allocations, rays and
image error are the first measurement's: the same renders give the same picture)."""

Log = Callable[[str], None]


def _size_key(size: Any) -> str:
    return "x".join(str(v) for v in size)


def _attempt(row: dict[str, Any]) -> dict[str, Any]:
    """One timing of a row, as its ``attempts`` list keeps it."""
    return {
        "size": list(row["size"]),
        "median": figures.median_wall(row),
        "cpu_share": round(figures.cpu_share(row), 3),
        "busy": figures.is_busy(row),
    }


def slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", name).strip("-")


def _size_list(size: Size) -> list[int]:
    return [size.width, size.height]


def _series_task(
    section: str, points: list[tuple[Size, int]], budget: float | None
) -> dict[str, Any]:
    """A measuring process's task: render each (size, samples) point."""
    return {
        "kind": "series",
        "budget": budget,
        "images": section != "sizes",
        "points": [{"size": _size_list(size), "samples": n} for size, n in points],
    }


def _series_entry(
    section: str, name: str, scene: SceneRef, extra: dict[str, Any], outcome: JobOutcome
) -> dict[str, Any]:
    """A series entry of the run file from a series task's outcome."""
    entry: dict[str, Any] = {"section": section, "name": name, "scene": scene.name, **extra}
    if outcome.ok:
        entry.update(status="ok", **outcome.result["tasks"][0])
    else:
        entry.update(status="failed", error=outcome.result["error"], points=[])
    return entry


@contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM ends the run like Ctrl-C: children stopped, staging removed, no result."""

    def interrupt(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    try:
        previous = signal.signal(signal.SIGTERM, interrupt)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


class Bench:
    """One bench run: runs the sections, collects rows and series, writes images."""

    def __init__(
        self, settings: BenchSettings, writer: RunWriter, log: Log, watch: Watch | None = None
    ) -> None:
        self.settings = settings
        self.writer = writer
        self.log = log
        self.watch = watch
        self.rows: list[dict[str, Any]] = []
        self.series: list[dict[str, Any]] = []
        self.notes: list[str] = []
        self.naive_images: dict[tuple[str, str], np.ndarray] = {}
        self.keep_pictures: set[str] = set()  # the variants whose pictures sections read
        self.pictures: dict[tuple[str, str], dict[str, np.ndarray]] = {}
        self._jobs = 0
        self.compare_size = self.comparison_size(settings.size)
        if "ladder" in settings.sections:
            from harness import ladder

            self.keep_pictures = ladder.names()

    def comparison_size(self, size: Size) -> Size:
        """``size`` scaled down to the mode's comparison pixel count (never up)."""
        return scaled(size, math.sqrt(self.settings.mode.compare_pixels / size.pixels))

    # ------------------------------------------------------------------ plumbing

    def _job(
        self, variant: str, scene: SceneRef, tasks: list[dict[str, Any]], depth: int | None = None
    ) -> JobOutcome:
        if self.watch is not None:
            self.watch.sample()
        return run_job(*self._job_spec(variant, scene, tasks, depth))

    def _job_spec(
        self, variant: str, scene: SceneRef, tasks: list[dict[str, Any]], depth: int | None = None
    ) -> tuple[Path, dict[str, Any]]:
        """A job's folder (numbered in the run's staging folder) and the job."""
        self._jobs += 1
        job = {
            "variant": variant,
            "scene": scene.as_dict(),
            "depth": self.settings.depth if depth is None else depth,
            "seed": self.settings.seed,
            "epsilon": self.settings.epsilon,
            "threads": self.settings.threads,
            "tasks": tasks,
        }
        return self.writer.staging / "jobs" / f"{self._jobs:03d}", job

    def _image_name(self, section: str, name: str, suffix: str = "") -> str:
        return f"{section}-{slug(name)}{suffix}.png"

    def _save_image(self, image: np.ndarray, filename: str) -> str:
        scale = max(1, min(8, 160 // max(1, image.shape[1])))
        imagediff.save_png(image, self.writer.staging / filename, scale=scale)
        return f"{self.writer.stem}/{filename}"

    # ------------------------------------------------------------------ rows

    def row_budget(self, name: str) -> float | None:
        """The budget of one row: ``BASELINE_BUDGET_FACTOR`` times more for naive, since every
        speed-up in its section is taken against it."""
        budget = self.settings.budget
        if budget is None:
            return None
        return budget * BASELINE_BUDGET_FACTOR if name == BASELINE else budget

    def _row_task(
        self, name: str, size: Size, samples: int, repeat: int, *, allocations: bool,
        rays: bool, compare: Size | None,
    ) -> dict[str, Any]:  # fmt: skip
        return {
            "kind": "row",
            "size": _size_list(size),
            "samples": samples,
            "repeat": repeat,
            "budget": self.row_budget(name),
            "allocations": allocations,
            "rays": rays,
            "compare_size": _size_list(compare) if compare is not None else None,
        }

    def measure_row(
        self,
        section: str,
        name: str,
        scene: SceneRef,
        task: dict[str, Any],
        extra: dict[str, Any] | None = None,
        depth: int | None = None,
    ) -> dict[str, Any]:
        """Run one row's job; keep its picture, its error against naive and its figures. A
        row that did not get the cores it asked for (``figures.is_busy``) is timed again, up
        to ``settings.again`` times (``--again``), each after waiting up to ``QUIET_WAIT`` s
        for a quieter machine (``sharing.wait_for_quiet``); the least busy measurement is
        kept, every one is listed in ``attempts``, and the row stays busy only if that one
        was."""
        self.log(f"{section}: {name}")
        outcome = self._job(name, scene, [task], depth)
        row: dict[str, Any] = {
            "section": section,
            "name": name,
            "scene": scene.name,
            **(extra or {}),
        }
        if not outcome.ok:
            row.update(status="failed", error=outcome.result["error"])
            row["traceback"] = outcome.result.get("traceback", "")
            self.rows.append(row)
            outcome.discard()
            return row
        measured = outcome.result["tasks"][0]
        row.update(status="ok", summary=outcome.result.get("summary", ""), **measured)
        row["allocation_method"] = outcome.result.get("allocation_method")
        kept: dict[str, np.ndarray] = {}
        if section != "threads":  # the scaling rows' pictures are the table's
            image = outcome.image(measured["image"])
            row["image"] = self._save_image(image, self._image_name(section, name))
            kept[_size_key(row["size"])] = image
        if measured.get("compare_image"):
            compare = outcome.image(measured["compare_image"])
            self._compare(section, name, row, compare)
            kept[_size_key(row["compare_size"])] = compare
        outcome.discard()
        if name in self.keep_pictures:
            self.pictures[(section, name)] = kept
        if figures.is_busy(row) and self.settings.again > 0:
            self._measure_again(row, scene, task, depth)
        self.rows.append(row)
        return row

    def _measure_again(
        self, row: dict[str, Any], scene: SceneRef, task: dict[str, Any], depth: int | None
    ) -> None:
        """Time a busy row again (see ``measure_row``), in place."""
        from harness.sharing import wait_for_quiet

        name = str(row["name"])
        asked = figures.cores_asked(name, int(row.get("cores") or available_cores()))
        timing = {**task, "allocations": False, "rays": False, "compare_size": None}
        attempts = [_attempt(row)]
        best = dict(row)
        for _ in range(self.settings.again):
            quiet = wait_for_quiet(asked, QUIET_WAIT)
            self.log(
                f"{row['section']}: {name} again: it got {figures.cpu_share(best):.2f} of "
                f"{asked} cores ({quiet})"
            )
            outcome = self._job(name, scene, [timing], depth)
            if not outcome.ok:
                outcome.discard()
                attempts.append({"error": str(outcome.result.get("error", ""))[:200]})
                continue
            measured = outcome.result["tasks"][0]
            outcome.discard()
            again = {**row, **{key: measured[key] for key in TIMING_FIELDS if key in measured}}
            attempts.append(_attempt(again))
            if figures.cpu_share(again) > figures.cpu_share(best):
                best = again
            if not figures.is_busy(best):
                break
        row.update({key: best[key] for key in TIMING_FIELDS if key in best})
        row["attempts"] = attempts

    def _compare(self, section: str, name: str, row: dict[str, Any], image: np.ndarray) -> None:
        """The row's picture at the comparison size against naive's (naive: kept as the
        reference)."""
        key = "x".join(map(str, row["compare_size"]))
        if key != "x".join(map(str, row["size"])):
            row["compare_image"] = self._save_image(
                image, self._image_name(section, name, f"-{key}")
            )
        if name == BASELINE:
            self.naive_images[(section, key)] = image
            row["error_vs_naive"] = None
            return
        reference = self.naive_images.get((section, key))
        if reference is None:
            row["error_vs_naive"] = None
            return
        error = imagediff.image_error(image, reference)
        row["error_vs_naive"] = {**error.as_dict(), "size": key}
        heat = imagediff.heat_map(image, reference)
        row["heatmap"] = self._save_image(heat, self._image_name(section, name, "-diff"))

    def _finish_section(self, section: str) -> None:
        rows = [r for r in self.rows if r["section"] == section]
        baseline = next((r for r in rows if r["name"] == BASELINE), None)
        for row in rows:
            row["speedup"] = figures.speedup(row, baseline)

    # ------------------------------------------------------------------ sections

    def table(self) -> None:
        s = self.settings
        for name in s.variants:
            task = self._row_task(
                name,
                s.size,
                s.samples,
                s.repeat,
                allocations=True,
                rays=True,
                compare=self.compare_size,
            )
            self.measure_row("table", name, s.scene, task)
        self._finish_section("table")

    def preset(self) -> None:
        s = self.settings
        preset = PRESETS[s.preset]
        size = s.mode.preset_size
        for name in default_names(s.variants):
            task = self._row_task(
                name,
                size,
                preset.samples,
                s.mode.side_repeat,
                allocations=False,
                rays=False,
                compare=self.comparison_size(size),
            )
            self.measure_row(
                "preset", name, s.preset_scene, task, {"depth": preset.depth}, preset.depth
            )
        self._finish_section("preset")

    def _truth_variant(self) -> tuple[str, float]:
        """The fastest variant whose table picture equals naive's, and its time per sample."""
        best = (BASELINE, math.inf)
        for row in self.rows:
            if row["section"] != "table" or row["status"] != "ok":
                continue
            error = row.get("error_vs_naive")
            if row["name"] != BASELINE and (error is None or error["max_abs"] > EXACT):
                continue
            per_sample = 1 / figures.samples_per_second(row)
            if per_sample < best[1]:
                best = (row["name"], per_sample)
        return best

    def _sweep_configs(self) -> list[str]:
        names = default_names(self.settings.variants)
        for row in self.rows:
            error = row.get("error_vs_naive") if row["section"] == "table" else None
            if error is not None and error["max_abs"] > EXACT and row["name"] not in names:
                names.append(row["name"])
        return names

    def _series_job(
        self,
        section: str,
        name: str,
        scene: SceneRef,
        points: list[tuple[Size, int]],
        budget: float | None,
        extra: dict[str, Any],
    ) -> tuple[dict[str, Any], JobOutcome]:
        self.log(f"{section}: {name}")
        outcome = self._job(name, scene, [_series_task(section, points, budget)])
        return _series_entry(section, name, scene, extra, outcome), outcome

    def _sweep_jobs(
        self, configs: list[tuple[str, list[tuple[Size, int]]]], truth: str
    ) -> list[tuple[dict[str, Any], JobOutcome]]:
        """The sweep's configurations, one after the other here, or all at once on the
        cluster ``--sweep-on`` names (``harness.cluster_jobs``)."""
        s = self.settings
        extra = {"truth": truth}
        if s.sweep_on is None:
            return [
                self._series_job("sweep", name, s.scene, points, s.budget, extra)
                for name, points in configs
            ]
        from harness.cluster_jobs import cluster_jobs

        specs = [
            self._job_spec(name, s.scene, [_series_task("sweep", points, s.budget)])
            for name, points in configs
        ]
        self.log(f"sweep: {len(specs)} configurations as tasks on {s.sweep_on}")
        self.notes.append(
            f"The error sweep's {len(specs)} configurations ran as tasks on {s.sweep_on}, "
            "side by side: their timings shared the workers' machines (each point's CPU "
            "share says what it got)."
        )
        with cluster_jobs(s.sweep_on) as run:
            outcomes = run(specs)
        return [
            (_series_entry("sweep", name, s.scene, extra, outcome), outcome)
            for (name, _), outcome in zip(configs, outcomes, strict=True)
        ]

    def sweep(self) -> None:
        s = self.settings
        size = s.mode.sweep_size
        truth_name, per_sample = self._truth_variant()
        budget = s.budget
        truth = s.mode.truth_samples
        if budget is not None and math.isfinite(per_sample):
            while truth > 4 and per_sample * size.pixels * truth > 4 * budget:
                truth //= 2
        if truth < 4:
            self.notes.append("sweep skipped: no variant renders a ground truth within budget")
            return
        entry, outcome = self._series_job(
            "truth",
            truth_name,
            s.scene,
            [(size, truth)],
            None if budget is None else 4 * budget,
            {"samples": truth},
        )
        point = entry["points"][0] if entry.get("points") else {}
        if not outcome.ok or "image" not in point or point.get("image") is None:
            self.notes.append(f"sweep skipped: the ground truth failed ({entry.get('error')})")
            outcome.discard()
            self.series.append(entry)
            return
        reference = outcome.image(point["image"])
        point["image"] = self._save_image(reference, "sweep-truth.png")
        outcome.discard()
        self.series.append(entry)
        counts = [n for n in s.mode.sweep_samples if n * 4 <= truth]
        points = [(size, n) for n in counts]
        configs = [
            (name, points)
            for name in self._sweep_configs()
            if not self._hopeless("sweep", name, points)
        ]
        try:
            measured = self._sweep_jobs(configs, truth_name)
        except RenderError as error:  # the cluster: no scheduler there, or none started
            self.log(f"sweep: {error}")
            self.notes.append(f"sweep not run: {error}")
            return
        for entry, outcome in measured:
            for point in entry.get("points", []):
                if point.get("image"):
                    image = outcome.image(point["image"])
                    point["error"] = imagediff.image_error(image, reference).as_dict()
                    point["image"] = None
            outcome.discard()
            self.series.append(entry)

    def _hopeless(self, section: str, name: str, points: list[tuple[Size, int]]) -> bool:
        """True (and a skipped entry recorded) when the table's measurement of ``name`` shows
        that even the cheapest point would take longer than the budget."""
        row = next((r for r in self.rows if r["section"] == "table" and r["name"] == name), None)
        budget = self.settings.budget
        if budget is None or row is None or row["status"] != "ok":
            return False
        per_sample = 1 / figures.samples_per_second(row)
        cheapest = min(size.pixels * n for size, n in points) * per_sample
        if cheapest <= budget:
            return False
        why = (
            f"the table's time per sample puts its cheapest point at "
            f"{figures.rough_seconds(cheapest)}, over the {budget:g} s budget"
        )
        skipped = [{"size": _size_list(size), "samples": n, "skipped": why} for size, n in points]
        self.series.append(
            {"section": section, "name": name, "scene": self.settings.scene.name,
             "status": "ok", "points": skipped}
        )  # fmt: skip
        self.log(f"{section}: {name} not run: {why}")
        return True

    def scaling(self) -> None:
        s = self.settings
        sizes = s.scaling_sizes
        for name in default_names(s.variants):
            points = [(size, s.samples) for size in sizes]
            if self._hopeless("sizes", name, points):
                continue
            entry, outcome = self._series_job("sizes", name, s.scene, points, s.budget, {})
            for point in entry.get("points", []):
                point["image"] = None
            outcome.discard()
            self.series.append(entry)
        cores = available_cores() if s.threads is None else s.threads
        counts = list(range(1, max(2, cores) + 1))
        for label, configs in parallel_configs(s.variants, counts).items():
            for count, name in configs:
                task = self._row_task(
                    name,
                    s.size,
                    s.samples,
                    s.mode.side_repeat,
                    allocations=False,
                    rays=False,
                    compare=None,
                )
                self.measure_row("threads", name, s.scene, task, {"group": label, "count": count})

    def ladder(self) -> None:
        """The optimizations step by step, beside POV-Ray (``harness.ladder``)."""
        from harness import ladder

        ladder.measure(self)

    def scene_size(self) -> None:
        """Cost against scene size (``harness.scene_size``): load, prepare and render time
        of a mesh of 1k to 1M triangles per variant, and the OBJ parser's time and memory."""
        from harness import scene_size

        s = self.settings
        plan = scene_size.Plan(
            variants=s.mesh_variants, meshes=s.meshes, size=s.size, samples=s.samples,
            depth=s.depth, seed=s.seed, threads=s.threads, repeat=s.repeat, budget=s.budget,
        )  # fmt: skip
        jobs = self.writer.staging / "jobs" / "scene-size"
        self.series.extend(scene_size.run(plan, jobs, self.log, self._save_image))

    def light_samples(self) -> None:
        """Soft shadows (``harness.light_samples``): light cells and jitter against samples
        per pixel, each priced in time and in error from a ground truth."""
        from harness import light_samples

        s = self.settings
        plan = light_samples.Plan(
            variant=s.light_variant, size=s.size, depth=s.depth, seed=s.seed,
            repeat=s.repeat, threads=s.threads, budget=s.budget,
        )  # fmt: skip
        jobs = self.writer.staging / "jobs" / "light-samples"
        self.series.extend(light_samples.run(plan, jobs, self.log, self._save_image))

    def pass_size(self) -> None:
        """Pass size against time and memory (``harness.pass_size``): the wavefront
        variant's render time and peak memory at each ``max_mb``, and its memory at
        4000x3000 with 16 samples."""
        from harness import pass_size

        s = self.settings
        plan = pass_size.Plan(
            variant=s.pass_variant, scene=s.scene, size=s.size, samples=s.samples,
            depth=s.depth, seed=s.seed, epsilon=s.epsilon, threads=s.threads,
            repeat=s.repeat, budget=s.budget,
        )  # fmt: skip
        jobs = self.writer.staging / "jobs" / "pass-size"
        self.series.extend(pass_size.run(plan, jobs, self.log, self._save_image))

    def cluster(self) -> None:
        """What a cluster buys and costs (``harness.cluster``): numba on 1 and 2 threads
        against 1 and 2 local Dask workers, on a render of at least 5 s."""
        from harness import cluster

        s = self.settings
        plan = cluster.Plan(
            scene=s.scene, size=s.size, samples=s.samples, depth=s.depth, seed=s.seed,
            epsilon=s.epsilon, repeat=s.repeat,
        )  # fmt: skip
        jobs = self.writer.staging / "jobs" / "cluster"
        self.series.extend(cluster.run(plan, jobs, self.log, self._save_image))

    def profile(self) -> None:
        """Where the time goes (``harness.profiling``): the stages, the top functions and a
        flame graph of naive, cached, prealloc and numba at a small size."""
        from harness import profiling

        plan = profiling.plan_for(self.settings)
        jobs = self.writer.staging / "jobs" / "profile"
        staging, stem = self.writer.staging, self.writer.stem
        self.series.extend(profiling.run(plan, jobs, self.log, staging, stem))

    def kata(self) -> dict[str, Any] | None:
        self.log("kata: rtc kata --variant all --json")
        try:
            done = subprocess.run(
                [sys.executable, "-m", "rtc.cli", "kata", "--variant", "all", "--json"],
                capture_output=True,
                text=True,
                timeout=1800,
            )
            data = json.loads(done.stdout)
        except (subprocess.TimeoutExpired, json.JSONDecodeError, OSError) as error:
            self.notes.append(f"chapter progress unavailable: {type(error).__name__}: {error}")
            return None
        return {
            "ok": data.get("ok"),
            "variants": data.get("variants"),
            "summary": data.get("summary", []),
            "errors": data.get("errors", []),
        }

    # ------------------------------------------------------------------ the run

    def run(self) -> dict[str, Any]:
        started = datetime.now(UTC)
        t0 = time.perf_counter()
        machine = describe_machine(Path.cwd())
        kata = None
        for section in self.settings.sections:
            if self.watch is not None:
                self.watch.sample()
            if section == "kata":
                kata = self.kata()
            else:
                getattr(self, section.replace("-", "_"))()
        seen = self.watch.finish() if self.watch is not None else {"load": None, "shared": None}
        if seen["shared"]:
            self.log(f"the machine was shared: {seen['shared']}")
        rtc = {
            "stem": self.writer.stem,
            "started": started.isoformat(),
            "seconds": time.perf_counter() - t0,
            "machine": machine,
            "settings": self.settings.as_dict(),
            "compare_size": _size_list(self.compare_size),
            "heat_scale": {"kind": "log", "low": imagediff.HEAT_LOW, "high": imagediff.HEAT_HIGH},
            "unavailable": self.settings.unavailable,
            "rows": self.rows,
            "series": self.series,
            "kata": kata,
            "notes": self.notes,
            "load": seen["load"],
            "shared": seen["shared"],
        }
        return pyperf_document(self._benchmarks(machine), rtc)

    def _benchmarks(self, machine: dict[str, Any]) -> list[dict[str, Any]]:
        common = {
            "hostname": machine["hostname"],
            "cpu_model_name": machine["cpu_model"],
            "cpu_count": machine["cpu_count"],
            "python_version": machine["python"],
            "platform": machine["platform"],
            "commit": machine.get("commit") or "unknown",
            "tree_dirty": str(machine.get("dirty")),
            "date": datetime.now(UTC).strftime("%Y-%m-%d %H:%M:%S"),
        }
        found: list[dict[str, Any]] = []
        for row in self.rows:
            if row["status"] != "ok" or row.get("reused"):
                continue
            w, h = row["size"]
            labels = {"table": "", "preset": f" [{self.settings.preset}]", "threads": " [scaling]"}
            label = labels.get(row["section"], f" [{row['section']}]")
            metadata = {
                **common,
                "variant": row["name"],
                "scene": row["scene"],
                "width": w,
                "height": h,
                "samples": row["samples"],
                "cpu_share": figures.cpu_share(row),
                "budget_note": row.get("budget_note") or None,
            }
            found.append(
                {
                    "name": f"{row['scene']} {row['name']}{label}",
                    "values": row["wall"],
                    "metadata": metadata,
                }
            )
        for entry in self.series:
            for point in entry.get("points", []):
                if entry["section"] == "scene-size" and point.get("render"):
                    name = f"scene-size {entry['name']} {point['mesh']}"
                    found.append({"name": name, "values": point["render"], "metadata": {
                        **common, "variant": entry["name"], "triangles": point["triangles"],
                        "width": self.settings.size.width, "height": self.settings.size.height,
                        "samples": self.settings.samples}})  # fmt: skip
                if "wall" not in point:
                    continue
                w, h = point["size"]
                name = f"{entry['section']} {entry['name']} {w}x{h} {point['samples']}spp"
                if point.get("threads"):
                    name += f" {point['threads']} threads"
                metadata = {
                    **common,
                    "variant": entry["name"],
                    "width": w,
                    "height": h,
                    "samples": point["samples"],
                }
                found.append({"name": name, "values": [point["wall"]], "metadata": metadata})
        return found


def check_scene(settings: BenchSettings) -> None:
    """Load the bench's scene file once with naive, before anything is measured or written:
    a ``SceneError`` (naming the file and line) when it does not load."""
    if settings.scene.path is None:  # built in code
        return
    from harness.scenefile import load_scene
    from variants.registry import load_variant

    load_scene(settings.scene.path, load_variant(BASELINE).api, variant=BASELINE, divide=False)


def run_bench(settings: BenchSettings, log: Log) -> Path:
    """Run the bench and publish its result file; nothing is left behind if it fails. A
    scene file that does not load stops it before anything is written (``check_scene``)."""
    check_scene(settings)
    writer = RunWriter(settings.results)
    watch = None
    try:
        with _terminate_as_interrupt():
            watch = Watch(settings.results, settings.threads or available_cores())
            document = Bench(settings, writer, log, watch).run()
            import shutil

            shutil.rmtree(writer.staging / "jobs", ignore_errors=True)
            return writer.publish(document)
    except BaseException:
        writer.abandon()
        raise
    finally:
        if watch is not None:
            watch.abandon()
