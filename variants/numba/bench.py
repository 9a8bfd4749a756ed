"""The numba variant's figures, against the targets of its issue (``python -m
variants.numba.bench``).

Prints, each as the median of ``--runs`` runs with the CPU share each run got (CPU seconds
of the process over wall seconds: up to 1.0 per thread that really ran):

1. cold start: compiling the reference scene's kernels in a fresh kernel folder (a
   subprocess), target under 40 s;
2. the reference scene, 640x480, 1 sample, depth 5, epsilon 0.001, compile excluded:
   1 thread (target 0.15 s) and 2 threads (target 0.08 s); and how evenly the interleaved
   rows split the work (each thread's rows timed alone, in CPU seconds);
3. the whole ``rtc render reference.yml -o out.png`` command with cached kernels, 2 threads
   (target 0.7 s);
4. ``naive`` at 160x120 in the same run, and the speed-up per pixel (target 10,000x);
5. numba runtime allocations (NRT statistics, a subprocess): the count for a render must not
   grow with the image size (target: zero per pixel);
6. the C++ report's workload (cpp-spheres.yml, 500x500, 8 samples, depth 5) in MRay/s
   (width x height x samples per second), target 20 with 2 threads;
7. the options: time against pixels that differ from float64 by more than 1/255.

Timings on a shared machine are rough: the CPU share column says how much of a core each
run really had. Pin the process with ``taskset -c 0,1`` for steadier figures.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "harness" / "scenes" / "reference.yml"
CPP = ROOT / "harness" / "scenes" / "cpp-spheres.yml"
ONE_STEP = 1.0 / 255.0


def _load(
    variant_name: str, path: Path, size: tuple[int, int] | None = None
) -> tuple[Any, Any, Any]:
    from harness.scenefile import load_scene
    from variants.registry import load_variant

    variant = load_variant(variant_name)
    scene = load_scene(path, variant.api, variant=variant.name)
    if size is not None:
        scene = scene.resized(*size)
    return variant, scene.camera, scene.world


def _timed(action: Callable[[], Any]) -> tuple[float, float, Any]:
    """(wall seconds, CPU share, result) of one call."""
    cpu = time.process_time()
    wall = time.perf_counter()
    result = action()
    wall = time.perf_counter() - wall
    cpu = time.process_time() - cpu
    return wall, cpu / wall if wall > 0 else 0.0, result


def _render_once(variant: Any, c: Any, w: Any, settings: Any) -> Any:
    return variant.api["render"](c, w, settings)


def _median_runs(action: Callable[[], Any], runs: int) -> tuple[float, list[tuple[float, float]]]:
    samples = [_timed(action)[:2] for _ in range(runs)]
    return statistics.median(w for w, _ in samples), samples


def _shares(samples: list[tuple[float, float]]) -> str:
    return ", ".join(f"{w:.3f}s@{s:.2f}" for w, s in samples)


def _verdict(ok: bool) -> str:
    return "met" if ok else "NOT met"


def _settings(**changes: Any) -> Any:
    from raytracer.camera import RenderSettings

    return RenderSettings(**{"epsilon": 0.001, **changes})


# ---------------------------------------------------------------------------- the sections


def cold_start() -> None:
    """Compile the reference scene's kernels (serial and parallel) from nothing."""
    with tempfile.TemporaryDirectory(prefix="rtc-numba-cold-") as folder:
        code = (
            "import time, sys\n"
            "from variants.numba.bench import _load, _settings\n"
            f"v, c, w = _load('numba', {str(REFERENCE)!r}, (8, 6))\n"
            "t = time.perf_counter(); c0 = time.process_time()\n"
            "v.api['render'](c, w, _settings())\n"
            "v2, c2, w2 = _load('numba[threads=1]', " + repr(str(REFERENCE)) + ", (8, 6))\n"
            "v2.api['render'](c2, w2, _settings())\n"
            "print(time.perf_counter() - t, time.process_time() - c0)\n"
        )
        env = {**os.environ, "RTC_NUMBA_KERNELS": folder}
        out = subprocess.run(
            [sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True
        )
        if out.returncode != 0:
            print(f"cold start: failed\n{out.stderr}")
            return
        wall, cpu = (float(v) for v in out.stdout.split()[-2:])
        print(
            f"cold start (compile the reference scene's serial and parallel kernels): "
            f"{wall:.1f} s wall, {cpu:.1f} s CPU -> target < 40 s {_verdict(wall < 40)}"
        )


def reference_render(runs: int) -> dict[int, float]:
    """The reference scene at 640x480 on 1 and 2 threads, compile excluded."""
    medians: dict[int, float] = {}
    for threads, target in ((1, 0.15), (2, 0.08)):
        variant, c, w = _load(f"numba[threads={threads}]", REFERENCE)
        warm = _load(f"numba[threads={threads}]", REFERENCE, (8, 6))
        variant.api["render"](warm[1], warm[2], _settings())
        median, samples = _median_runs(
            functools.partial(_render_once, variant, c, w, _settings()), runs
        )
        medians[threads] = median
        print(
            f"reference 640x480, {threads} thread{'s' if threads > 1 else ''}: median "
            f"{median:.3f} s (target {target} s: {_verdict(median <= target)}); runs "
            f"{_shares(samples)}"
        )
    return medians


def balance(runs: int) -> None:
    """How evenly interleaved rows split the reference scene between 2 threads: each
    thread's rows rendered alone, on this thread (CPU seconds, so the machine's load does
    not matter). 2 threads cannot beat the slower half."""
    from raytracer.sampling import GAMMA, MASK64
    from variants.numba import layout as L
    from variants.numba.features import analyse
    from variants.numba.pack import pack_camera
    from variants.numba.render import Options, packed_for_render
    from variants.numba.specialize import load_kernels

    _, c, w = _load("numba[threads=1]", REFERENCE)
    options = Options(threads=1)
    packed = packed_for_render(w, options)
    kernels = load_kernels(options.config(analyse(packed)))
    camera = pack_camera(c)
    settings = _settings()
    out = np.zeros((camera.vsize, camera.hsize, 3))
    size = max(packed.cs_size, packed.cs_prims, 2)
    stack = np.zeros((settings.depth + 2, L.STACK_WIDTH))
    sf, si = np.zeros((L.NSF, size)), np.zeros((L.NSI, size), dtype=np.int64)
    si[L.MEMO, 0] = -1
    seed_key = np.uint64((settings.seed * GAMMA) & MASK64)

    def rows(k: int, step: int) -> float:
        best = math.inf
        for _ in range(runs):
            cpu = time.process_time()
            kernels.render_rows(
                out, k, step, camera.array, *packed.arrays(), packed.light, settings.depth,
                settings.samples, seed_key, settings.epsilon, stack, sf, si,
            )  # fmt: skip
            best = min(best, time.process_time() - cpu)
        return best

    rows(0, 8)  # compile or load
    whole = rows(0, 1)
    rows(1, 8)
    halves = [rows(0, 2), rows(1, 2)]
    print(
        f"2-thread balance (reference 640x480, CPU seconds, best of {runs}): all rows "
        f"{whole:.3f} s, rows 0,2,4..: {halves[0]:.3f} s, rows 1,3,5..: {halves[1]:.3f} s "
        f"-> at most {whole / max(halves):.2f}x on 2 free cores "
        f"(a 2-thread render can take {max(halves):.3f} s)"
    )


def whole_command(runs: int) -> None:
    """``rtc render`` start to PNG written, kernels already cached."""
    rtc = Path(sys.executable).with_name("rtc")
    with tempfile.TemporaryDirectory(prefix="rtc-numba-cmd-") as folder:
        out_png = Path(folder) / "out.png"
        command = [
            str(rtc), "render", str(REFERENCE), "--variant", "numba[threads=2]",
            "--epsilon", "0.001", "-o", str(out_png),
        ]  # fmt: skip
        subprocess.run(command, cwd=ROOT, capture_output=True, check=True)  # cache the kernels
        samples = []
        for _ in range(runs):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run(command, cwd=ROOT, capture_output=True, check=True)
            wall = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            samples.append((wall, cpu / wall))
        median = statistics.median(w for w, _ in samples)
        print(
            f"whole command (rtc render ... -o out.png, 2 threads, cached kernels): median "
            f"{median:.3f} s (target 0.7 s: {_verdict(median <= 0.7)}); runs {_shares(samples)}"
        )


def against_naive(runs: int, medians: dict[int, float], size: tuple[int, int]) -> None:
    """naive and numba at ``size`` in this run, compared per pixel."""
    naive, c, w = _load("naive", REFERENCE, size)
    naive_wall, share, _ = _timed(lambda: naive.api["render"](c, w, _settings()))
    pixels = size[0] * size[1]
    per_pixel_naive = naive_wall / pixels
    print(f"naive {size[0]}x{size[1]}: {naive_wall:.1f} s (CPU share {share:.2f})")
    numba, c2, w2 = _load("numba[threads=2]", REFERENCE, size)
    numba.api["render"](c2, w2, _settings())
    small, _ = _median_runs(lambda: numba.api["render"](c2, w2, _settings()), runs)
    print(
        f"numba {size[0]}x{size[1]}, 2 threads: median {small:.4f} s -> "
        f"{per_pixel_naive / (small / pixels):,.0f}x naive per pixel"
    )
    for threads, median in sorted(medians.items()):
        speedup = per_pixel_naive / (median / (640 * 480))
        print(
            f"numba 640x480, {threads} thread{'s' if threads > 1 else ''}, per pixel: "
            f"{speedup:,.0f}x naive (target 10,000x: {_verdict(speedup >= 10_000)})"
        )


def allocations() -> None:
    """NRT allocation counts for renders of growing size (a subprocess: the statistics must
    be switched on before numba is imported)."""
    code = (
        "import json\n"
        "from numba.core.runtime import rtsys\n"
        "from variants.numba.bench import _load, _settings\n"
        "result = {}\n"
        "for threads in (1, 2):\n"
        "    for w, h in ((8, 6), (64, 48), (640, 480)):\n"
        f"        v, c, world = _load(f'numba[threads={{threads}}]', {str(REFERENCE)!r}, (w, h))\n"
        "        v.api['render'](c, world, _settings())\n"
        "        before = rtsys.get_allocation_stats()\n"
        "        v.api['render'](c, world, _settings())\n"
        "        after = rtsys.get_allocation_stats()\n"
        "        result[f'{threads} {w}x{h}'] = after.alloc - before.alloc\n"
        "print(json.dumps(result))\n"
    )
    env = {**os.environ, "NUMBA_NRT_STATS": "1"}
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True
    )
    if out.returncode != 0:
        print(f"allocations: failed\n{out.stderr}")
        return
    counts = json.loads(out.stdout.strip().splitlines()[-1])
    for threads in (1, 2):
        row = {k.split()[1]: v for k, v in counts.items() if k.startswith(f"{threads} ")}
        constant = len(set(row.values())) == 1
        shown = ", ".join(f"{size}: {n}" for size, n in row.items())
        print(
            f"NRT allocations per render, {threads} thread{'s' if threads > 1 else ''}: {shown} "
            f"-> {'0 per pixel (constant)' if constant else 'GROWS with the image'} "
            f"(target: {_verdict(constant)})"
        )


