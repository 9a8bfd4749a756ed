"""Scaling (``rtc bench --sections scaling``): time against pixel count (part ``sizes``: a
series per variant's default over several sizes of the run's aspect), and throughput
against the worker or thread count for the variants that advertise such an option (rows of
part ``threads``, one per count). ``harness.sections.scaling.report`` reports it."""

from __future__ import annotations

from typing import TYPE_CHECKING

from harness.engine.plan import default_names, parallel_configs
from harness.instruments.usage import available_cores

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "scaling"


def measure(bench: Bench) -> None:
    s = bench.settings
    for name in default_names(s.variants):
        points = [(size, s.samples) for size in s.scaling_sizes]
        if bench.hopeless(SECTION, name, points, part="sizes"):
            continue
        entry, outcome = bench.series_job(
            SECTION, name, s.scene, points, s.budget, {"part": "sizes"}, images=False
        )
        for point in entry.get("points", []):
            point["image"] = None
        outcome.discard()
        bench.series.append(entry)
    cores = available_cores() if s.threads is None else s.threads
    counts = list(range(1, max(2, cores) + 1))
    for label, configs in parallel_configs(s.variants, counts).items():
        for count, name in configs:
            task = bench.row_task(
                name, s.size, s.samples, s.mode.side_repeat, allocations=False, rays=False,
                compare=None,
            )  # fmt: skip
            extra = {"part": "threads", "group": label, "count": count}
            bench.measure_row(SECTION, name, s.scene, task, extra, picture=False)
