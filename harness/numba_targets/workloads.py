"""The numba variant on other workloads: the C++ report's (cpp-spheres), specialized against
generic kernels, rows rendered as regions, and inside ``pooled``."""

from __future__ import annotations

import functools
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from harness.instruments.usage import TreeCpuClock
from harness.numba_targets.common import (
    CPP,
    REFERENCE,
    difference,
    load,
    median_runs,
    render_once,
    render_settings,
    shares,
    timed,
    verdict,
)


def cpp_workload(runs: int) -> None:
    """The C++ report's 8 spheres, 500x500, 8 samples, depth 5, in MRay/s."""
    settings = render_settings(samples=8, depth=5)
    for threads in (1, 2):
        variant, c, w = load(f"numba[threads={threads}]", CPP)
        warm = load(f"numba[threads={threads}]", CPP, (8, 8))
        variant.api["render"](warm[1], warm[2], settings)
        median, samples = median_runs(
            functools.partial(render_once, variant, c, w, settings), runs
        )
        rays = c.hsize * c.vsize * settings.samples
        mrays = rays / median / 1e6
        target = f" (target 20: {verdict(mrays >= 20)})" if threads == 2 else ""
        print(
            f"cpp-spheres 500x500x8, {threads} thread{'s' if threads > 1 else ''}: median "
            f"{median:.3f} s = {mrays:.1f} MRay/s{target}; runs {shares(samples)}"
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
        variant, c, w = load(name, REFERENCE)
        warm = load(name, REFERENCE, (8, 6))
        variant.api["render"](warm[1], warm[2], render_settings())
        median, samples = median_runs(
            functools.partial(render_once, variant, c, w, render_settings()), runs
        )
        pixels = variant.api["render"](c, w, render_settings()).to_array()
        if base is None:
            base = pixels
        print(
            f"{name:38s} median {median:.3f} s; vs float64: {difference(pixels, base)}; "
            f"runs {shares(samples)}"
        )


def specialization(runs: int) -> None:
    """The kernel specialized to the scene against the generic one, side by side: renders
    alternate between the two, and the median of each pair's ratio is printed."""
    for label, path, settings in (
        ("reference 640x480", REFERENCE, render_settings()),
        ("cpp-spheres 500x500x8", CPP, render_settings(samples=8, depth=5)),
    ):
        loaded = [load(name, path) for name in ("numba", "numba[specialize=off]")]
        for variant, c, w in loaded:
            variant.api["render"](c, w, settings)  # warm: compile or load both
        times: list[list[float]] = [[], []]
        for _ in range(runs):
            for which, (variant, c, w) in enumerate(loaded):
                action = functools.partial(render_once, variant, c, w, settings)
                times[which].append(timed(action)[0])
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
    variant, c, w = load("numba[threads=1]", REFERENCE)
    tracer = variant.tracer
    settings = render_settings()
    whole = tracer.render(c, w, settings)  # warm: load the render entry

    def by_rows() -> Any:
        tracer.forget()
        values: list[float] = []
        for y in range(c.vsize):
            values.extend(tracer.render_region(c, w, settings, (0, y, c.hsize, y + 1)))
        return np.array(values).reshape(c.vsize, c.hsize, 3)

    tracer.render_region(c, w, settings, (0, 0, 1, 1))  # prepare the frame
    row_median, row_samples = median_runs(
        lambda: [
            tracer.render_region(c, w, settings, (0, y, c.hsize, y + 1)) for y in range(c.vsize)
        ],
        runs,
    )
    render_median, render_samples = median_runs(
        functools.partial(render_once, variant, c, w, settings), runs
    )
    same = np.array_equal(by_rows(), whole.to_array())
    tracer.forget()
    print(
        f"regions (reference 640x480, 1 thread): render median {render_median:.3f} s; "
        f"480 render_region rows of a prepared frame: median {row_median:.3f} s "
        f"({row_median / render_median:.2f}x; runs {shares(row_samples)}; render runs "
        f"{shares(render_samples)}); same picture: {same}"
    )


POOL_PAIRS = (
    ("numba[threads=1]", "pooled[workers=1]:numba"),
    ("numba", "pooled[workers=2]:numba[threads=1]"),
)
START_UP_SIZE = (8, 6)  # a render this small costs what a render costs besides its pixels


def _timed_with_children(action: Callable[[], Any]) -> tuple[float, float]:
    """(wall seconds, CPU share) of one call, the CPU of its worker processes included
    (``harness.instruments.usage.TreeCpuClock``)."""
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
    settings = render_settings()
    big = (640, 480)
    for plain_name, pooled_name in POOL_PAIRS:
        loaded = {
            (name, size): load(name, REFERENCE, size)
            for name in (plain_name, pooled_name)
            for size in (big, START_UP_SIZE)
        }
        samples: dict[tuple[str, tuple[int, int]], list[tuple[float, float]]] = {}
        for variant, c, w in loaded.values():  # warm: kernels loaded, caches built
            render_once(variant, c, w, settings)
        for _ in range(runs):
            for key, (variant, c, w) in loaded.items():
                render = functools.partial(render_once, variant, c, w, settings)
                samples.setdefault(key, []).append(_timed_with_children(render))
        median = {key: statistics.median(t for t, _ in found) for key, found in samples.items()}
        pixels = big[0] * big[1] - START_UP_SIZE[0] * START_UP_SIZE[1]
        per_pixel = {
            name: (median[(name, big)] - median[(name, START_UP_SIZE)]) / pixels
            for name in (plain_name, pooled_name)
        }
        ratio = per_pixel[pooled_name] / per_pixel[plain_name]
        goal = (
            f" (target 2x: {verdict(ratio <= 2.0)})"
            if pooled_name.startswith("pooled[workers=1]")
            else ""
        )
        print(f"pooled against {plain_name} (reference scene, {runs} alternating renders each):")
        for name in (plain_name, pooled_name):
            print(
                f"  {name}: 640x480 median {median[(name, big)]:.3f} s "
                f"({shares(samples[(name, big)])}); start-up (8x6) "
                f"{median[(name, START_UP_SIZE)]:.3f} s; per pixel "
                f"{per_pixel[name] * 1e6:.3f} µs"
            )
        print(f"  per pixel, pooled / plain: {ratio:.2f}x{goal}", flush=True)
