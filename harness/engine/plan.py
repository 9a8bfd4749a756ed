"""What a bench run measures: its settings (quick, full or custom) and its list of variants.

``--variants all`` means every available variant with its default options plus the option
sets ``BENCH_CONFIGS`` lists for it (spelled in the registry's grammar, e.g.
``numba[float32]`` or ``pooled[workers=1]``). ``naive`` is always measured: the speed-ups and
image errors are taken against it, in the same run.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from groundwork.files import recorded_path
from groundwork.sizes import Size
from harness.engine.budget import smaller_sizes
from harness.engine.figures import PARALLEL_OPTIONS
from harness.scenery.make_meshes import SCALE_MESHES
from harness.scenery.presets import PRESETS, SceneRef
from raytracer.camera import INTEGRATORS, WHITTED, RenderSettings
from variants.registry import Variant, load_variant, parse_variant_name, registry

BASELINE = "naive"
AGAIN = 2  # a busy row is timed again up to this many times (``--again``)
BENCH_CONFIGS: dict[str, tuple[str, ...]] = {
    "pooled": (
        "pooled[workers=1]",
        "pooled[granularity=pixel]",
        "pooled[granularity=tile]",
        "pooled:prealloc",
        "pooled[workers=1]:numba",
        "pooled[workers=2]:numba[threads=1]",
    ),
    "numba": ("numba[threads=1]", "numba[float32]", "numba[fastmath]", "numba[specialize=off]"),
    "wavefront": ("wavefront[float32]", "wavefront[threads=2]"),
    "dask": ("dask[workers=2]:numba[threads=1]",),
}
"""Registry name -> what ``--variants all`` measures besides its default options."""


@dataclass(frozen=True)
class Mode:
    """The defaults of ``--quick`` and ``--full``.

    size, repeat, budget: the table's; sweep_size, sweep_samples, truth_samples: the error
    sweep's (ground truth rendered with ``truth_samples``); scaling_steps: how many sizes in
    the pixel-count plot; preset_size: the C++ workload's size (its own is 500x500);
    compare_pixels: the comparison size (allocations, rays, image error) has at most this
    many pixels; side_repeat: timed renders per row of the preset and scaling sections;
    convergence_*: the convergence section's scenes (files of ``scenes/``), its sizes for
    Python and for compiled variants, its samples per pixel and its converged picture's;
    wait_budget: the seconds the whole run may spend waiting for a quieter machine and timing
    busy rows again (``Bench.wait_for_quiet``): a machine that stays busy costs no more.
    """

    name: str
    size: Size
    repeat: int
    budget: float
    sweep_size: Size
    sweep_samples: tuple[int, ...]
    truth_samples: int
    scaling_steps: int
    preset_size: Size
    compare_pixels: int
    side_repeat: int
    convergence_scenes: tuple[str, ...]
    convergence_size: Size
    convergence_compiled_size: Size
    convergence_samples: tuple[int, ...]
    convergence_truth: int
    wait_budget: float = 60.0


QUICK = Mode(
    name="quick", size=Size(160, 120), repeat=3, budget=6.0, sweep_size=Size(64, 48),
    sweep_samples=(1, 2, 4, 8, 16), truth_samples=64, scaling_steps=4,
    preset_size=Size(500, 500), compare_pixels=300, side_repeat=1,
    convergence_scenes=("cpp-spheres",), convergence_size=Size(16, 16),
    convergence_compiled_size=Size(96, 96), convergence_samples=(1, 2, 4, 8),
    convergence_truth=128, wait_budget=30.0,
)  # fmt: skip
FULL = Mode(
    name="full", size=Size(640, 480), repeat=5, budget=300.0, sweep_size=Size(160, 120),
    sweep_samples=(1, 2, 4, 8, 16, 32, 64), truth_samples=256, scaling_steps=5,
    preset_size=Size(500, 500), compare_pixels=19200, side_repeat=3,
    convergence_scenes=("cpp-spheres", "spheres-box", "soft-shadows"),
    convergence_size=Size(32, 32),
    convergence_compiled_size=Size(200, 200), convergence_samples=(1, 2, 4, 8, 16, 32, 64),
    convergence_truth=2048, wait_budget=300.0,
)  # fmt: skip
MODES = {"quick": QUICK, "full": FULL}


@dataclass
class BenchSettings:
    """Everything one ``rtc bench`` run does (recorded with its results).

    scene: the table's scene; size, samples, depth, seed: the table's renders; threads: CPUs each
    measuring process may use (None: all); repeat: timed renders per row; budget: seconds the
    renders of one row may take (None: no limit); variants: canonical names, naive first; sections:
    which parts to run (``harness.sections``); mode: quick or full (its defaults); epsilon:
    ``RenderSettings.epsilon`` (None: the book's EPSILON); mesh_variants, meshes: the ``scene-size``
    section's (``harness.sections.scene_size.measure``); light_variant: the ``light-samples``
    section's (``harness.sections.light_samples.measure``); pass_variant: the ``pass-size``
    section's (``harness.sections.pass_size.measure``); sweep_on: the Dask cluster the error sweep's
    configurations run on (``harness.engine.cluster_jobs``; None: here, one after the other); again:
    how many times a busy row is timed again (``Bench.measure_row``); integrator: the renders'
    (``RenderSettings.integrator``: ``--integrator``; the convergence section and the path
    preset path-trace whatever it is); light_sampling: the path integrator's
    (``--light-sampling``; the convergence section measures both where it matters);
    variants_asked: ``--variants`` as given ("all": a whole
    run; any other: a partial run, which the report adds and never shows in a fuller run's
    place, ``harness.report.choice``).
    """

    scene: SceneRef
    size: Size
    samples: int
    depth: int
    seed: int
    threads: int | None
    repeat: int
    budget: float | None
    variants: list[str]
    sections: tuple[str, ...]
    mode: Mode
    results: Path
    unavailable: dict[str, str] = field(default_factory=dict)
    preset: str = "cpp-spheres"
    epsilon: float | None = None
    mesh_variants: tuple[str, ...] = ("numba", "numba[bvh=off]")
    meshes: tuple[str, ...] = SCALE_MESHES
    light_variant: str = "numba"
    pass_variant: str = "wavefront"
    sweep_on: str | None = None
    again: int = AGAIN
    integrator: str = WHITTED
    light_sampling: bool = True
    variants_asked: str = "all"

    def as_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["scene"] = self.scene.as_dict()
        if self.scene.path is not None:
            data["scene"]["path"] = recorded_path(str(self.scene.path))
        data["size"] = [self.size.width, self.size.height]
        data["mode"] = {
            key: [value.width, value.height] if isinstance(value, Size) else value
            for key, value in asdict(self.mode).items()
        }
        for key, value in vars(self.mode).items():
            if isinstance(value, Size):
                data["mode"][key] = [value.width, value.height]
        data["results"] = recorded_path(str(self.results))
        return data

    @property
    def scaling_sizes(self) -> list[Size]:
        return smaller_sizes(self.size, self.mode.scaling_steps)

    @property
    def preset_scene(self) -> SceneRef:
        return SceneRef(self.preset, PRESETS[self.preset].path)


def refusal(variant: Variant, integrator: str) -> str | None:
    """Why ``variant`` cannot render with ``integrator`` (its tracer's one line, from
    ``check_settings``), or None when it can (a tracer-less package: it is not asked)."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be {' or '.join(INTEGRATORS)}, got {integrator!r}")
    if variant.tracer is None:
        return None
    try:
        variant.tracer.check_settings(RenderSettings(integrator=integrator))
    except ValueError as error:
        return " ".join(str(error).split())
    return None


