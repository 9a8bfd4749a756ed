"""``rtc profile SCENE.yml --variant NAME``: where a render's time goes (issue 18): the
stages timed, the top functions by own and cumulative time (cProfile), a flame graph
(py-spy); for a compiled variant (numba), the stages: load, pack, compile or cache load,
trace, encode. The render of chapter 7, through ``harness.sections.profile.measure``."""

from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

from groundwork.sizes import Size
from harness.engine.plan import refusal
from harness.scenery.make_meshes import provide
from raytracer.camera import INTEGRATORS, WHITTED
from rtc.cli import (
    SWITCH,
    UserError,
    add_light_sampling,
    check_memory,
    check_target,
    parse_size,
    say,
)
from scene import SceneError, load_scene
from variants.registry import load_variant

NAME = "profile"
DEFAULT_OUTPUT = Path("results/local/profile")
OUTPUTS = (".svg", ".pstats", ".png")  # profile-SCENE-VARIANT.*: the files the profile writes


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", type=Path, metavar="SCENE.yml", help="the scene file")
    parser.add_argument(
        "--variant", required=True, metavar="NAME",
        help="the tracer to profile: naive, cached, prealloc, numba, pooled:prealloc ...",
    )  # fmt: skip
    parser.add_argument(
        "--size", metavar="WxH",
        help="image size in pixels (default: the camera's scaled to about 768 pixels, e.g. "
        "32x24, where a naive render of the reference scene takes about 10 s, and two to "
        "three times that under cProfile; for a faster variant, numba or wavefront, the size "
        "whose trace takes about half a second, from a probe render at 8x6)",
    )  # fmt: skip
    parser.add_argument(
        "--spp", type=int, default=1, metavar="N", help="samples per pixel (default: 1)"
    )
    parser.add_argument(
        "--integrator", default=WHITTED, choices=INTEGRATORS,
        help="whitted (the book's, the default) or path (Monte Carlo path tracing)",
    )  # fmt: skip
    add_light_sampling(
        parser,
        "path tracing: on (the default) aims a shadow ray at every light from each diffuse "
        "hit; off finds an area light only where a path crosses it (as rtc render takes it)",
    )
    parser.add_argument(
        "--top", type=int, default=15, metavar="N",
        help="functions in each table (default: 15)",
    )  # fmt: skip
    parser.add_argument(
        "-o", "--output-dir", type=Path, default=DEFAULT_OUTPUT, metavar="DIR",
        help="where the flame graph (.svg), the cProfile statistics (.pstats) and the "
        f"picture (.png) go, named profile-SCENE-VARIANT (default: {DEFAULT_OUTPUT}, a "
        "results folder of your own that git ignores)",
    )  # fmt: skip
    parser.add_argument(
        "--no-flame", action="store_true",
        help="skip the flame graph (py-spy's sampling run); the stages are still timed",
    )  # fmt: skip


def _folder(path: Path) -> Path:
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise UserError(f"-o {str(path)!r}: cannot make the folder: {error.strerror}") from None
    if not path.is_dir():
        raise UserError(f"-o {str(path)!r}: not a folder")
    return path


PROBE = Size(8, 6)


def _per_pixel(variant: str, args: argparse.Namespace) -> float | None:
    """Seconds per pixel of ``variant`` on the scene, from a second render at ``PROBE`` (the
    first loads, or compiles once, a compiled variant's kernels), for the default size; None
    when the probe fails (the render itself then says why)."""
    # deferred: saves ~60 ms of rtc --help (the measuring process's renderer)
    from harness.engine.child import Renderer

    job = {"variant": variant, "scene": {"name": args.scene.stem, "path": str(args.scene)},
           "depth": 5, "seed": 0, "integrator": args.integrator,
           "light_sampling": _light_sampling(args)}  # fmt: skip
    try:
        renderer = Renderer(job)
        renderer.render(PROBE, args.spp)
        return renderer.timed(PROBE, args.spp).wall / PROBE.pixels
    except Exception:  # only a default size: the profile's own render reports the error
        return None


def _light_sampling(args: argparse.Namespace) -> bool:
    """``--light-sampling``: True unless off."""
    return SWITCH[args.light_sampling or "on"]


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~40 ms of rtc --help (the profiler)
    from harness.sections.profile.profiler import Request, is_compiled, profile, profile_size, slug

    # deferred: saves ~75 ms of rtc --help (the profile's report)
    from harness.sections.profile.report import text

    size = Size(*parse_size(args.size)) if args.size is not None else None
    if args.spp < 1:
        raise UserError(f"--spp {args.spp}: expected 1 or more samples per pixel")
    if args.top < 1:
        raise UserError(f"--top {args.top}: expected 1 or more functions")
    try:
        variant = load_variant(args.variant)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0] if error.args else error}") from None
    why = refusal(variant, args.integrator)
    if why is not None:
        raise UserError(f"--integrator {args.integrator}: {why}")
    try:
        scene = load_scene(args.scene, variant.api, variant=variant.name, provide_mesh=provide)
    except SceneError as error:
        raise UserError(str(error)) from None
    for warning in scene.warnings:
        say("profile", f"warning: {warning}")
    if size is None:
        camera = Size(scene.camera.hsize, scene.camera.vsize)
        size = profile_size(camera, _per_pixel(variant.name, args))
    check_memory(variant.name, size.width, size.height)
    folder = _folder(args.output_dir)
    request = Request(
        variant=variant.name, scene=args.scene.resolve(), size=size, folder=folder,
        stem=f"profile-{slug(args.scene.stem)}-{slug(variant.name)}", samples=args.spp,
        integrator=args.integrator, light_sampling=_light_sampling(args), top=args.top,
        flame=not args.no_flame,
        compiled=is_compiled(variant),
    )  # fmt: skip
    for suffix in OUTPUTS:  # never written through a link, nor into a pipe (it would block)
        target = folder / f"{request.stem}{suffix}"
        check_target(target, f"-o {str(args.output_dir)!r}: cannot write {target.name!r}")
    print(
        f"profiling {args.scene} at {size} with {variant.name} ({args.spp} sample"
        f"{'s' if args.spp > 1 else ''} per pixel, depth {request.depth}, the {args.integrator} "
        f"integrator{'' if request.light_sampling else ', light sampling off'})",
        flush=True,
    )

    def log(message: str) -> None:
        say("profile", message)

    jobs = Path(tempfile.mkdtemp(prefix="rtc-profile-"))
    try:
        entry = profile(request, jobs, log)
    finally:
        shutil.rmtree(jobs, ignore_errors=True)
    if entry.get("status") != "ok":
        raise UserError(f"{variant.name} could not render {args.scene}: {entry.get('error')}")
    picture = folder / f"{request.stem}.png"
    if picture.is_file():
        entry["image"] = str(picture)
    print("\n".join(text(entry, args.top)))
    return 0
