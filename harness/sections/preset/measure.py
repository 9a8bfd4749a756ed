"""The C++ report's workload (``rtc bench --sections preset``): each variant's default on
``cpp-spheres`` (500x500, 8 samples per pixel, depth 5) with the book's Whitted integrator,
then the same scene as the C++ report rendered it (``cpp-spheres-path``: path-traced, 8 rays
per pixel, 5 bounces, its sky) by every default that path-traces (the others: rows of status
``refused`` with their one line). A row too slow for the budget is measured at a smaller size
(MRay/s is per ray, so it compares). Reported in MRay/s beside the C++ report's figures by
``harness.sections.preset.report``."""

from __future__ import annotations

from typing import TYPE_CHECKING

from harness.engine import figures
from harness.engine.plan import BASELINE, default_names, refusal
from harness.scenery.presets import PATH_PRESET, PRESETS, SceneRef
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "preset"


def _measure(bench: Bench, preset_name: str) -> list[dict[str, object]]:
    """Each default that renders with the preset's integrator: its row (or a refusal)."""
    s = bench.settings
    preset = PRESETS[preset_name]
    scene = SceneRef(preset_name, preset.path)
    size = s.mode.preset_size
    found = []
    for name in default_names(s.variants):
        extra = {"depth": preset.depth, "preset": preset_name, "integrator": preset.integrator}
        why = refusal(load_variant(name), preset.integrator)
        if why is not None:
            bench.log(f"{SECTION}: {preset_name}: {name} not run: {why}")
            row = {"section": SECTION, "name": name, "scene": preset_name, **extra,
                   "status": "refused", "error": why}  # fmt: skip
            bench.rows.append(row)
            found.append(row)
            continue
        task = bench.row_task(
            name, size, preset.samples, s.mode.side_repeat, allocations=False, rays=False,
            compare=bench.comparison_size(size),
        )  # fmt: skip
        found.append(bench.measure_row(
            SECTION, name, scene, task, extra, preset.depth, integrator=preset.integrator,
            tag="" if preset_name == s.preset else "-path",
        ))  # fmt: skip
    return found


def measure(bench: Bench) -> None:
    _measure(bench, bench.settings.preset)
    bench.finish_section(SECTION)  # the speed-ups of the book's integrator, over naive's
    rows = _measure(bench, PATH_PRESET)
    baseline = next((r for r in rows if r["name"] == BASELINE), None)
    for row in rows:
        row["speedup"] = figures.speedup(row, baseline)
