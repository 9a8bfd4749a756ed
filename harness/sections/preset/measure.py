"""The C++ report's workload (``rtc bench --sections preset``): each variant's default on
``cpp-spheres`` (500x500, 8 samples per pixel, depth 5), reported in MRay/s beside the C++
report's figure by ``harness.sections.preset.report``."""

from __future__ import annotations

from typing import TYPE_CHECKING

from harness.engine.plan import default_names
from harness.scenery.presets import PRESETS

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "preset"


def measure(bench: Bench) -> None:
    s = bench.settings
    preset = PRESETS[s.preset]
    size = s.mode.preset_size
    for name in default_names(s.variants):
        task = bench.row_task(
            name, size, preset.samples, s.mode.side_repeat, allocations=False, rays=False,
            compare=bench.comparison_size(size),
        )  # fmt: skip
        extra = {"depth": preset.depth}
        bench.measure_row(SECTION, name, s.preset_scene, task, extra, preset.depth)
    bench.finish_section(SECTION)
