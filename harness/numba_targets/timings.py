"""The numba variant's times: its cold start, the reference render on 1 and 2 threads, how
evenly the rows split, and the whole ``rtc render`` command."""

from __future__ import annotations

import functools
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from harness.numba_targets.common import (
    EPSILONS,
    REFERENCE,
    ROOT,
    load,
    median_runs,
    render_once,
    render_settings,
    shares,
    verdict,
)

if TYPE_CHECKING:
    pass




def cold_start() -> None:
    """Build the reference scene's render library from nothing (a fresh kernel folder)."""
    with tempfile.TemporaryDirectory(prefix="rtc-numba-cold-") as folder:
        code = (
            "import time\n"
            "from harness.numba_targets import load, render_settings\n"
            f"v, c, w = load('numba', {str(REFERENCE)!r}, (8, 6))\n"
            "t = time.perf_counter(); c0 = time.process_time()\n"
            "v.api['render'](c, w, render_settings())\n"
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
            f"-> target < 40 s {verdict(wall < 40)}"
        )


def reference_render(runs: int) -> dict[tuple[int, float], float]:
    """The reference scene at 640x480 on 1 and 2 threads, compile excluded."""
    medians: dict[tuple[int, float], float] = {}
    for epsilon in EPSILONS:
        for threads, target in ((1, 0.15), (2, 0.08)):
            variant, c, w = load(f"numba[threads={threads}]", REFERENCE)
            warm = load(f"numba[threads={threads}]", REFERENCE, (8, 6))
            variant.api["render"](warm[1], warm[2], render_settings(epsilon=epsilon))
            once = functools.partial(render_once, variant, c, w, render_settings(epsilon=epsilon))
            median, samples = median_runs(once, runs)
            medians[threads, epsilon] = median
            print(
                f"reference 640x480, epsilon {epsilon:g}, {threads} thread"
                f"{'s' if threads > 1 else ''}: median {median:.3f} s (target {target} s: "
                f"{verdict(median <= target)}); runs {shares(samples)}"
            )
    return medians


def balance(runs: int) -> None:
    """How evenly interleaved rows split the reference scene between 2 threads: each
    thread's rows rendered alone, on this thread (CPU seconds, so the machine's load does
    not matter much). 2 threads cannot beat the slower half."""
    # deferred: saves ~200 ms (numba's render) of rtc bench --help
    from variants.numba.render import Options, prepare_frame

    _, c, w = load("numba[threads=1]", REFERENCE)
    settings = render_settings()
    out = np.zeros((c.vsize, c.hsize, 3))

    def rows(k: int, step: int) -> float:
        best = math.inf
        for _ in range(runs):
            # a fresh frame per render: its scratch's shadow memo empty, as a render's is
            frame = prepare_frame(Options(threads=1), c, w, settings)
            cpu = time.process_time()
            frame.renderer.function(
                out.ctypes.data, 0, 0, c.hsize, c.vsize, k, step, *frame.common,
                *frame.addresses[0],
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
        # deferred: saves ~200 ms (numba's render) of rtc bench --help
        from variants.numba.render import max_threads

        print(
            f"whole command (rtc render reference.yml --variant numba -o out.png: "
            f"{max_threads()} threads, epsilon 0.0001, cached kernels): median {median:.3f} s "
            f"(target 0.7 s: {verdict(median <= 0.7)}); runs {shares(samples)}"
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
