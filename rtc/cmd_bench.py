"""``rtc bench``: measure every variant on the reference scene; one new result file per run.
``rtc bench --numba-targets``: the numba variant's figures against its targets
(``harness.numba_targets``), printed."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TYPE_CHECKING, Any

from groundwork.sizes import parse_size
from harness import numba_targets
from harness.engine.plan import (
    AGAIN,
    BASELINE,
    FULL,
    QUICK,
    BenchSettings,
    expand_variants,
    refusal,
    split_names,
)
from harness.scenery.presets import resolve_scene
from harness.sections import DEFAULTS, NAMES, QUICK_DEFAULTS, help_text, measuring, measuring_order
from raytracer.camera import INTEGRATORS, WHITTED
from rtc.cli import (
    SWITCH,
    UserError,
    add_light_sampling,
    add_results_dir,
    cannot_write,
    check_memory,
    check_writable,
    publishing,
)
from scene import SceneError
from variants.registry import VariantError, load_variant, parse_variant_name

if TYPE_CHECKING:
    from harness.engine.plan import BenchSettings

NAME = "bench"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """rtc bench's options, in the order --help lists them."""
    _what_to_render(parser)
    _how_to_time(parser)
    _which_sections(parser)
    add_results_dir(
        parser,
        publish="write the run into the committed results/runs/ (a maintainer's run on a quiet "
        "machine; without it the run goes to results/local/runs/, your own, which git ignores)",
    )
    _gate(parser)
    _numba_targets(parser)


def _what_to_render(parser: argparse.ArgumentParser) -> None:
    """The scene, its size (or a preset of size, repeats and budget), the variants and how
    each renders."""
    parser.add_argument(
        "--scene",
        default="reference",
        metavar="FILE",
        help="a scene file, or a preset: reference (default), cpp-spheres, default-world",
    )
    sizes = parser.add_mutually_exclusive_group()
    sizes.add_argument("--size", metavar="WxH", help="the table's canvas size, e.g. 320x240")
    sizes.add_argument(
        "--quick",
        action="store_true",
        help="the default: the optimizations step by step (the ladder), 160x120 (compiled "
        "steps 640x480), 3 repeats, 6 s budget per row (18 s for naive)",
    )
    sizes.add_argument(
        "--full",
        action="store_true",
        help="every default section (the table, sweeps, scaling, the C++ workload, "
        "convergence, kata), 640x480, 5 repeats, 300 s budget per row (900 s for naive)",
    )
    parser.add_argument(
        "--variants",
        default="all",
        metavar="A,B|all",
        help="variant names (the registry's grammar), comma-separated; 'all' (default) = every "
        "available variant and the option sets it advertises; naive is always measured",
    )
    parser.add_argument("--spp", type=int, default=1, metavar="N", help="samples per pixel")
    parser.add_argument("--depth", type=int, default=5, metavar="N", help="recursion depth")
    parser.add_argument("--seed", type=int, default=0, metavar="N", help="sampling seed")
    parser.add_argument(
        "--integrator", default=WHITTED, choices=INTEGRATORS,
        help="how the table's and the other sections' renders gather light: whitted (the "
        "book's, the default) or path (Monte Carlo path tracing); a variant that has no such "
        "integrator is listed as unavailable with its reason (the convergence section and the "
        "path preset always path-trace)",
    )  # fmt: skip
    add_light_sampling(
        parser,
        "path tracing: on (the default) aims a shadow ray at every light from each diffuse "
        "hit; off finds an area light only where a path crosses it (as rtc render takes it; "
        "the convergence section measures both where a scene has an area light)",
    )
    parser.add_argument(
        "--epsilon", type=float, default=None, metavar="E",
        help="the over/under-point offset (default: the book's 0.0001; the Go renderer the "
        "reference scene comes from used 0.001)",
    )  # fmt: skip


