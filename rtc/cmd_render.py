"""``rtc render SCENE.yml -o OUT.png``: render a scene file (the book's YAML format) with a
variant, as PNG or PPM."""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from groundwork.images import canvas_problem, write_image
from groundwork.progress import MODES, Progress, compile_ticker, duration
from raytracer.camera import INTEGRATORS, PATH, RenderSettings
from rtc.cli import (
    SWITCH,
    UserError,
    add_light_sampling,
    check_memory,
    check_output,
    parse_size,
    say,
)
from scene import SceneError, load_scene
from variants.registry import (
    RenderError,
    VariantError,
    load_variant,
    parse_variant_name,
    variant_names,
)

NAME = "render"
QUICK_EXIT = True  # its files are written and closed when it returns (``cli._exit_at_once``)

LONG_SECONDS = 30.0  # a render estimated to take longer gets the line naming a faster variant
FAST_VARIANT = "numba"  # one of the project's own (OWN): named without a look-up
COMPILED = ("numba", "wavefront")  # a render through one of these gets no such line
# How many times faster numba renders than a pure-Python variant, at the least (the bench's
# table, results/README.md: about 14,000x naive, 400x cached and robust, 130x prealloc): the
# line's estimate of numba's time errs on the long side.
SPEED_UP = {"prealloc": 100.0}
SPEED_UP_OTHERS = 1000.0
# A path-traced render through a Python variant is timed on a few pixels before it starts
# (numba's speed-up above is the book's integrator's): at most PROBE_PIXELS, spread over the
# image, and no more once PROBE_SECONDS have passed.
PROBE_PIXELS = 16
PROBE_SECONDS = 1.0
# the flags that set RenderSettings fields (None: not given; the scene file's render item,
# then RenderSettings' default, decides)
SETTING_FLAGS = {
    "integrator": "--integrator", "depth": "--depth", "samples": "--samples", "seed": "--seed",
    "roulette": "--roulette", "epsilon": "--epsilon", "light_sampling": "--light-sampling",
}  # fmt: skip


LIGHT_SAMPLING_HELP = (
    "path tracing: on (the default) aims a shadow ray at every light from each diffuse hit; "
    "off finds an area light only where a path crosses it (the same picture, noisier; point "
    "lights are sampled either way; docs/scene-format.md)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", type=Path, metavar="SCENE.yml", help="the scene file")
    parser.add_argument(
        "-o", "--output", required=True, metavar="OUT.png",
        help="the image to write: .png or .ppm (checked before rendering: its folder must "
        "exist and be writable)",
    )  # fmt: skip
    parser.add_argument(
        "--size", metavar="WxH",
        help="image size in pixels, e.g. 160x120 (default: the camera's width and height; "
        "the field of view stays)",
    )  # fmt: skip
    variant = parser.add_argument(
        "--variant", default="naive", metavar="V",
        help="the tracer to use, one of: %(registered)s (default: naive, the "
        "book's pure-Python reference; numba is the fastest); a wrapper takes the variant "
        "it runs after a colon, e.g. pooled:cached; options in brackets, e.g. "
        "numba[threads=1]; rtc variants describes each",
    )  # fmt: skip
    variant.registered = _Registered()  # type: ignore[attr-defined]
    parser.add_argument(
        "--integrator", metavar="NAME",
        help="how light is gathered: whitted (the book's recursive ray tracer, the default) "
        "or path (Monte Carlo path tracing: a sky, emissive surfaces, soft shadows and "
        "colour bleeding; docs/scene-format.md); wins over the scene file's render item",
    )  # fmt: skip
    parser.add_argument(
        "--depth", type=int, metavar="N",
        help="how many times a ray may be reflected or refracted, or a path may scatter "
        "(default: the scene file's, else 5, the book's)",
    )  # fmt: skip
    parser.add_argument(
        "--roulette", type=int, metavar="N",
        help="path tracing: Russian roulette ends paths at random from bounce N on, "
        "keeping the picture unbiased (default: the scene file's, else 0: off)",
    )  # fmt: skip
    add_light_sampling(parser, LIGHT_SAMPLING_HELP)
    parser.add_argument(
        "--epsilon", type=float, default=None, metavar="E",
        help="the offset for over_point/under_point (default: the book's 0.0001; "
        "0.001 matches the Go renderer's reference image)",
    )  # fmt: skip
    parser.add_argument(
        "--samples", type=int, metavar="N",
        help="rays per pixel (default: the scene file's, else 1, through the pixel centre "
        "as in the book)",
    )  # fmt: skip
    parser.add_argument(
        "--seed", type=int, metavar="N",
        help="chooses the sample positions when --samples is above 1, and the path "
        "integrator's random numbers (default: the scene file's, else 0)",
    )  # fmt: skip
    parser.add_argument(
        "--progress", choices=MODES, default="auto",
        help="how to show the progress of a render that takes more than a second, on "
        "stderr: auto (the default: a bar on a terminal, else lines), bar, lines (one every "
        "10 s) or none",
    )  # fmt: skip
    parser.add_argument(
        "--explain", action="store_true",
        help="print what the variant will run for this scene (e.g. the features a compiled "
        "kernel is specialized to) before rendering",
    )  # fmt: skip