def split_names(text: str) -> list[str]:
    """``"numba[float32,threads=1],cached"`` -> the two names (commas inside [] stay)."""
    names, depth, current = [], 0, ""
    for char in text:
        if char == "[":
            depth += 1
        elif char == "]":
            depth -= 1
        if char == "," and depth == 0:
            names.append(current.strip())
            current = ""
        else:
            current += char
    names.append(current.strip())
    return [name for name in names if name]


def bench_configs(variant: Any) -> tuple[str, ...]:
    """``BENCH_CONFIGS`` of a variant's registry entry (a name, or a ``Variant``)."""
    name = variant if isinstance(variant, str) else variant.name
    return BENCH_CONFIGS.get(parse_variant_name(name).name, ())


def expand_variants(text: str) -> tuple[list[str], dict[str, str]]:
    """Canonical names to measure (naive first, no repeats), and unavailable ones -> why.

    Raises ``LookupError`` (the registry's ``VariantError``) for a bad or unknown name.
    """
    wanted: list[str] = []
    unavailable: dict[str, str] = {}
    for token in split_names(text):
        if token == "all":
            for entry in registry():
                if entry.variant is None:
                    unavailable[entry.name] = entry.reason
                    continue
                wanted.append(entry.variant.name)
                for config in bench_configs(entry.name):
                    try:
                        wanted.append(load_variant(config).name)
                    except LookupError as error:  # its inner variant is unavailable here
                        unavailable[config] = str(error)
        else:
            wanted.append(load_variant(token).name)
    ordered = [BASELINE] + [name for name in wanted if name != BASELINE]
    return list(dict.fromkeys(ordered)), unavailable


def default_names(names: list[str]) -> list[str]:
    """Of ``names``, those that are a registry entry's default (no options): one per variant."""
    defaults = {entry.variant.name for entry in registry() if entry.variant is not None}
    return [name for name in names if name in defaults]


def parallel_configs(names: list[str], counts: list[int]) -> dict[str, list[tuple[int, str]]]:
    """For each variant whose advertised configs set a worker or thread count: the count
    option spelled with each of ``counts`` -> {label: [(count, canonical name), ...]}."""
    found: dict[str, list[tuple[int, str]]] = {}
    for entry in registry():
        if entry.variant is None or entry.variant.name not in names:
            continue
        keys = {
            key
            for config in bench_configs(entry.name)
            for key, _ in parse_variant_name(config).options
            if key in PARALLEL_OPTIONS
        }
        for key in sorted(keys):
            label = f"{entry.name} ({key})"
            found[label] = [
                (count, load_variant(f"{entry.name}[{key}={count}]").name) for count in counts
            ]
    return found
