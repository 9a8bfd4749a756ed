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
import os
from importlib.metadata import version
from typing import Any

from groundwork.sizes import parse_size
from harness.numba_targets.accuracy import against_naive, allocations
from harness.numba_targets.timings import balance, cold_start, reference_render, whole_command
from harness.numba_targets.workloads import cpp_workload, options, pooled, regions, specialization

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

