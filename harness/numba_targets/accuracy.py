"""The numba variant against naive (speed-up per pixel, the picture's difference), its runtime
allocations, and its options' time against pixels that differ."""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
from typing import Any

import numpy as np

from harness.numba_targets.common import (
    REFERENCE,
    ROOT,
    difference,
    load,
    median_runs,
    render_settings,
    timed,
    verdict,
)
from raytracer.tolerance import using_epsilon
from raytracer.tracer import pixel_color


def against_naive(
    runs: int, medians: dict[tuple[int, float], float], size: tuple[int, int], samples: int
) -> None:
    """naive and numba at ``size`` in this run: time per pixel and the picture's
    difference; then naive's colors of ``samples`` random pixels of the 640x480 picture."""

    settings = render_settings()
    naive, c, w = load("naive", REFERENCE, size)
    naive_wall, share, expected = timed(lambda: naive.api["render"](c, w, settings))
    pixels = size[0] * size[1]
    per_pixel_naive = naive_wall / pixels
    print(f"naive {size[0]}x{size[1]}: {naive_wall:.1f} s (CPU share {share:.2f})")
    numba, c2, w2 = load("numba[threads=2]", REFERENCE, size)
    got = numba.api["render"](c2, w2, settings)
    small, _ = median_runs(lambda: numba.api["render"](c2, w2, settings), runs)
    print(
        f"numba {size[0]}x{size[1]}, 2 threads: median {small:.4f} s -> "
        f"{per_pixel_naive / (small / pixels):,.0f}x naive per pixel; picture vs naive: "
        f"{difference(got.to_array(), _array(naive, expected))}"
    )
    for (threads, epsilon), median in sorted(medians.items()):
        if epsilon != settings.epsilon:
            continue
        speedup = per_pixel_naive / (median / (640 * 480))
        print(
            f"numba 640x480, {threads} thread{'s' if threads > 1 else ''}, per pixel: "
            f"{speedup:,.0f}x naive (target 10,000x: {verdict(speedup >= 10_000)})"
        )
    if samples <= 0:
        return
    numba, c3, w3 = load("numba[threads=2]", REFERENCE)
    picture = numba.api["render"](c3, w3, settings).to_array()
    naive, c4, w4 = load("naive", REFERENCE)
    chosen = random.Random(5).sample(range(640 * 480), samples)
    colors = []
    with using_epsilon(settings.epsilon):
        for index in chosen:
            color = pixel_color(c4, w4, index % 640, index // 640, settings)
            colors.append((color.red, color.green, color.blue))
    numba_colors = np.array([picture[index // 640, index % 640] for index in chosen])
    print(
        f"640x480, {samples} random pixels, naive's colors vs numba's picture: "
        f"{difference(numba_colors, np.array(colors))}"
    )


def _array(variant: Any, image: Any) -> np.ndarray:
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
        "from harness.numba_targets import load, render_settings\n"
        "allocating = njit(lambda n: np.zeros(n).sum())\n"
        "allocating(3)\n"
        "before = rtsys.get_allocation_stats().alloc\n"
        "allocating(3)\n"
        "result = {'control': rtsys.get_allocation_stats().alloc - before}\n"
        "for threads in (1, 2):\n"
        "    for w, h in ((8, 6), (64, 48), (640, 480)):\n"
        f"        v, c, world = load(f'numba[threads={{threads}}]', {str(REFERENCE)!r}, (w, h))\n"
        "        v.api['render'](c, world, render_settings())\n"
        "        before = rtsys.get_allocation_stats().alloc\n"
        "        v.api['render'](c, world, render_settings())\n"
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
            f"(target: {verdict(constant)}; a function that allocates counted "
            f"{counts['control']})"
        )
