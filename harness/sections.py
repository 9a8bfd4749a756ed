"""The bench's sections, in one table (``SECTIONS``).

A section is what ``rtc bench --sections NAME`` runs: its rows and series entries in the
run file carry ``"section": NAME`` (and a ``"part"`` where a section writes several kinds,
such as the sweep's ground truth), one module measures it and one reports it. Everything
else reads this table: ``harness.plan`` (the names, the defaults), ``rtc bench --help``,
``Bench.run`` (what to measure, in which order) and ``rtc report`` (the report's sections
in the table's order, their plots, the lines printed after a bench). Adding a section is
its two modules and one line here.

The measuring module (``measures``; ``module:function`` where the function is not called
``measure``) has ``measure(bench)``: it runs its jobs through the ``harness.bench.Bench`` it
is given (``measure_row``, ``series_job``, ``save_image`` ...) and adds rows to
``bench.rows`` and entries to ``bench.series``. It may also have ``before(bench)``, run for
every section asked for before any is measured (the ladder keeps the pictures of the
table's rows it reuses). A section runs after those of its ``after`` that were asked for.

The reporting module (``reports``) has ``newest(runs)`` (the newest run, of the run files
oldest first, that measured the section, or None), ``blocks(run, plot, context, runs)`` (its
part of the report: ``plot`` the path of its plot in the results folder or None,
``context`` the line naming the machine and the run, ``runs`` every run, for a section that
quotes an earlier one) and ``console_lines(run)`` (what ``rtc bench`` prints after the run);
where ``plot_file`` is set, ``plot(run, path)`` draws it (None: nothing to draw).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from harness.bench import Bench

Run = Mapping[str, Any]


@dataclass(frozen=True)
class Section:
    """One section (see the module): ``name`` as ``--sections`` and the run files spell
    it; ``about``: what it measures, for ``rtc bench --help``; ``default``: run without
    ``--sections``; ``plot_file``: its plot's file in the report folder, if it has one."""

    name: str
    measures: str
    reports: str
    about: str
    default: bool = False
    after: tuple[str, ...] = ()
    plot_file: str = ""


SECTIONS = (
    Section(
        "ladder", "harness.ladder", "harness.ladder_report",
        "the optimizations step by step, each over the one before, beside POV-Ray when "
        "installed", default=True, after=("table",), plot_file="ladder.png",
    ),
    Section(
        "table", "harness.table", "harness.table_report",
        "a row per variant and option set: time, speed-up, rays, allocations, image error",
        default=True, plot_file="speedup.png",
    ),
    Section(
        "sweep", "harness.sweep", "harness.sweep_report",
        "error against run time over samples per pixel, from a ground truth", default=True,
        after=("table",), plot_file="error-vs-time.png",
    ),
    Section(
        "scaling", "harness.scaling", "harness.scaling_report",
        "time against pixel count, throughput against workers and threads", default=True,
        after=("table",), plot_file="scaling.png",
    ),
    Section(
        "preset", "harness.preset", "harness.preset_report",
        "the C++ report's workload (cpp-spheres) in MRay/s", default=True,
    ),
    Section(
        "scene-size", "harness.scene_size", "harness.scene_size_report",
        "render, load and pack time against a mesh's triangle count (minutes)",
        plot_file="time-vs-triangles.png",
    ),
    Section(
        "light-samples", "harness.light_samples", "harness.light_samples_report",
        "soft shadows: light cells against pixel samples",
        plot_file="soft-shadows-error-vs-time.png",
    ),
    Section(
        "profile", "harness.profiling", "harness.profiling_report",
        "where the time goes in naive, cached, prealloc and numba (about a minute)",
    ),
    Section(
        "cluster", "harness.cluster", "harness.cluster_report",
        "numba on 1 and 2 threads against 1 and 2 local Dask workers (about two minutes)",
        plot_file="cluster.png",
    ),
    Section(
        "pass-size", "harness.pass_size", "harness.pass_size_report",
        "the wavefront variant's time and memory against max_mb (about ten minutes)",
        plot_file="pass-size.png",
    ),
    Section(
        "kata", "harness.kata", "harness.kata_report",
        "the chapter progress of every variant (rtc kata --variant all)", default=True,
    ),
)  # fmt: skip
"""The sections in the report's order."""

BY_NAME = {section.name: section for section in SECTIONS}
NAMES = tuple(section.name for section in SECTIONS)
DEFAULTS = tuple(section.name for section in SECTIONS if section.default)


def _resolve(spec: str, default: str | None) -> Any:
    """``module`` (its ``default`` attribute, or the module itself when None) or
    ``module:attribute``."""
    module, _, attribute = spec.partition(":")
    found = importlib.import_module(module)
    name = attribute or default
    return found if name is None else getattr(found, name)


def reporting(name: str) -> Any:
    """The reporting module of section ``name`` (see the module)."""
    return _resolve(BY_NAME[name].reports, None)


def measuring_order(names: Iterable[str]) -> list[str]:
    """``names`` in the table's order, each after those of its ``after`` among them."""
    wanted = [section.name for section in SECTIONS if section.name in set(names)]
    done: list[str] = []
    while wanted:
        ready = next(
            name for name in wanted
            if all(other in done or other not in wanted for other in BY_NAME[name].after)
        )  # fmt: skip
        wanted.remove(ready)
        done.append(ready)
    return done


def prepare(names: Iterable[str], bench: Bench) -> None:
    """Every asked-for section's ``before(bench)``, where its measuring module has one."""
    for name in names:
        spec = BY_NAME[name].measures
        if ":" in spec:  # a function, not a module of its own
            continue
        before: Callable[[Bench], None] | None = getattr(_resolve(spec, None), "before", None)
        if before is not None:
            before(bench)


def measure(name: str, bench: Bench) -> None:
    """Measure section ``name`` into ``bench``."""
    function: Callable[[Bench], None] = _resolve(BY_NAME[name].measures, "measure")
    function(bench)


def help_text() -> str:
    """The sections for ``rtc bench --help``."""
    parts = [f"{s.name}{' (default)' if s.default else ''}: {s.about}" for s in SECTIONS]
    return "; ".join(parts)
