"""The bench's table (``rtc bench --sections table``): one row per variant and option set
(``harness.engine.plan``) at the run's size, each measured by ``Bench.measure_row`` in a fresh
process: time, CPU share, speed-up over naive, rays, allocations, peak memory and the image
error against naive at the comparison size. ``harness.sections.table.report`` reports it."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "table"


def before(bench: Bench) -> None:
    """Compile the compiled variants' kernels in the background while the Python rows are
    timed (``Bench.warm``)."""
    bench.warm(list(bench.settings.variants), rays=True)


def measure(bench: Bench) -> None:
    s = bench.settings
    for name in s.variants:
        task = bench.row_task(
            name, s.size, s.samples, s.repeat, allocations=True, rays=True,
            compare=bench.compare_size,
        )  # fmt: skip
        bench.measure_row(SECTION, name, s.scene, task)
    bench.finish_section(SECTION)