def _flag_settings(args: argparse.Namespace) -> dict[str, Any]:
    """The ``RenderSettings`` fields the flags give, each checked: a ``UserError`` naming
    the flag for a bad value."""
    options = {
        field: getattr(args, field)
        for field in SETTING_FLAGS
        if getattr(args, field, None) is not None
    }
    if "light_sampling" in options:
        options["light_sampling"] = SWITCH[options["light_sampling"]]
    if "integrator" in options and options["integrator"] not in INTEGRATORS:
        raise UserError(
            f"bad option {SETTING_FLAGS['integrator']} {options['integrator']!r}: expected "
            f"{' or '.join(INTEGRATORS)}"
        )
    for field, value in options.items():
        try:
            RenderSettings(**{field: value})
        except ValueError as error:
            message = str(error).removeprefix("RenderSettings: ")
            raise UserError(f"bad option {SETTING_FLAGS[field]}: {message}") from None
    return options


def _settings(flags: dict[str, Any], scene: Any) -> RenderSettings:
    """The render's settings: the flags given, else the scene file's ``- add: render``
    item, else ``RenderSettings``' defaults (each value is checked where it was read)."""
    return RenderSettings(**{**scene.render, **flags})


class _Registered:
    """The registered variant names as ``--help`` prints them, looked up only when it
    does (a render does not pay for the lookup)."""

    def __str__(self) -> str:
        return ", ".join(_registered())


def _registered() -> list[str]:
    """The registered variant names, for ``--help`` (naive first)."""
    return variant_names()


def _python_chain(name: str) -> list[str] | None:
    """The variants a render through ``name`` goes through (``pooled:cached``: pooled,
    cached), when none of them is compiled; else None."""
    try:
        spec: Any = parse_variant_name(name)
    except VariantError:
        return None
    chain = []
    while spec is not None:
        chain.append(spec.name)
        spec = spec.inner
    return None if any(part in COMPILED for part in chain) else chain


def _advice(name: str, settings: RenderSettings) -> Callable[[float], str | None] | None:
    """For a render with the book's integrator through a pure-Python variant (naive,
    cached, prealloc, robust, a learner's, or a pool of them): given the render's estimated
    seconds, a line naming the variant that renders it fast when the render will take
    longer than ``LONG_SECONDS``, else None. None for a render that goes through a compiled
    variant already, and for a path-traced render
    (``_path_estimate`` spoke before it started, naming numba)."""
    chain = _python_chain(name)
    if chain is None or settings.integrator == PATH:
        return None
    speed_up = min(SPEED_UP.get(part, SPEED_UP_OTHERS) for part in chain)

    def advise(seconds: float) -> str | None:
        if seconds < LONG_SECONDS:
            return None
        fast = seconds / speed_up
        when = "in under a second" if fast < 1.0 else f"in about {duration(fast)}"
        return (
            f"rtc render: {name} will take about {duration(seconds)} for this render; "
            f"--variant {FAST_VARIANT} renders it {when} (plus, the first time, a compile "
            "of some seconds)"
        )

    return advise