def _how_to_time(parser: argparse.ArgumentParser) -> None:
    """The CPUs, repeats, retries and time budget of each row."""
    parser.add_argument(
        "--threads",
        type=int,
        default=None,
        metavar="N",
        help="CPUs each measuring process may use (pinned; default: all)",
    )
    parser.add_argument("--repeat", type=int, default=None, metavar="N", help="timed renders")
    parser.add_argument(
        "--again", type=int, default=AGAIN, metavar="N",
        help="a row that did not get the cores it asked for (busy) is timed again up to N "
        f"times after waiting for a quieter machine (default {AGAIN}; 0: never); the whole "
        f"run waits and re-times at most {QUICK.wait_budget:g} s (quick) or "
        f"{FULL.wait_budget:g} s (--full), then marks busy rows as such",
    )  # fmt: skip
    parser.add_argument(
        "--budget",
        type=float,
        default=None,
        metavar="SECONDS",
        help="seconds the timed renders of one row may take (naive: three times that); a "
        "slower variant is measured at a smaller size and its row says so (0: no limit)",
    )


def _which_sections(parser: argparse.ArgumentParser) -> None:
    """The sections to run, and the variants and meshes of those that take their own."""
    parser.add_argument(
        "--sections",
        default=None,
        metavar="A,B",
        help=f"which parts to run, of {', '.join(NAMES)} (default: {','.join(QUICK_DEFAULTS)} "
        f"in quick mode, and the table with --variants other than all; {','.join(DEFAULTS)} "
        f"with --full); {help_text()}",
    )
    parser.add_argument(
        "--mesh-variants", default="numba,numba[bvh=off]", metavar="A,B",
        help="the scene-size section's variants (default: numba,numba[bvh=off])",
    )  # fmt: skip
    parser.add_argument(
        "--light-variant", default="numba", metavar="NAME",
        help="the light-samples section's variant (default: numba)",
    )  # fmt: skip
    parser.add_argument(
        "--pass-variant", default="wavefront", metavar="NAME",
        help="the pass-size section's variant, its max_mb set per point (default: wavefront)",
    )  # fmt: skip
    parser.add_argument(
        "--sweep-on", default=None, metavar="CLUSTER",
        help="run the error sweep's configurations as tasks on a Dask cluster, all at once: "
        "dask[workers=N] (a local one) or dask[scheduler=tcp://HOST:8786] (a running one)",
    )  # fmt: skip
    parser.add_argument(
        "--meshes", default="all", metavar="A,B",
        help="the scene-size section's meshes: 1k, 10k, 100k, 1m (default: all)",
    )  # fmt: skip


def _gate(parser: argparse.ArgumentParser) -> None:
    """The opt-in performance gate: this run against an earlier one."""
    gate = parser.add_argument_group(
        "a performance gate (opt-in; the default CI does not run it: its machine is noisy)",
        "after the run is written, compare it with RUN as rtc compare does and exit 1 when a "
        "variant measured at one size in both is significantly slower (Student's t-test over "
        "the timed renders, 95%) by more than PCT",
    )
    gate.add_argument(
        "--compare-to", metavar="RUN", default=None,
        help="a run file, its name in DIR/runs/, latest or previous (resolved before the run)",
    )  # fmt: skip
    gate.add_argument(
        "--fail-slower", metavar="PCT", default=None,
        help="the slow-down allowed, e.g. 25%% (with --compare-to; without it: compare only)",
    )  # fmt: skip


def _numba_targets(parser: argparse.ArgumentParser) -> None:
    """rtc bench --numba-targets and its own options."""
    targets = parser.add_argument_group(
        "the numba variant's targets",
        "rtc bench --numba-targets [--runs N] [--skip SECTION] ...: the numba variant's "
        "figures against its targets (cold compile, renders at 640x480, the whole rtc render "
        "command, the speed-up over naive, allocations, MRay/s, options, regions, pooled), "
        "printed; no result file, and the table's options do not apply",
    )
    targets.add_argument(
        "--numba-targets", action="store_true", help="run that benchmark instead of the table"
    )
    numba_targets.add_arguments(targets)


NUMBA_TARGET_OPTIONS = ("runs", "naive_size", "naive_pixels", "skip")


