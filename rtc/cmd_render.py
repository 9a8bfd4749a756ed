"""``rtc render SCENE.yml -o OUT.png``: render a scene file (the book's YAML format) with a
variant, as PNG or PPM."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from harness.images import write_image
from harness.make_meshes import provide
from raytracer.camera import RenderSettings
from rtc.cli import UserError, check_memory, check_output
from rtc.cmd_demo import parse_size
from scene import SceneError, load_scene

NAME = "render"
HELP = "render a scene file (the book's YAML scene format) to a PNG or PPM image"


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
    parser.add_argument(
        "--variant", default="naive", metavar="V", help="the tracer to use (default: naive)"
    )
    parser.add_argument(
        "--depth", type=int, default=5, metavar="N",
        help="how many times a ray may be reflected or refracted (default: 5, the book's)",
    )  # fmt: skip
    parser.add_argument(
        "--epsilon", type=float, default=None, metavar="E",
        help="the offset for over_point/under_point (default: the book's 0.0001; "
        "0.001 matches the Go renderer's reference image)",
    )  # fmt: skip
    parser.add_argument(
        "--samples", type=int, default=1, metavar="N",
        help="rays per pixel (default: 1, through the pixel centre as in the book)",
    )  # fmt: skip
    parser.add_argument(
        "--seed", type=int, default=0, metavar="N",
        help="chooses the sample positions when --samples is above 1 (default: 0)",
    )  # fmt: skip
    parser.add_argument(
        "--explain", action="store_true",
        help="print what the variant will run for this scene (e.g. the features a compiled "
        "kernel is specialized to) before rendering",
    )  # fmt: skip


def _settings(args: argparse.Namespace) -> RenderSettings:
    options: dict[str, Any] = {"depth": args.depth, "samples": args.samples, "seed": args.seed}
    if args.epsilon is not None:
        options["epsilon"] = args.epsilon
    try:
        return RenderSettings(**options)
    except ValueError as error:
        message = str(error).removeprefix("RenderSettings: ")
        raise UserError(f"bad option: {message}") from None


def _progress_bar(rows: int) -> tuple[Callable[[int], object] | None, Callable[[], None]]:
    """A tqdm bar on stderr counting rows, only when stderr is a terminal; (update, close)."""
    if not sys.stderr.isatty():
        return None, lambda: None
    from tqdm import tqdm

    bar = tqdm(total=rows, unit="row", file=sys.stderr, leave=False, dynamic_ncols=True)
    return bar.update, bar.close


def _watch_compiles() -> tuple[list[float], Callable[[], None]]:
    """Say on stderr what numba compiles and that it happens once (the first render of a
    new kind of scene compiles for seconds); the seconds spent, one entry per compile.
    Nothing is watched unless the variant loaded numba's kernels module. Returns the list
    and what stops the watch (a process that renders again, a test, is told nothing more)."""
    spent: list[float] = []
    if "variants.numba" not in sys.modules:
        return spent, lambda: None
    from variants.numba.specialize import kernel_folder, on_compile

    def told(what: str, seconds: float | None) -> None:
        if seconds is None:
            print(
                f"rtc render: compiling {what}: first time only, kept in {kernel_folder()}",
                file=sys.stderr,
                flush=True,
            )
        else:
            spent.append(seconds)
            print(f"rtc render: compiled in {seconds:.1f} s", file=sys.stderr, flush=True)

    return spent, on_compile(told)


def run(args: argparse.Namespace) -> int:
    from variants.registry import RenderError, load_variant

    settings = _settings(args)
    size = parse_size(args.size) if args.size is not None else None
    output = check_output(args.output)
    try:
        variant = load_variant(args.variant)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0] if error.args else error}") from None
    try:
        scene = load_scene(args.scene, variant.api, variant=variant.name, provide_mesh=provide)
        if size is not None:
            scene = scene.resized(*size)
        world = variant.world_for(scene)
    except SceneError as error:
        raise UserError(str(error)) from None
    camera = scene.camera
    check_memory(variant.name, camera.hsize, camera.vsize)
    for warning in scene.warnings:
        print(f"rtc render: warning: {warning}", file=sys.stderr, flush=True)
    print(
        f"rendering {args.scene} at {camera.hsize}x{camera.vsize} with {variant.name} "
        f"(depth {settings.depth}, epsilon {settings.epsilon:g}, "
        f"{settings.samples} sample{'s' if settings.samples > 1 else ''} per pixel)",
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
    compiles, unwatch = _watch_compiles()
    update, close = _progress_bar(camera.vsize)
    start = time.perf_counter()
    try:
        image = variant.api["render"](camera, world, settings, update)
    except RenderError as error:
        raise UserError(f"{variant.name} could not render {args.scene}: {error}") from None
    finally:
        close()
        unwatch()
    elapsed = time.perf_counter() - start
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
