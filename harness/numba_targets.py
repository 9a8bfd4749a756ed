"""The numba variant's figures, against the targets of its issue (``rtc bench
--numba-targets``, or ``python -m harness.numba_targets``).

Prints, each as the median of ``--runs`` runs with the CPU share each run got (CPU seconds
of the process over wall seconds: up to 1.0 per thread that really ran):

1. cold start: building the reference scene's render library in a fresh kernel folder
   (numba compiles, the C compiler links; a subprocess), target under 40 s;
2. the reference scene, 640x480, 1 sample, depth 5, compile excluded, at the project's
   epsilon 0.0001 and at the Go renderer's 0.001: 1 thread (target 0.15 s) and 2 threads
   (target 0.08 s); and how evenly the interleaved rows split the work (each thread's rows
   timed alone, in CPU seconds);
3. the whole ``rtc render reference.yml --variant numba -o out.png`` command with cached
   kernels (target 0.7 s), and where its time goes in a fresh process;
4. ``naive`` at 160x120 in the same run: the speed-up per pixel (target 10,000x) and the
   picture's difference (max, mean, pixels beyond 1/255); and at 640x480, ``naive``'s
   colors of a random sample of pixels against numba's picture;
5. numba runtime allocations (NRT statistics, a subprocess): the count for a render must not
   grow with the image size (target: zero per pixel);
6. the C++ report's workload (cpp-spheres.yml, 500x500, 8 samples, depth 5) in MRay/s
   (width x height x samples per second), target 20 with 2 threads;
7. the options: time against pixels that differ from float64 by more than 1/255;
8. what specialization buys: the specialized and the generic kernel, alternating, on the
   reference scene and on cpp-spheres;
9. regions: the reference scene rendered whole and as one ``render_region`` call per row
   (what a pooled worker makes), 1 thread, after the frame is prepared;
10. pooled: ``pooled[workers=1]:numba`` against ``numba[threads=1]`` and
   ``pooled[workers=2]:numba[threads=1]`` against ``numba``, renders alternating, per pixel
   with the start-up apart (target: one worker within 2x per pixel).

Timings on a shared machine are rough: the CPU share column says how much of a core each
run really had. Pin the process with ``taskset -c 0,1`` for steadier figures.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import random
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # numpy is imported where it is used: ``rtc bench``'s parser needs none
    import numpy as np

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "harness" / "scenes" / "reference.yml"
CPP = ROOT / "harness" / "scenes" / "cpp-spheres.yml"
ONE_STEP = 1.0 / 255.0
EPSILONS = (0.0001, 0.001)  # the project's (the book's) and the Go renderer's


def _load(
    variant_name: str, path: Path, size: tuple[int, int] | None = None
) -> tuple[Any, Any, Any]:
    from harness.make_meshes import provide
    from scene import load_scene
    from variants.registry import load_variant

    variant = load_variant(variant_name)
    scene = load_scene(path, variant.api, variant=variant.name, provide_mesh=provide)
    if size is not None:
        scene = scene.resized(*size)
    return variant, scene.camera, variant.world_for(scene)


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

    return RenderSettings(**changes)


def _difference(got: np.ndarray, expected: np.ndarray) -> str:
    """Max and mean difference per channel, and pixels beyond 1/255, of clamped colors."""
    import numpy as np

    a = np.clip(got, 0.0, 1.0)
    b = np.clip(expected, 0.0, 1.0)
    difference = np.abs(a - b)
    beyond = int((difference.max(axis=-1) > ONE_STEP).sum())
    pixels = difference.size // 3
    return (
        f"max {difference.max():.2g}, mean {difference.mean():.2g}, {beyond} of {pixels} "
        "pixels beyond 1/255"
    )


# ---------------------------------------------------------------------------- the sections


def cold_start() -> None:
    """Build the reference scene's render library from nothing (a fresh kernel folder)."""
    with tempfile.TemporaryDirectory(prefix="rtc-numba-cold-") as folder:
        code = (
            "import time\n"
            "from harness.numba_targets import _load, _settings\n"
            f"v, c, w = _load('numba', {str(REFERENCE)!r}, (8, 6))\n"
            "t = time.perf_counter(); c0 = time.process_time()\n"
            "v.api['render'](c, w, _settings())\n"
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
        built = sorted(p.name for p in Path(folder).glob("*.so"))
        print(
            f"cold start (compile and link the reference scene's render: {', '.join(built)}): "
            f"{wall:.1f} s wall, {cpu:.1f} s CPU of this process (the C compiler's not counted) "
            f"-> target < 40 s {_verdict(wall < 40)}"
        )


def reference_render(runs: int) -> dict[tuple[int, float], float]:
    """The reference scene at 640x480 on 1 and 2 threads, compile excluded."""
    medians: dict[tuple[int, float], float] = {}
    for epsilon in EPSILONS:
        for threads, target in ((1, 0.15), (2, 0.08)):
            variant, c, w = _load(f"numba[threads={threads}]", REFERENCE)
            warm = _load(f"numba[threads={threads}]", REFERENCE, (8, 6))
            variant.api["render"](warm[1], warm[2], _settings(epsilon=epsilon))
            median, samples = _median_runs(
                functools.partial(_render_once, variant, c, w, _settings(epsilon=epsilon)), runs
            )
            medians[threads, epsilon] = median
            print(
                f"reference 640x480, epsilon {epsilon:g}, {threads} thread"
                f"{'s' if threads > 1 else ''}: median {median:.3f} s (target {target} s: "
                f"{_verdict(median <= target)}); runs {_shares(samples)}"
            )
    return medians


def balance(runs: int) -> None:
    """How evenly interleaved rows split the reference scene between 2 threads: each
    thread's rows rendered alone, on this thread (CPU seconds, so the machine's load does
    not matter much). 2 threads cannot beat the slower half."""
    import numpy as np

    from variants.numba.render import Options, Scratch, prepare_frame

    _, c, w = _load("numba[threads=1]", REFERENCE)
    settings = _settings()
    frame = prepare_frame(Options(threads=1), c, w, settings)
    out = np.zeros((c.vsize, c.hsize, 3))

    def rows(k: int, step: int) -> float:
        best = math.inf
        for _ in range(runs):
            scratch = Scratch(1, settings.depth, frame.packed, np.float64)
            cpu = time.process_time()
            frame.renderer.function(
                out.ctypes.data, 0, 0, c.hsize, c.vsize, k, step, *frame.common,
                *scratch.addresses(0),
            )  # fmt: skip
            best = min(best, time.process_time() - cpu)
        return best

    whole = rows(0, 1)
    halves = [rows(0, 2), rows(1, 2)]
    print(
        f"2-thread balance (reference 640x480, CPU seconds, best of {runs}): all rows "
        f"{whole:.3f} s, rows 0,2,4..: {halves[0]:.3f} s, rows 1,3,5..: {halves[1]:.3f} s "
        f"-> at most {whole / max(halves):.2f}x on 2 free cores "
        f"(a 2-thread render can take {max(halves):.3f} s)"
    )


STARTUP = """
import time
t0 = time.perf_counter()
from groundwork.images import write_image
from scene import load_scene
from raytracer.camera import RenderSettings
from variants.registry import load_variant
t1 = time.perf_counter()
variant = load_variant("numba")
t2 = time.perf_counter()
scene = load_scene({scene!r}, variant.api, variant=variant.name)
world = variant.world_for(scene)
t3 = time.perf_counter()
image = variant.api["render"](scene.camera, world, RenderSettings())
t4 = time.perf_counter()
write_image(image, {png!r})
t5 = time.perf_counter()
image = variant.api["render"](scene.camera, world, RenderSettings())
t6 = time.perf_counter()
import sys
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t6 - t5, "numba" in sys.modules)
"""


def whole_command(runs: int) -> None:
    """``rtc render`` start to PNG written, kernels already cached; then where the time of
    a fresh process goes."""
    rtc = Path(sys.executable).with_name("rtc")
    with tempfile.TemporaryDirectory(prefix="rtc-numba-cmd-") as folder:
        out_png = Path(folder) / "out.png"
        command = [str(rtc), "render", str(REFERENCE), "--variant", "numba", "-o", str(out_png)]
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
        from variants.numba.render import max_threads

        print(
            f"whole command (rtc render reference.yml --variant numba -o out.png: "
            f"{max_threads()} threads, epsilon 0.0001, cached kernels): median {median:.3f} s "
            f"(target 0.7 s: {_verdict(median <= 0.7)}); runs {_shares(samples)}"
        )
        code = STARTUP.format(scene=str(REFERENCE), png=str(out_png))
        done = subprocess.run(
            [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
        )
        *parts, numba_imported = done.stdout.split()
        imports, variant, scene, first, png, second = (float(v) for v in parts)
        print(
            f"  in a fresh process: imports {imports:.3f} s, load_variant {variant:.3f} s, "
            f"scene {scene:.3f} s, first render {first:.3f} s (a second: {second:.3f} s), "
            f"PNG {png:.3f} s; numba imported: {numba_imported}"
        )


def against_naive(
    runs: int, medians: dict[tuple[int, float], float], size: tuple[int, int], samples: int
) -> None:
    """naive and numba at ``size`` in this run: time per pixel and the picture's
    difference; then naive's colors of ``samples`` random pixels of the 640x480 picture."""
    import numpy as np

    from raytracer.tolerance import using_epsilon
    from raytracer.tracer import pixel_color

    settings = _settings()
    naive, c, w = _load("naive", REFERENCE, size)
    naive_wall, share, expected = _timed(lambda: naive.api["render"](c, w, settings))
    pixels = size[0] * size[1]
    per_pixel_naive = naive_wall / pixels
    print(f"naive {size[0]}x{size[1]}: {naive_wall:.1f} s (CPU share {share:.2f})")
    numba, c2, w2 = _load("numba[threads=2]", REFERENCE, size)
    got = numba.api["render"](c2, w2, settings)
    small, _ = _median_runs(lambda: numba.api["render"](c2, w2, settings), runs)
    print(
        f"numba {size[0]}x{size[1]}, 2 threads: median {small:.4f} s -> "
        f"{per_pixel_naive / (small / pixels):,.0f}x naive per pixel; picture vs naive: "
        f"{_difference(got.to_array(), _array(naive, expected))}"
    )
    for (threads, epsilon), median in sorted(medians.items()):
        if epsilon != settings.epsilon:
            continue
        speedup = per_pixel_naive / (median / (640 * 480))
        print(
            f"numba 640x480, {threads} thread{'s' if threads > 1 else ''}, per pixel: "
            f"{speedup:,.0f}x naive (target 10,000x: {_verdict(speedup >= 10_000)})"
        )
    if samples <= 0:
        return
    numba, c3, w3 = _load("numba[threads=2]", REFERENCE)
    picture = numba.api["render"](c3, w3, settings).to_array()
    naive, c4, w4 = _load("naive", REFERENCE)
    chosen = random.Random(5).sample(range(640 * 480), samples)
    colors = []
    with using_epsilon(settings.epsilon):
        for index in chosen:
            color = pixel_color(c4, w4, index % 640, index // 640, settings)
            colors.append((color.red, color.green, color.blue))
    numba_colors = np.array([picture[index // 640, index % 640] for index in chosen])
    print(
        f"640x480, {samples} random pixels, naive's colors vs numba's picture: "
        f"{_difference(numba_colors, np.array(colors))}"
    )


def _array(variant: Any, image: Any) -> np.ndarray:
    import numpy as np

    pixel_at = variant.api["pixel_at"]
    rows = [
        [(p.red, p.green, p.blue) for p in (pixel_at(image, x, y) for x in range(image.width))]
        for y in range(image.height)
    ]
    return np.array(rows, dtype=np.float64)


def allocations() -> None:
    """NRT allocation counts for renders of growing size (a subprocess: the statistics must
    be switched on before numba is imported; a function that allocates shows they count)."""
    code = (
        "import json\n"
        "import numpy as np\n"
        "from numba import njit\n"
        "from numba.core.runtime import rtsys\n"
        "from harness.numba_targets import _load, _settings\n"
        "allocating = njit(lambda n: np.zeros(n).sum())\n"
        "allocating(3)\n"
        "before = rtsys.get_allocation_stats().alloc\n"
        "allocating(3)\n"
        "result = {'control': rtsys.get_allocation_stats().alloc - before}\n"
        "for threads in (1, 2):\n"
        "    for w, h in ((8, 6), (64, 48), (640, 480)):\n"
        f"        v, c, world = _load(f'numba[threads={{threads}}]', {str(REFERENCE)!r}, (w, h))\n"
        "        v.api['render'](c, world, _settings())\n"
        "        before = rtsys.get_allocation_stats().alloc\n"
        "        v.api['render'](c, world, _settings())\n"
        "        after = rtsys.get_allocation_stats().alloc\n"
        "        result[f'{threads} {w}x{h}'] = after - before\n"
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
            f"(target: {_verdict(constant)}; a function that allocates counted "
            f"{counts['control']})"
        )


def cpp_workload(runs: int) -> None:
    """The C++ report's 8 spheres, 500x500, 8 samples, depth 5, in MRay/s."""
    settings = _settings(samples=8, depth=5)
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
        "numba[threads=1]",
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
        pixels = variant.api["render"](c, w, _settings()).to_array()
        if base is None:
            base = pixels
        print(
            f"{name:38s} median {median:.3f} s; vs float64: {_difference(pixels, base)}; "
            f"runs {_shares(samples)}"
        )


def specialization(runs: int) -> None:
    """The kernel specialized to the scene against the generic one, side by side: renders
    alternate between the two, and the median of each pair's ratio is printed."""
    for label, path, settings in (
        ("reference 640x480", REFERENCE, _settings()),
        ("cpp-spheres 500x500x8", CPP, _settings(samples=8, depth=5)),
    ):
        loaded = [_load(name, path) for name in ("numba", "numba[specialize=off]")]
        for variant, c, w in loaded:
            variant.api["render"](c, w, settings)  # warm: compile or load both
        times: list[list[float]] = [[], []]
        for _ in range(runs):
            for which, (variant, c, w) in enumerate(loaded):
                action = functools.partial(_render_once, variant, c, w, settings)
                times[which].append(_timed(action)[0])
        ratio = statistics.median(g / s for s, g in zip(times[0], times[1], strict=True))
        print(
            f"{label}, 2 threads, {runs} alternating pairs: specialized median "
            f"{statistics.median(times[0]):.3f} s, generic (specialize=off) "
            f"{statistics.median(times[1]):.3f} s; generic/specialized per pair: {ratio:.2f}x"
        )


def regions(runs: int) -> None:
    """The reference scene at 640x480, 1 thread: one ``render`` against one
    ``render_region`` call per row of the same frame (a pooled worker's jobs), the frame
    prepared by a first call; the pictures must be equal."""
    import numpy as np

    variant, c, w = _load("numba[threads=1]", REFERENCE)
    tracer = variant.tracer
    settings = _settings()
    whole = tracer.render(c, w, settings)  # warm: load the render entry

    def by_rows() -> Any:
        tracer.forget()
        values: list[float] = []
        for y in range(c.vsize):
            values.extend(tracer.render_region(c, w, settings, (0, y, c.hsize, y + 1)))
        return np.array(values).reshape(c.vsize, c.hsize, 3)

    tracer.render_region(c, w, settings, (0, 0, 1, 1))  # prepare the frame
    row_median, row_samples = _median_runs(
        lambda: [
            tracer.render_region(c, w, settings, (0, y, c.hsize, y + 1)) for y in range(c.vsize)
        ],
        runs,
    )
    render_median, render_samples = _median_runs(
        functools.partial(_render_once, variant, c, w, settings), runs
    )
    same = np.array_equal(by_rows(), whole.to_array())
    tracer.forget()
    print(
        f"regions (reference 640x480, 1 thread): render median {render_median:.3f} s; "
        f"480 render_region rows of a prepared frame: median {row_median:.3f} s "
        f"({row_median / render_median:.2f}x; runs {_shares(row_samples)}; render runs "
        f"{_shares(render_samples)}); same picture: {same}"
    )


POOL_PAIRS = (
    ("numba[threads=1]", "pooled[workers=1]:numba"),
    ("numba", "pooled[workers=2]:numba[threads=1]"),
)
START_UP_SIZE = (8, 6)  # a render this small costs what a render costs besides its pixels


def _timed_with_children(action: Callable[[], Any]) -> tuple[float, float]:
    """(wall seconds, CPU share) of one call, the CPU of its worker processes included
    (``harness.usage.TreeCpuClock``)."""
    from harness.usage import TreeCpuClock

    clock = TreeCpuClock()
    clock.start()
    start = time.perf_counter()
    action()
    wall = time.perf_counter() - start
    return wall, clock.stop() / wall if wall > 0 else 0.0


def pooled(runs: int) -> None:
    """``pooled`` over ``numba`` against ``numba`` itself, their renders alternating: the
    reference scene at 640x480, at 8x6 (its start-up apart: the pool's processes starting,
    each loading the variant and preparing the frame), and per pixel (the difference). A
    worker calls its numba tracer's ``render_region`` per line; the target is pooled with
    one worker within 2x of ``numba[threads=1]`` per pixel."""
    settings = _settings()
    big = (640, 480)
    for plain_name, pooled_name in POOL_PAIRS:
        loaded = {
            (name, size): _load(name, REFERENCE, size)
            for name in (plain_name, pooled_name)
            for size in (big, START_UP_SIZE)
        }
        samples: dict[tuple[str, tuple[int, int]], list[tuple[float, float]]] = {}
        for variant, c, w in loaded.values():  # warm: kernels loaded, caches built
            _render_once(variant, c, w, settings)
        for _ in range(runs):
            for key, (variant, c, w) in loaded.items():
                render = functools.partial(_render_once, variant, c, w, settings)
                samples.setdefault(key, []).append(_timed_with_children(render))
        median = {key: statistics.median(t for t, _ in found) for key, found in samples.items()}
        pixels = big[0] * big[1] - START_UP_SIZE[0] * START_UP_SIZE[1]
        per_pixel = {
            name: (median[(name, big)] - median[(name, START_UP_SIZE)]) / pixels
            for name in (plain_name, pooled_name)
        }
        ratio = per_pixel[pooled_name] / per_pixel[plain_name]
        goal = (
            f" (target 2x: {_verdict(ratio <= 2.0)})"
            if pooled_name.startswith("pooled[workers=1]")
            else ""
        )
        print(f"pooled against {plain_name} (reference scene, {runs} alternating renders each):")
        for name in (plain_name, pooled_name):
            print(
                f"  {name}: 640x480 median {median[(name, big)]:.3f} s "
                f"({_shares(samples[(name, big)])}); start-up (8x6) "
                f"{median[(name, START_UP_SIZE)]:.3f} s; per pixel "
                f"{per_pixel[name] * 1e6:.3f} µs"
            )
        print(f"  per pixel, pooled / plain: {ratio:.2f}x{goal}", flush=True)


SECTIONS = (
    "cold", "render", "balance", "command", "naive", "allocations", "cpp", "options",
    "specialize", "regions", "pooled",
)  # fmt: skip


def add_arguments(parser: Any) -> None:
    """The options (``parser``: an ``ArgumentParser`` or an argument group); None is the
    default (``settings``)."""
    parser.add_argument(
        "--runs", type=int, default=None, metavar="N", help="runs per figure (median; default 5)"
    )
    parser.add_argument(
        "--naive-size", default=None, metavar="WxH", help="naive's render size (default 160x120)"
    )
    parser.add_argument(
        "--naive-pixels", type=int, default=None, metavar="N",
        help="random pixels of the 640x480 picture naive computes too (default 200; 0: none)",
    )  # fmt: skip
    parser.add_argument(
        "--skip", action="append", default=[], choices=SECTIONS, metavar="SECTION",
        help=f"leave a section out (repeatable): {', '.join(SECTIONS)}",
    )  # fmt: skip


def settings(args: argparse.Namespace) -> tuple[int, tuple[int, int], int, set[str]]:
    """(runs, naive's size, naive's pixels, sections skipped) from ``add_arguments``'
    options; ``ValueError`` for a bad one."""
    runs = 5 if args.runs is None else args.runs
    if runs < 1:
        raise ValueError("--runs must be at least 1")
    from groundwork.sizes import parse_size

    try:
        size = parse_size(args.naive_size or "160x120")
    except ValueError as error:
        raise ValueError(f"--naive-size: {error}") from None
    pixels = 200 if args.naive_pixels is None else args.naive_pixels
    if pixels < 0:
        raise ValueError("--naive-pixels must be 0 or more")
    return runs, (size.width, size.height), pixels, set(args.skip)


def run(args: argparse.Namespace) -> int:
    """Print every section not skipped (``settings(args)`` must have been checked)."""
    runs, size, pixels, skip = settings(args)
    from importlib.metadata import version

    print(
        f"machine: {os.cpu_count()} CPUs, affinity {sorted(os.sched_getaffinity(0))}, load "
        f"{os.getloadavg()[0]:.2f}; numba {version('numba')}; render threads: Python threads "
        "calling the compiled render through ctypes",
        flush=True,
    )
    if "cold" not in skip:
        cold_start()
    medians: dict[tuple[int, float], float] = {}
    if "render" not in skip:
        medians = reference_render(runs)
    if "balance" not in skip:
        balance(runs)
    if "command" not in skip:
        whole_command(runs)
    if "naive" not in skip:
        against_naive(runs, medians, size, pixels)
    if "allocations" not in skip:
        allocations()
    if "cpp" not in skip:
        cpp_workload(runs)
    if "options" not in skip:
        options(runs)
    if "specialize" not in skip:
        specialization(runs)
    if "regions" not in skip:
        regions(runs)
    if "pooled" not in skip:
        pooled(runs)
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m harness.numba_targets", description=(__doc__ or "").split("\n\n")[0]
    )
    add_arguments(parser)
    args = parser.parse_args(argv)
    try:
        settings(args)
    except ValueError as error:
        parser.error(str(error))
    return run(args)


if __name__ == "__main__":
    sys.exit(main())