def settings_from(args: argparse.Namespace) -> BenchSettings:
    """The run's settings from the command line; ``UserError`` for a bad value."""
    mode = FULL if args.full else QUICK
    try:
        scene = resolve_scene(args.scene)
        size = parse_size(args.size) if args.size is not None else mode.size
    except ValueError as error:
        raise UserError(str(error)) from None
    for flag, value, low, high in (
        ("--spp", args.spp, 1, 1 << 20),
        ("--depth", args.depth, 0, 100),
        ("--seed", args.seed, 0, 2**64 - 1),
        ("--repeat", args.repeat, 1, 1000),
        ("--threads", args.threads, 1, 4096),
        ("--again", args.again, 0, 100),
    ):
        if value is not None and not low <= value <= high:
            raise UserError(f"{flag} {value}: expected a whole number {low} to {high}")
    if args.epsilon is not None and not 0 < args.epsilon < 1:
        raise UserError(f"--epsilon {args.epsilon}: expected a number between 0 and 1")
    if args.budget is not None and args.budget < 0:
        raise UserError(f"--budget {args.budget}: expected seconds, 0 or more (0: no limit)")
    asked = args.sections
    if asked is None:  # quick: the ladder; the table too for variants named (a learner's)
        quick = QUICK_DEFAULTS if args.variants == "all" else ("table", *QUICK_DEFAULTS)
        asked = ",".join(DEFAULTS if mode is FULL else quick)
    sections = tuple(s.strip() for s in asked.split(",") if s.strip())
    unknown = [s for s in sections if s not in NAMES]
    if unknown or not sections:
        raise UserError(f"--sections {asked!r}: choose from {', '.join(NAMES)}")
    sections = tuple(measuring_order(sections))  # the order they are measured in
    try:
        names, unavailable = expand_variants(args.variants)
    except LookupError as error:
        raise UserError(f"--variants: {error.args[0]}") from None
    names = _integrating(names, args.integrator, unavailable)
    budget = mode.budget if args.budget is None else (args.budget or None)
    if budget is None:  # every row renders at the size asked (a budget shrinks slow rows)
        for name in (BASELINE, *names):
            check_memory(name, size.width, size.height)
    meshes, mesh_variants = _scene_size_options(args)
    check_writable(args.results_dir, f"--results-dir {str(args.results_dir)!r}")
    return BenchSettings(
        scene=scene,
        size=size,
        samples=args.spp,
        depth=args.depth,
        seed=args.seed,
        threads=args.threads,
        repeat=args.repeat or mode.repeat,
        budget=budget,
        variants=names,
        sections=sections,
        mode=mode,
        results=args.results_dir,
        unavailable=unavailable,
        epsilon=args.epsilon,
        mesh_variants=mesh_variants,
        meshes=meshes,
        light_variant=args.light_variant,
        pass_variant=args.pass_variant,
        sweep_on=_sweep_on(args.sweep_on, sections),
        again=args.again,
        integrator=args.integrator,
        light_sampling=SWITCH[args.light_sampling or "on"],
        variants_asked=",".join(split_names(args.variants)),
    )


def _integrating(names: list[str], integrator: str, unavailable: dict[str, str]) -> list[str]:
    """Of ``names``, those that render with ``integrator``; the others go to ``unavailable``
    with their one-line reason. Naive (the reference) renders with every integrator."""
    kept = []
    for name in names:
        why = refusal(load_variant(name), integrator)
        if why is None:
            kept.append(name)
        else:
            unavailable[name] = why
    return kept


def _sweep_on(text: str | None, sections: tuple[str, ...]) -> str | None:
    """``--sweep-on`` checked: its spelling, the sweep among the sections, and a running
    scheduler reached now (before minutes of measuring), one ``UserError`` line otherwise."""
    if text is None:
        return None
    if "sweep" not in sections:
        raise UserError("--sweep-on: the sweep is not among --sections (add sweep)")
    # deferred: saves ~25 ms of rtc --help (harness.engine.cluster_jobs)
    from harness.engine.cluster_jobs import cluster_options

    # deferred: saves ~40 ms of rtc --help (dask's variant)
    from variants.dask_cluster import probe

    try:
        _workers, scheduler, timeout = cluster_options(text)
        if scheduler is not None:
            probe(scheduler, timeout)
    except (ValueError, OSError, TimeoutError) as error:
        raise UserError(f"--sweep-on: {error}") from None
    return text


