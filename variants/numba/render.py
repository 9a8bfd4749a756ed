"""Rendering through the kernels (chapter 7), the variant's options, and ``explain``.

A render packs the world once, finds its feature set, loads (or compiles, then caches) the
kernel module for that set, and runs it on T threads, thread k taking rows k, k + T, ...
Nothing is allocated per pixel: each thread allocates its scratch once (see
``kernels_trace.render_rows``).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import Camera, RenderSettings
from raytracer.sampling import GAMMA, MASK64
from raytracer.world import World
from variants.numba.canvas import ArrayCanvas
from variants.numba.features import FeatureSet, analyse
from variants.numba.pack import Packed, PackError, pack_camera, pack_world
from variants.numba.specialize import KernelConfig, load_kernels


def max_threads() -> int:
    """How many threads numba can use here (``NUMBA_NUM_THREADS``, else the usable CPUs)."""
    configured = os.environ.get("NUMBA_NUM_THREADS")
    if configured and configured.isdigit() and int(configured) > 0:
        return int(configured)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@dataclass(frozen=True)
class Options:
    """The variant's options (all off by default).

    float32: compute and store in float32; fastmath: LLVM fast-math; threads: render
    threads (None: every one numba may use); specialize: a kernel per feature set (False:
    the generic kernel with every feature, to show what specialization buys).
    """

    float32: bool = False
    fastmath: bool = False
    threads: int | None = None
    specialize: bool = True

    @property
    def dtype(self) -> Any:
        return np.float32 if self.float32 else np.float64

    def config(self, features: FeatureSet, count_rays: bool = False) -> KernelConfig:
        chosen = features if self.specialize else FeatureSet.everything()
        return KernelConfig(chosen, self.float32, self.fastmath, count_rays)

    def generic(self) -> KernelConfig:
        """The kernel module the book-API calls use: every feature, this precision."""
        return KernelConfig(FeatureSet.everything(), self.float32, self.fastmath)


def _numba() -> Any:
    """numba, imported on first use, with a fork-safe threading layer unless one is chosen:
    after a parallel kernel has run on GNU OpenMP, a forked process hangs (DESIGN.md)."""
    import numba

    if not os.environ.get("NUMBA_THREADING_LAYER"):
        config: Any = numba.config
        config.THREADING_LAYER = "workqueue"
    return numba


def render_threads(options: Options) -> int:
    numba = _numba()
    threads = options.threads or numba.config.NUMBA_NUM_THREADS
    if not 1 <= threads <= numba.config.NUMBA_NUM_THREADS:
        raise ValueError(
            f"numba: threads={threads} is more than the {numba.config.NUMBA_NUM_THREADS} "
            "threads numba may use here (NUMBA_NUM_THREADS)"
        )
    return int(threads)


def packed_for_render(w: World, options: Options, caller: str = "render") -> Packed:
    packed = pack_world(w, options.dtype)
    if w.light is None and len(packed.shapes):
        raise PackError(f"{caller}: the world has no light source")
    return packed


def _render(
    options: Options,
    c: Camera,
    w: World,
    settings: RenderSettings | None,
    count_rays: bool,
) -> tuple[ArrayCanvas, np.ndarray]:
    settings = settings if settings is not None else RenderSettings()
    camera = pack_camera(c, options.dtype)
    packed = packed_for_render(w, options)
    kernels = load_kernels(options.config(analyse(packed), count_rays))
    threads = render_threads(options)
    out = np.zeros((camera.vsize, camera.hsize, 3), dtype=options.dtype)
    counts = np.zeros((threads, 3), dtype=np.int64)
    seed_key = np.uint64((settings.seed * GAMMA) & MASK64)
    common = (
        camera.array, *packed.arrays(), packed.light, settings.depth, settings.samples,
        seed_key, float(settings.epsilon), packed.cs_size, packed.cs_prims, counts,
    )  # fmt: skip
    if threads == 1:
        kernels.render_serial(out, *common)
    else:
        _numba().set_num_threads(threads)
        kernels.render_parallel(out, threads, *common)
    return ArrayCanvas(out), counts


def render(
    options: Options,
    c: Camera,
    w: World,
    settings: RenderSettings | None = None,
    progress: Callable[[int], object] | None = None,
) -> ArrayCanvas:
    """Chapter 7: ``render(c, w, settings, progress)`` through a kernel specialized to ``w``.

    progress: called once, with the number of rows, when the whole image is done.
    """
    image, _ = _render(options, c, w, settings, False)
    if progress is not None:
        progress(c.vsize)
    return image


def count_rays(
    options: Options, c: Camera, w: World, settings: RenderSettings | None = None
) -> dict[str, int]:
    """Every ray one render casts, by kind (``Variant.count_rays``): camera rays, shadow
    rays (none is cast where the light is behind the surface: it could not change the
    color) and reflected or refracted ones. Runs a counting kernel, never a timed one."""
    settings = settings if settings is not None else RenderSettings()
    return {kind: n for kind, n in traversals(options, c, w, settings).items() if kind != "n1n2"}


def traversals(
    options: Options, c: Camera, w: World, settings: RenderSettings | None = None
) -> dict[str, int]:
    """``count_rays``, plus ``n1n2``: the extra passes over the world that find n1 and n2
    at transparent hits (the reference reads them off the hit's intersection list)."""
    settings = settings if settings is not None else RenderSettings()
    _, counts = _render(options, c, w, settings, True)
    traced, shadow, n1n2 = (int(v) for v in counts.sum(axis=0))
    camera = c.hsize * c.vsize * settings.samples
    return {"camera": camera, "shadow": shadow, "secondary": traced - camera, "n1n2": n1n2}


def explain(options: Options, w: World) -> str:
    """What a render of ``w`` runs: the feature set found, the kernel, the threads."""
    packed = packed_for_render(w, options, "explain")
    found = analyse(packed)
    config = options.config(found)
    kinds: dict[str, int] = {}
    for shape in packed.shapes:
        kinds[type(shape).__name__] = kinds.get(type(shape).__name__, 0) + 1
    counted = ", ".join(f"{name} x{count}" for name, count in sorted(kinds.items()))
    lines = [
        f"numba: this world has {len(packed.shapes)} primitives ({counted or 'none'}) and needs",
        *[f"  {line}" for line in found.describe()],
    ]
    if options.specialize:
        left_out = ", ".join(found.left_out()) or "nothing"
        lines.append(f"  kernel: specialized to these features; left out: {left_out}")
    else:
        lines.append("  kernel: generic, every feature compiled in (specialize=off)")
    lines.append(f"  precision: {config.describe()}")
    threads = options.threads or render_threads(options)
    lines.append(
        f"  threads: {threads}"
        + (
            f" (thread k renders rows k, k + {threads}, k + {2 * threads}, ...)"
            if threads > 1
            else ""
        )
    )
    return "\n".join(lines)
