"""``rtc bench``: measure every variant on a scene and keep the result as one new file.

The sections it runs (``--sections``) are listed in ``harness.sections`` and given to ``run_bench``
in the order they are measured, each measuring through the ``Bench`` here: ``measure_row`` (a row:
warm-up, timed renders, allocations, rays and the picture against naive's at the comparison size; a
row that did not get the cores it asked for is timed again, ``--again``), ``series_job`` (a series
of points), ``save_image`` and the run's ``rows``, ``series`` and ``notes``.

Every measurement runs in a fresh process (``harness.engine.jobs``, ``harness.engine.child``).
Pictures are kept as PNG beside the run file, with heat maps of their difference from naive.

Before anything is measured the scene file is loaded once with naive: a scene that does not
load stops the bench there (a ``SceneError`` naming the file and line; no run file), since
every variant would fail on it alike. While it runs, ``harness.engine.sharing`` watches the load
average and other benches; the run file notes when the machine was shared (``"shared"``).
"""

from __future__ import annotations

import math
import re
import shutil
import signal
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from groundwork.sizes import Size
from harness.engine import figures, sharing
from harness.engine.budget import scaled
from harness.engine.jobs import JobOutcome, run_job
from harness.engine.machine import describe_machine
from harness.engine.plan import BASELINE, BenchSettings
from harness.engine.results import RunWriter, pyperf_document
from harness.engine.sharing import Watch
from harness.engine.warmer import Warmer, warm_task
from harness.instruments import imagediff
from harness.instruments.usage import available_cores
from harness.scenery.presets import SceneRef
from scene import load_scene
from variants.registry import load_variant

BASELINE_BUDGET_FACTOR = 3.0  # naive's rows get three budgets: every speed-up depends on them
QUIET_WAIT = 20.0  # seconds at most, each time, to wait for a quieter machine
TIMING_FIELDS = (
    "requested_size", "size", "budget", "budget_estimate", "reduced", "budget_note", "warmup",
    "probe", "wall", "cpu", "cores", "cpu_source", "peak_memory",
)  # fmt: skip
"""A row's fields that a measurement again replaces (its picture, allocations, rays and
image error are the first measurement's: the same renders give the same picture)."""

Log = Callable[[str], None]


class Section(Protocol):
    """What the bench runs: a section of ``harness.sections``, by its name."""

    @property
    def name(self) -> str: ...

    def before(self, bench: Bench) -> None: ...

    def measure(self, bench: Bench) -> None: ...


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


def series_task(
    points: list[tuple[Size, int]], budget: float | None, images: bool = True
) -> dict[str, Any]:
    """A measuring process's task: render each (size, samples) point (and keep its picture
    when ``images``)."""
    return {
        "kind": "series",
        "budget": budget,
        "images": images,
        "points": [{"size": _size_list(size), "samples": n} for size, n in points],
    }


