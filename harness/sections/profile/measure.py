"""Where the time goes, in a bench run (``rtc bench --sections profile``): each of
``BENCH_VARIANTS`` profiled (``harness.sections.profile.profiler``) on the run's scene at a
small size, the flame graphs kept beside the run file."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from groundwork.sizes import Size
from harness.scenery.presets import PRESETS
from harness.sections.profile.profiler import (
    SECTION,
    Request,
    is_compiled,
    profile,
    profile_size,
    slug,
)
from harness.sections.profile.stats import findings
from raytracer.camera import WHITTED
from variants.registry import load_variant

if TYPE_CHECKING:
    from harness.engine.bench import Bench

BENCH_VARIANTS = ("naive", "cached", "prealloc", "numba")
REPORT_TOP = 8  # functions per variant in the report
Log = Callable[[str], None]


def measure(bench: Bench) -> None:
    """The section in a bench run (``harness.engine.bench.Bench``): ``plan_for`` its settings, its
    entries into the run's series, the flame graphs into the run's folder."""
    plan = plan_for(bench.settings)
    staging, stem = bench.writer.staging, bench.writer.stem
    bench.series.extend(run(plan, bench.jobs_folder(SECTION), bench.log, staging, stem))


# ---------------------------------------------------------------------------- the bench


@dataclass(frozen=True)
class Plan:
    """The bench section: ``variants`` on ``scene`` at ``size`` (see ``profile_size``)."""

    scene: Path
    size: Size
    variants: tuple[str, ...] = BENCH_VARIANTS
    samples: int = 1
    depth: int = 5
    seed: int = 0
    threads: int | None = None
    integrator: str = WHITTED


def plan_for(settings: Any) -> Plan:
    """The section's plan in a bench run (``harness.engine.plan.BenchSettings``): its scene (the
    reference scene when the run's has no file), scaled to ``DEFAULT_PIXELS``, one sample
    per pixel, the run's depth, seed and threads."""
    scene = settings.scene.path
    if scene is None:
        scene = PRESETS["reference"].path
    return Plan(
        scene=Path(scene), size=profile_size(settings.size), depth=settings.depth,
        seed=settings.seed, threads=settings.threads, integrator=settings.integrator,
    )  # fmt: skip


def run(plan: Plan, jobs: Path, log: Log, images: Path, stem: str) -> list[dict[str, Any]]:
    """The ``profile`` section: one entry per variant of ``plan``; the flame graphs go into
    ``images`` (the run's folder), named in the entry as ``STEM/profile-VARIANT.svg``."""
    entries: list[dict[str, Any]] = []
    for name in plan.variants:
        try:
            variant = load_variant(name)
        except LookupError as error:
            reason = str(error.args[0] if error.args else error)
            log(f"{SECTION}: {name} not run: {reason}")
            entries.append({"section": SECTION, "name": name, "status": "unavailable",
                            "error": reason})  # fmt: skip
            continue
        work = jobs / slug(variant.name) / "out"
        work.mkdir(parents=True, exist_ok=True)
        request = Request(
            variant=variant.name, scene=plan.scene, size=plan.size, folder=work,
            stem=f"{SECTION}-{slug(variant.name)}", samples=plan.samples, depth=plan.depth,
            seed=plan.seed, top=REPORT_TOP * 2, compiled=is_compiled(variant),
            threads=plan.threads, integrator=plan.integrator,
        )  # fmt: skip
        entry = profile(request, work.parent, lambda m: log(f"{SECTION}: {m}"))
        for key in ("image", "pstats"):
            entry.pop(key, None)
        flame = entry.pop("flame", None)
        if flame:
            target = images / Path(flame).name
            shutil.move(flame, target)
            entry["flame"] = f"{stem}/{target.name}"
        entry["finding"] = findings(entry)
        log(entry["finding"])
        entries.append(entry)
    return entries