def _scene_size_options(args: argparse.Namespace) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """``--meshes`` and ``--mesh-variants`` checked: (mesh names, variant names). A variant
    the registry cannot build here (an option not there yet) is recorded as unavailable by
    the section, not refused: only the spelling is checked."""
    # deferred: saves ~55 ms of rtc --help (the scene-size section)
    from harness.sections.scene_size.measure import mesh_names

    try:
        meshes = mesh_names(args.meshes)
    except ValueError as error:
        raise UserError(f"--meshes: {error}") from None
    names = tuple(split_names(args.mesh_variants))
    for name in names:
        try:
            parse_variant_name(name)
        except VariantError as error:
            raise UserError(f"--mesh-variants: {error.args[0]}") from None
    if not names:
        raise UserError("--mesh-variants: name at least one variant, e.g. numba")
    try:
        parse_variant_name(args.light_variant)
    except VariantError as error:
        raise UserError(f"--light-variant: {error.args[0]}") from None
    try:
        parse_variant_name(args.pass_variant)
    except VariantError as error:
        raise UserError(f"--pass-variant: {error.args[0]}") from None
    return meshes, names


def run(args: argparse.Namespace) -> int:
    publishing(args)
    given = [
        f"--{o.replace('_', '-')}"
        for o in NUMBA_TARGET_OPTIONS
        if getattr(args, o, None) not in (None, [])
    ]
    baseline = _gate_baseline(args)
    if args.numba_targets:
        if baseline is not None:
            raise UserError("--compare-to, --fail-slower: not with --numba-targets")
        try:
            numba_targets.settings(args)
        except ValueError as error:
            raise UserError(str(error)) from None
        return numba_targets.run(args)
    if given:
        raise UserError(f"{', '.join(given)}: only with --numba-targets")

    # deferred: saves ~65 ms of rtc --help (the bench engine)
    from harness.engine.bench import run_bench

    # deferred: saves ~25 ms of rtc --help (the run files)
    from harness.engine.results import load_run

    # deferred: saves ~0.6 s of rtc --help (every section's report)
    from harness.report.console import console_table

    started = time.monotonic()

    def log(message: str) -> None:
        elapsed = time.monotonic() - started
        print(f"rtc bench [{elapsed:5.0f} s]: {message}", file=sys.stderr, flush=True)

    settings = settings_from(args)  # errors: one line, before any other (no progress yet)
    # what the run measures, on stdout: stderr's lines are progress and, for a scene that
    # does not load, its one error line
    print(f"rtc bench: {', '.join(settings.sections)} of {len(settings.variants)} variant(s), "
          f"mode {settings.mode.name}, into {settings.results}", flush=True)  # fmt: skip

    try:
        path = run_bench(settings, log, measuring(settings.sections))
    except SceneError as error:  # checked before anything is measured or written
        raise UserError(str(error)) from None
    except OSError as error:  # a full disk: no run file, no lock, no staging folder
        raise UserError(cannot_write(error, settings.results)) from None
    print(console_table(load_run(path)["rtc"]))
    print(f"rtc bench: wrote {path}")
    if baseline is None:
        return 0
    # deferred: saves ~70 ms of rtc --help (harness.report.compare)
    from harness.report.compare import gate

    report, failures = gate(baseline[0], load_run(path)["rtc"], baseline[1])
    print("\n".join(report))
    for line in failures:
        print(f"rtc bench: slower: {line}", file=sys.stderr)
    return 1 if failures else 0


def _gate_baseline(args: argparse.Namespace) -> tuple[dict[str, Any], float | None] | None:
    """``--compare-to`` and ``--fail-slower`` checked before the run: (the run compared with,
    the percentage allowed or None), or None without ``--compare-to``."""
    # deferred: saves ~70 ms of rtc --help (harness.report.compare)
    from harness.report.compare import RunChoiceError, load, parse_percent

    if args.compare_to is None:
        if args.fail_slower is not None:
            raise UserError("--fail-slower: give the run to compare with, --compare-to RUN")
        return None
    try:
        percent = None if args.fail_slower is None else parse_percent(args.fail_slower)
    except ValueError as error:
        raise UserError(f"--fail-slower {error}") from None
    try:
        return load(args.compare_to, args.results_dir), percent
    except RunChoiceError as error:
        raise UserError(f"--compare-to {error}") from None