def series_entry(
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
        self.kata: dict[str, Any] | None = None  # the chapter progress (sections.kata)
        self.keep_pictures: set[str] = set()  # the variants whose pictures sections read
        self.pictures: dict[tuple[str, str], dict[str, np.ndarray]] = {}
        self._jobs = 0
        self.compare_size = self.comparison_size(settings.size)
        self.clock: Callable[[], float] = time.monotonic
        self.wait_left = settings.mode.wait_budget  # seconds the run may spend on busy rows
        self.warmer: Warmer | None = None  # the background compile (``warm``), or None

    def jobs_folder(self, section: str) -> Path:
        """A folder for a section's own job files (removed with the staging's jobs)."""
        return self.writer.staging / "jobs" / section

    def comparison_size(self, size: Size) -> Size:
        """``size`` scaled down to the mode's comparison pixel count (never up)."""
        return scaled(size, math.sqrt(self.settings.mode.compare_pixels / size.pixels))

    # ------------------------------------------------------------------ plumbing

    def _job(
        self, variant: str, scene: SceneRef, tasks: list[dict[str, Any]], depth: int | None = None,
        **settings: Any,
    ) -> JobOutcome:  # fmt: skip
        if self.watch is not None:
            self.watch.sample()
        return run_job(*self.job_spec(variant, scene, tasks, depth, **settings))

    def job_spec(
        self, variant: str, scene: SceneRef, tasks: list[dict[str, Any]], depth: int | None = None,
        **settings: Any,
    ) -> tuple[Path, dict[str, Any]]:  # fmt: skip
        """A job's folder (numbered in the run's staging folder) and the job; ``settings``
        replace the run's ``seed`` or ``integrator`` for this job, or set its
        ``light_sampling`` (the path integrator's; True when not given)."""
        self._jobs += 1
        job = {
            "variant": variant,
            "scene": scene.as_dict(),
            "depth": self.settings.depth if depth is None else depth,
            "seed": self.settings.seed,
            "epsilon": self.settings.epsilon,
            "threads": self.settings.threads,
            "integrator": self.settings.integrator,
            "light_sampling": self.settings.light_sampling,
            "tasks": tasks,
        }
        unknown = set(settings) - {"seed", "integrator", "light_sampling"}
        if unknown:
            raise TypeError(f"job_spec: no setting {', '.join(sorted(unknown))}")
        job.update(settings)
        return self.writer.staging / "jobs" / f"{self._jobs:03d}", job

    def warm(self, names: list[str], rays: bool) -> None:
        """Compile the kernels of ``names`` (those that compile; with the ray-counting ones
        when their rows count rays, ``rays``) in the background once the sections' ``before``
        are done, while one-core Python rows are timed (``harness.engine.warmer``)."""
        self._warmer().add(names, rays)

    def warm_job(self, label: str, module: str, job: Mapping[str, Any]) -> None:
        """Run a section's own compile (``python -m MODULE job.json``) in the background too,
        after the variants' (``Warmer.add_job``); a section calls it from its ``before``."""
        self._warmer().add_job(label, module, job)

    def _warmer(self) -> Warmer:
        if self.warmer is None:

            def job(name: str, counted: bool) -> dict[str, Any]:
                return {**self.job_spec(name, self.settings.scene, [warm_task(counted)])[1]}

            folder = self.writer.staging / "jobs" / "warm"
            self.warmer = Warmer(folder, job, self.log, self.settings.threads)
        return self.warmer

    def image_name(self, section: str, name: str, suffix: str = "") -> str:
        return f"{section}-{slug(name)}{suffix}.png"

    def save_image(self, image: np.ndarray, filename: str) -> str:
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

    def row_task(
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
        picture: bool = True,
        integrator: str | None = None,
        tag: str = "",
    ) -> dict[str, Any]:
        """Run one row's job; keep its picture (unless ``picture`` is False: a row whose
        picture another row already shows), its error against naive and its figures. A
        row that did not get the cores it asked for (``figures.is_busy``) is timed again, up
        to ``settings.again`` times (``--again``), each after waiting up to ``QUIET_WAIT`` s
        for a quieter machine (``sharing.wait_for_quiet``); the least busy measurement is
        kept, every one is listed in ``attempts``, and the row stays busy only if that one
        was. ``integrator``: the row's, when not the run's (the path preset's); ``tag``: added to
        its pictures' names, for a second row of the same variant in the section."""
        self.log(f"{section}: {name}")
        if self.warmer is not None:
            self.warmer.before(name)
        chosen = {} if integrator is None else {"integrator": integrator}
        outcome = self._job(name, scene, [task], depth, **chosen)
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
        if picture:
            image = outcome.image(measured["image"])
            row["image"] = self.save_image(image, self.image_name(section, name, tag))
            kept[_size_key(row["size"])] = image
        if measured.get("compare_image"):
            compare = outcome.image(measured["compare_image"])
            self._compare(section, name, row, compare, tag)
            kept[_size_key(row["compare_size"])] = compare
        outcome.discard()
        if name in self.keep_pictures:
            self.pictures[(section, name)] = kept
        if figures.is_busy(row) and self.settings.again > 0:
            self._measure_again(row, scene, task, depth, chosen)
        self.rows.append(row)
        self.log(f"{section}: {name}: {self.figure_text(row)}")
        return row

    def figure_text(self, row: dict[str, Any]) -> str:
        """A measured row's figure in a line, printed as soon as it exists: its median
        frame, time per pixel, throughput over naive's in its section, and busy."""
        per_pixel = figures.median_wall(row) / figures.pixels(row)
        text = (
            f"{figures.seconds_text(figures.median_wall(row))} at {_size_key(row['size'])} "
            f"({figures.per_pixel_text(per_pixel)} per pixel"
        )
        naive = next(
            (r for r in self.rows if r["section"] == row["section"] and r["name"] == BASELINE
             and r.get("status") == "ok" and r.get("wall")),
            None,
        )  # fmt: skip
        if naive is not None and row["name"] != BASELINE:
            over = figures.median_wall(naive) / figures.pixels(naive) / per_pixel
            text += f", {figures.speedup_text(over)} naive's throughput"
        busy = f"; busy: it got {figures.cpu_share(row):.2f} cores" if figures.is_busy(row) else ""
        return text + ")" + busy

    def wait_for_quiet(self, cores: int, label: str) -> str | None:
        """Wait for ``cores`` idle cores, at most ``QUIET_WAIT`` s and never beyond what is left
        of the run's wait budget (``Mode.wait_budget``); None (no wait) once it is spent."""
        longest = min(QUIET_WAIT, self.wait_left)
        if longest < 1.0:
            self.log(f"{label}: the run's {self.settings.mode.wait_budget:g} s of waiting for a "
                     "quieter machine are spent: it stays marked busy")  # fmt: skip
            return None
        self.log(f"{label}: waiting up to {longest:.0f} s for a quieter machine to time it again")
        start = self.clock()
        quiet = sharing.wait_for_quiet(cores, longest, report=lambda t: self.log(f"{label}: {t}"))
        self.spend(self.clock() - start)
        return quiet

    def spend(self, seconds: float) -> None:
        """Take ``seconds`` (a wait, or a busy row's second timing) from the wait budget."""
        self.wait_left = max(0.0, self.wait_left - seconds)

    def _measure_again(
        self, row: dict[str, Any], scene: SceneRef, task: dict[str, Any], depth: int | None,
        chosen: dict[str, Any],
    ) -> None:  # fmt: skip
        """Time a busy row again (see ``measure_row``), in place."""
        name = str(row["name"])
        asked = figures.cores_asked(name, int(row.get("cores") or available_cores()))
        timing = {**task, "allocations": False, "rays": False, "compare_size": None}
        attempts = [_attempt(row)]
        best = dict(row)
        for _ in range(self.settings.again):
            label = f"{row['section']}: {name}"
            self.log(f"{label} got {figures.cpu_share(best):.2f} of {asked} cores")
            quiet = self.wait_for_quiet(asked, label)
            if quiet is None:
                break
            self.log(f"{label} again ({quiet})")
            start = self.clock()
            outcome = self._job(name, scene, [timing], depth, **chosen)
            self.spend(self.clock() - start)
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
        if len(attempts) > 1:
            row["attempts"] = attempts

    def _compare(
        self, section: str, name: str, row: dict[str, Any], image: np.ndarray, tag: str = ""
    ) -> None:
        """The row's picture at the comparison size against naive's (naive: kept as the
        reference)."""
        key = "x".join(map(str, row["compare_size"]))
        if key != "x".join(map(str, row["size"])):
            row["compare_image"] = self.save_image(
                image, self.image_name(section, name, f"{tag}-{key}")
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
        row["heatmap"] = self.save_image(heat, self.image_name(section, name, f"{tag}-diff"))

    def finish_section(self, section: str) -> None:
        rows = [r for r in self.rows if r["section"] == section]
        baseline = next((r for r in rows if r["name"] == BASELINE), None)
        for row in rows:
            row["speedup"] = figures.speedup(row, baseline)

    # ------------------------------------------------------------------ sections

    def hopeless(
        self, section: str, name: str, points: list[tuple[Size, int]], part: str | None = None
    ) -> bool:
        """True (and a skipped entry recorded, of ``part`` when given) when the table's
        measurement of ``name`` shows that even the cheapest point would take longer than
        the budget."""
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
        entry = {"section": section, "name": name, "scene": self.settings.scene.name,
                 "status": "ok", "points": skipped}  # fmt: skip
        if part is not None:
            entry["part"] = part
        self.series.append(entry)
        self.log(f"{section}: {name} not run: {why}")
        return True

    def series_job(
        self,
        section: str,
        name: str,
        scene: SceneRef,
        points: list[tuple[Size, int]],
        budget: float | None,
        extra: dict[str, Any],
        images: bool = True,
    ) -> tuple[dict[str, Any], JobOutcome]:
        """One variant's series of (size, samples) points in a fresh process, as an entry
        of ``section`` (with ``extra``) and the outcome holding its pictures."""
        self.log(f"{section}: {name}")
        outcome = self._job(name, scene, [series_task(points, budget, images)])
        return series_entry(section, name, scene, extra, outcome), outcome

    # ------------------------------------------------------------------ the run

    def run(self, sections: Sequence[Section]) -> dict[str, Any]:
        """Measure ``sections`` (in this order, each ``before`` first) into the run file's
        document."""
        started = datetime.now(UTC)
        t0 = time.perf_counter()
        machine = describe_machine(Path.cwd())
        for section in sections:
            section.before(self)
        if self.warmer is not None:
            self.warmer.start()
        try:
            for section in sections:
                if self.watch is not None:
                    self.watch.sample()
                section.measure(self)
        finally:
            if self.warmer is not None:
                self.warmer.stop()
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
            "kata": self.kata,
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
            labels = {"table": "", "preset": f" [{self.settings.preset}]"}
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
                if entry["section"] == "convergence":  # a series per scene, and its truth
                    name += f" {entry['scene']} {entry.get('part') or ''}".rstrip()
                    if entry.get("light_sampling") == "off":  # the same series both ways
                        name += " light sampling off"
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

    load_scene(settings.scene.path, load_variant(BASELINE).api, variant=BASELINE)


def run_bench(settings: BenchSettings, log: Log, sections: Sequence[Section]) -> Path:
    """Run the bench's ``sections`` (``harness.sections.measuring``) and publish its result
    file; nothing is left behind if it fails. A scene file that does not load stops it before
    anything is written (``check_scene``)."""
    check_scene(settings)
    writer = RunWriter(settings.results)
    watch = None
    try:
        with _terminate_as_interrupt():
            watch = Watch(settings.results, settings.threads or available_cores())
            document = Bench(settings, writer, log, watch).run(sections)

            shutil.rmtree(writer.staging / "jobs", ignore_errors=True)
            return writer.publish(document)
    except BaseException:
        writer.abandon()
        raise
    finally:
        if watch is not None:
            watch.abandon()