def cpp_workload(runs: int) -> None:
    """The C++ report's 8 spheres, 500x500, 8 samples, depth 5, in MRay/s."""
    settings = _settings(samples=8, depth=5, epsilon=0.0001)
    for threads in (1, 2):
        variant, c, w = _load(f"numba[threads={threads}]", CPP)
        warm = _load(f"numba[threads={threads}]", CPP, (8, 8))
        variant.api["render"](warm[1], warm[2], settings)
        median, samples = _median_runs(
            functools.partial(_render_once, variant, c, w, settings), runs
        )
        rays = c.hsize * c.vsize * settings.samples
        mrays = rays / median / 1e6
        target = f" (target 20: {_verdict(mrays >= 20)})" if threads == 2 else ""
        print(
            f"cpp-spheres 500x500x8, {threads} thread{'s' if threads > 1 else ''}: median "
            f"{median:.3f} s = {mrays:.1f} MRay/s{target}; runs {_shares(samples)}"
        )


def options(runs: int) -> None:
    """Each option's time (2 threads) and pixels that differ from float64 by > 1/255."""
    base: np.ndarray | None = None
    for name in (
        "numba[threads=2]",
        "numba[fastmath,threads=2]",
        "numba[float32,threads=2]",
        "numba[fastmath,float32,threads=2]",
        "numba[specialize=off,threads=2]",
    ):
        variant, c, w = _load(name, REFERENCE)
        warm = _load(name, REFERENCE, (8, 6))
        variant.api["render"](warm[1], warm[2], _settings())
        median, samples = _median_runs(
            functools.partial(_render_once, variant, c, w, _settings()), runs
        )
        image = variant.api["render"](c, w, _settings())
        pixels = np.clip(image.to_array(), 0.0, 1.0)
        if base is None:
            base = pixels
        difference = np.abs(pixels - base).max(axis=2)
        changed = int((difference > ONE_STEP).sum())
        print(
            f"{name:38s} median {median:.3f} s; vs float64: max {difference.max():.2g}, "
            f"{changed} pixels beyond 1/255; runs {_shares(samples)}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m variants.numba.bench", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("--runs", type=int, default=5, help="runs per figure (median; default 5)")
    parser.add_argument(
        "--naive-size", default="160x120", help="naive's render size (default 160x120)"
    )
    parser.add_argument(
        "--skip", action="append", default=[],
        choices=["cold", "render", "balance", "command", "naive", "allocations", "cpp", "options"],
        help="leave a section out (repeatable)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    width, height = (int(v) for v in args.naive_size.lower().split("x"))
    import numba

    print(
        f"machine: {os.cpu_count()} CPUs, affinity {sorted(os.sched_getaffinity(0))}, load "
        f"{os.getloadavg()[0]:.2f}; numba {numba.__version__}, threading layer "
        f"{os.environ.get('NUMBA_THREADING_LAYER', 'workqueue (the variant default)')}"
    )
    skip = set(args.skip)
    if "cold" not in skip:
        cold_start()
    medians: dict[int, float] = {}
    if "render" not in skip:
        medians = reference_render(args.runs)
    if "balance" not in skip:
        balance(args.runs)
    if "command" not in skip:
        whole_command(args.runs)
    if "naive" not in skip:
        against_naive(args.runs, medians, (width, height))
    if "allocations" not in skip:
        allocations()
    if "cpp" not in skip:
        cpp_workload(args.runs)
    if "options" not in skip:
        options(args.runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
