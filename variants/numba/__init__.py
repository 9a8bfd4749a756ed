"""``numba``: the book's tracer compiled with numba: packed arrays, parallel kernels with no
allocation per pixel, one kernel per scene feature set (chapters 1-16).

Options (all off by default; the name spells the ones given, sorted):

- ``float32``: compute and store in float32 instead of float64;
- ``fastmath``: LLVM fast-math (reassociation, fused multiply-add, ...);
- ``threads=N``: render on N threads (default: every thread numba may use);
- ``specialize=off``: always the generic kernel, every feature compiled in.

The package: ``layout`` (array columns), ``pack`` (world -> arrays), ``features`` (what a
scene needs), ``specialize`` (one generated, disk-cached kernel module per feature set),
``kernels_*`` (the kernel template), ``render``, ``api`` (the book API through the
kernels), ``canvas`` (an array-backed ``Canvas``), ``bench`` (the figures).
"""

from __future__ import annotations

import functools
import importlib.util

from variants.registry import (
    Unavailable,
    Variant,
    canonical_name,
    check_options,
    parse_bool,
    parse_int,
    reject_inner,
)

NAME = "numba"
OPTIONS = ("fastmath", "float32", "specialize", "threads")
USAGE = "float32, fastmath, threads=N (default: every thread numba may use), specialize=off"
ONE_STEP = 1.0 / 255.0
# what ``rtc bench --variants all`` measures besides the default (see variants.registry)
BENCH_CONFIGS = ("numba[threads=1]", "numba[float32]", "numba[fastmath]", "numba[specialize=off]")


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: ``numba``, ``numba[float32,fastmath,threads=1]``,
    ``numba[specialize=off]``."""
    reject_inner(NAME, inner)
    check_options(NAME, options, OPTIONS)
    if importlib.util.find_spec("numba") is None:
        raise Unavailable("numba is not installed (pip install numba)")
    from variants.numba.api import COMPILED, NumbaBook
    from variants.numba.render import Options, count_rays, max_threads

    float32 = parse_bool(NAME, "float32", options.get("float32", "off"))
    fastmath = parse_bool(NAME, "fastmath", options.get("fastmath", "off"))
    specialize = parse_bool(NAME, "specialize", options.get("specialize", "on"))
    threads = (
        parse_int(NAME, "threads", options["threads"], 1, max_threads())
        if "threads" in options
        else None
    )
    chosen = Options(float32=float32, fastmath=fastmath, threads=threads, specialize=specialize)
    book = NumbaBook(chosen)
    name = canonical_name(
        NAME,
        {
            "float32": float32 or None,
            "fastmath": fastmath or None,
            "threads": threads,
            "specialize": None if specialize else False,
        },
    )
    exact = not (float32 or fastmath)
    return Variant(
        name=name,
        summary="compiled with numba: packed arrays, parallel rows, a kernel per feature set",
        api=book.mapping(),
        overrides=COMPILED,
        base="naive",
        usage=USAGE,
        # float64 follows the reference's arithmetic; group transforms are composed and
        # reflections summed in another order, so a few last bits differ
        tolerance=ONE_STEP if exact else 0.25,
        bench_configs=BENCH_CONFIGS,
        count_rays=functools.partial(count_rays, chosen),
        explain=book.explain,
    )
