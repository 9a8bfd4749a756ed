"""The bench's sections, in one table (``SECTIONS``): adding a section is its own package
here and one line in the table.

A section is what ``rtc bench --sections NAME`` runs: its rows and series entries in the
run file carry ``"section": NAME`` (and a ``"part"`` where a section writes several kinds,
such as the sweep's ground truth). Its package, ``harness.sections.<NAME with _ for ->``,
holds up to three modules, each with one job:

- ``measure``: ``measure(bench)`` runs its jobs through the ``harness.engine.bench.Bench`` it
  is given (``measure_row``, ``series_job``, ``save_image`` ...) and adds rows to
  ``bench.rows`` and entries to ``bench.series``. It may also have ``before(bench)``, run for
  every section asked for before any is measured (the ladder keeps the pictures of the
  table's rows it reuses). A section runs after those of its ``after`` that were asked for.
- ``report``: ``newest(runs)`` (the newest run, of the run files oldest first, that measured
  the section, or None), ``blocks(run, plot, context, runs)`` (its part of the report:
  ``plot`` the path of its plot in the results folder or None, ``context`` the line naming
  the machine and the run, ``runs`` every run, for a section that quotes an earlier one) and
  ``console_lines(run)`` (what ``rtc bench`` prints after the run).
- ``plot`` (where ``plot_file`` is set): ``plot(run, path)`` draws it (None: nothing to draw).

Everything else reads this table: ``rtc bench`` (the names, the defaults, ``--help``, what
to measure and in which order: ``measuring``) and ``rtc report`` (the report's sections in
the table's order, their plots, the lines printed after a bench).
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import ModuleType
from typing import Any

Run = Mapping[str, Any]


@dataclass(frozen=True)
class Section:
    """One section (see the module): ``name`` as ``--sections`` and the run files spell
    it; ``about``: what it measures, for ``rtc bench --help``; ``default``: run without
    ``--sections`` in full mode (``--full``); ``quick``: run without ``--sections`` in quick mode
(the default); ``after``: the sections it reads, measured first when asked for;
    ``plot_file``: its plot's file in the report folder, if it has one."""

    name: str
    about: str
    default: bool = False
    quick: bool = False
    after: tuple[str, ...] = ()
    plot_file: str = ""

    @property
    def package(self) -> str:
        return f"{__name__}.{self.name.replace('-', '_')}"

    def module(self, job: str) -> ModuleType:
        """The section's ``measure``, ``report`` or ``plot`` module."""
        return importlib.import_module(f"{self.package}.{job}")

    def before(self, bench: Any) -> None:
        """The measuring module's ``before(bench)``, where it has one."""
        before = getattr(self.module("measure"), "before", None)
        if before is not None:
            before(bench)

    def measure(self, bench: Any) -> None:
        """Measure the section into ``bench``."""
        self.module("measure").measure(bench)


SECTIONS = (
    Section("ladder", "the optimizations step by step, each over the one before, beside "
            "POV-Ray when installed", default=True, quick=True, after=("table",),
            plot_file="ladder.png"),
    Section("table", "a row per variant and option set: time, speed-up, rays, allocations, "
            "image error", default=True, plot_file="speedup.png"),
    Section("sweep", "error against run time over samples per pixel, from a ground truth",
            default=True, after=("table",), plot_file="error-vs-time.png"),
    Section("scaling", "time against pixel count, throughput against workers and threads",
            default=True, after=("table",), plot_file="scaling.png"),
    Section("preset", "the C++ report's workload (cpp-spheres) in MRay/s", default=True),
    Section("convergence", "path tracing: RMSE against a converged picture as samples grow, "
            "against samples and time, fitted slopes, time to RMSE 0.01", default=True,
            plot_file="convergence.png"),
    Section("scene-size", "render, load and pack time against a mesh's triangle count "
            "(minutes)", plot_file="time-vs-triangles.png"),
    Section("light-samples", "soft shadows: light cells against pixel samples",
            plot_file="soft-shadows-error-vs-time.png"),
    Section("profile", "where the time goes in naive, cached, prealloc and numba (about a "
            "minute)"),
    Section("cluster", "numba on 1 and 2 threads against 1 and 2 local Dask workers (about "
            "two minutes)", plot_file="cluster.png"),
    Section("pass-size", "the wavefront variant's time and memory against max_mb (about ten "
            "minutes)", plot_file="pass-size.png"),
    Section("kata", "the chapter progress of every variant (rtc kata --variant all)",
            default=True),
)  # fmt: skip
"""The sections in the report's order."""

BY_NAME = {section.name: section for section in SECTIONS}
NAMES = tuple(section.name for section in SECTIONS)


def measuring_order(names: Iterable[str]) -> list[str]:
    """``names`` in the table's order, each after those of its ``after`` among them."""
    asked = set(names)
    wanted = [section.name for section in SECTIONS if section.name in asked]
    done: list[str] = []
    while wanted:
        ready = next(
            name for name in wanted
            if all(other in done or other not in wanted for other in BY_NAME[name].after)
        )  # fmt: skip
        wanted.remove(ready)
        done.append(ready)
    return done


DEFAULTS = tuple(measuring_order(section.name for section in SECTIONS if section.default))
"""What ``rtc bench --full`` runs without ``--sections``, in the order it measures them: the
sections the table marks ``default`` (the others take minutes each)."""
QUICK_DEFAULTS = tuple(measuring_order(section.name for section in SECTIONS if section.quick))
"""What ``rtc bench`` (quick, the default mode) runs without ``--sections``: the ladder, a
few minutes at most."""


def measuring(names: Iterable[str]) -> list[Section]:
    """The sections ``names``, in the order they are measured (``measuring_order``)."""
    return [BY_NAME[name] for name in measuring_order(names)]


def reporting(name: str) -> ModuleType:
    """The reporting module of section ``name`` (see the module)."""
    return BY_NAME[name].module("report")


def help_text() -> str:
    """The sections for ``rtc bench --help``."""
    def marks(section: Section) -> str:
        found = [m for m, on in (("quick", section.quick), ("full", section.default)) if on]
        return f" (default: {', '.join(found)})" if found else ""

    parts = [f"{s.name}{marks(s)}: {s.about}" for s in SECTIONS]
    return "; ".join(parts)