def _path_estimate(variant: Any, camera: Any, world: Any, settings: RenderSettings) -> str | None:
    """For a path-traced render through a pure-Python variant: the line saying how long it
    will take, when that is longer than ``LONG_SECONDS``, from the time ``_probe`` took;
    else None. Said before the render starts."""
    if settings.integrator != PATH or variant.tracer is None:
        return None
    if _python_chain(variant.name) is None:
        return None
    pixels, seconds = _probe(variant.tracer, camera, world, settings)
    total = seconds / pixels * camera.hsize * camera.vsize
    if total < LONG_SECONDS:
        return None
    rays = f"{settings.samples} ray{'s' if settings.samples > 1 else ''} per pixel"
    return (
        f"rtc render: {variant.name} will take about {duration(total)} of one core for this "
        f"path-traced render ({rays}, up to {settings.depth + 1} hits each; timed on "
        f"{pixels} pixel{'s' if pixels > 1 else ''}); fewer --samples, a lower --depth or "
        f"a smaller --size shortens it, or --variant {FAST_VARIANT} (compiled)"
    )


def _probe(tracer: Any, camera: Any, world: Any, settings: RenderSettings) -> tuple[int, float]:
    """(pixels traced, seconds they took): up to ``PROBE_PIXELS`` pixels on a grid over the
    image, one at a time through ``tracer.render_region``, stopping once ``PROBE_SECONDS``
    have passed (``_clock``)."""
    side = math.isqrt(PROBE_PIXELS)
    width, height = camera.hsize, camera.vsize
    grid = [
        ((2 * i + 1) * width // (2 * side), (2 * j + 1) * height // (2 * side))
        for j in range(side)
        for i in range(side)
    ]
    start = _clock()
    traced = 0
    for x, y in grid:
        tracer.render_region(camera, world, settings, (x, y, x + 1, y + 1))
        traced += 1
        if _clock() - start >= PROBE_SECONDS:
            break
    return traced, _clock() - start


def _provide(path: Path) -> bool:
    """The scene loader's maker of a missing generated mesh (``make_meshes.provide``),
    imported only when a scene names one (most renders never do)."""
    from harness.scenery.make_meshes import provide

    return provide(path)


def _clock() -> float:
    """The progress's clock (tests put one of their own here)."""
    return time.monotonic()


def _progress(
    args: argparse.Namespace, rows: int, name: str, settings: RenderSettings
) -> Progress:
    """The render's progress on stderr, counting rows (``groundwork.progress``)."""
    return Progress(
        "rtc render", rows, "row", mode=args.progress, clock=_clock,
        advice=_advice(name, settings),
    )  # fmt: skip


def _watch_compiles(progress: Progress) -> tuple[list[float], Callable[[], None]]:
    """Say on stderr what numba compiles, that it happens once (the first render of a new
    kind of scene compiles for seconds) and, every few seconds, that it still does; the
    seconds spent, one entry per compile, which the progress leaves out of the render's
    time, and a function that stops watching. Nothing is watched unless the variant loaded
    numba's kernels module."""
    spent: list[float] = []
    if "variants.numba" not in sys.modules:
        return spent, lambda: None
    # deferred: saves ~150 ms of rtc --help and of a render by another variant
    from variants.numba.specialize import kernel_folder, on_compile

    # the ticker first: it has stopped when the end of a compile is told
    ticking = on_compile(compile_ticker(lambda text: progress.write(f"rtc render: {text}")))

    def told(what: str, seconds: float | None) -> None:
        if seconds is None:
            progress.write(
                f"rtc render: compiling {what}: first time only, kept in {kernel_folder()}"
            )
        else:
            spent.append(seconds)
            progress.exclude(seconds)
            progress.write(f"rtc render: compiled in {seconds:.1f} s")

    telling = on_compile(told)

    def stop() -> None:
        ticking()
        telling()

    return spent, stop


def run(args: argparse.Namespace) -> int:
    flags = _flag_settings(args)
    size = parse_size(args.size) if args.size is not None else None
    output = check_output(args.output)
    try:
        variant = load_variant(args.variant)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0] if error.args else error}") from None
    try:
        scene = load_scene(args.scene, variant.api, variant=variant.name, provide_mesh=_provide)
        if size is not None:
            scene = scene.resized(*size)
        world = variant.world_for(scene)
    except SceneError as error:
        raise UserError(str(error)) from None
    camera = scene.camera
    settings = _settings(flags, scene)
    if settings.integrator == PATH and variant.tracer is None:
        raise UserError(
            f"{variant.name} renders with a render() of its own, which takes no integrator: "
            "path-trace with a variant built on raytracer.tracer.Tracer (naive, cached, "
            "robust, prealloc, pooled or dask over them), or render with --integrator whitted"
        )
    check_memory(variant.name, camera.hsize, camera.vsize)
    for warning in scene.warnings:
        say("render", f"warning: {warning}")
    print(
        f"rendering {args.scene} at {camera.hsize}x{camera.vsize} with {variant.name} "
        f"({_describe(settings)})",
        flush=True,
    )
    if args.explain:
        tracer = variant.tracer
        print(
            tracer.explain(world)
            if tracer is not None
            else f"{variant.name}: nothing to explain"
        )
        for note in scene.notes:
            print(f"scene: {note}")
    try:
        estimate = _path_estimate(variant, camera, world, settings)
    except RenderError as error:
        raise UserError(f"{variant.name} could not render {args.scene}: {error}") from None
    if estimate is not None:
        print(estimate, file=sys.stderr, flush=True)
    progress = _progress(args, camera.vsize, variant.name, settings)
    compiles, unwatch = _watch_compiles(progress)
    start = time.perf_counter()
    try:
        image = variant.api["render"](camera, world, settings, progress)
    except RenderError as error:
        raise UserError(f"{variant.name} could not render {args.scene}: {error}") from None
    except RecursionError:  # a learner's tracer that calls itself for ever
        raise UserError(
            f"{variant.name} could not render {args.scene}: its code recursed past Python's "
            f"limit of {sys.getrecursionlimit()} calls (RecursionError)"
        ) from None
    finally:
        unwatch()
        progress.close()
    elapsed = time.perf_counter() - start
    wrong = canvas_problem(image, camera.hsize, camera.vsize)
    if wrong is not None:
        raise UserError(f"{variant.name}'s render {wrong}; nothing was written")
    try:
        write_image(image, output)
    except OSError as error:
        raise UserError(f"cannot write {args.output!r}: {error.strerror or error}") from None
    if compiles:
        compiled = sum(compiles)
        print(
            f"rendered in {elapsed - compiled:.2f} s, after {compiled:.1f} s compiling (first "
            f"time only) -> {output}"
        )
    else:
        print(f"rendered in {elapsed:.2f} s -> {output}")
    return 0


def _describe(settings: RenderSettings) -> str:
    """The settings for the line that starts a render: the book's integrator as before
    (depth, epsilon, samples); the path integrator's with its seed and roulette."""
    samples = f"{settings.samples} sample{'s' if settings.samples > 1 else ''} per pixel"
    if settings.integrator != PATH:
        return f"depth {settings.depth}, epsilon {settings.epsilon:g}, {samples}"
    roulette = f"from bounce {settings.roulette}" if settings.roulette else "off"
    lights = "" if settings.light_sampling else ", light sampling off"
    return (
        f"path tracing: depth {settings.depth}, {samples}, seed {settings.seed}, roulette "
        f"{roulette}{lights}, epsilon {settings.epsilon:g}"
    )
