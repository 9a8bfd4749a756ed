"""Rendering through the kernels (chapter 7), the variant's options, and ``explain``.

A render packs the world once, finds its feature set, loads the compiled render entry for
that set (``specialize.load_renderer``: a shared library, built on first use) and runs it
on T threads: T - 1 Python threads and the calling one, each calling the entry through
ctypes (which releases the GIL) for rows k, k + T, k + 2T ... Nothing is allocated per
pixel, nor in compiled code at all: each thread's scratch (the ray stack and the CSG
lists) is allocated here, once per render, each thread's on pages of its own.

Why Python threads rather than numba's ``prange``: a ``parallel=True`` kernel needs numba
imported and its threading layer started in the process, which costs more than the render
of the reference scene (``specialize``); with interleaved rows and per-thread scratch,
Python threads split the work as evenly as ``prange`` did.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import Camera, RenderSettings
from raytracer.sampling import GAMMA, MASK64
from raytracer.world import World
from variants.numba import layout as L
from variants.numba.canvas import ArrayCanvas
from variants.numba.features import FeatureSet, analyse
from variants.numba.pack import Packed, PackedCamera, PackError, pack_camera, pack_world
from variants.numba.specialize import KernelConfig, Renderer, library_path, load_renderer

PAGE = 4096  # bytes: each thread's scratch starts on a page of its own (no false sharing)


def max_threads() -> int:
    """How many render threads make sense here (``NUMBA_NUM_THREADS`` if set, else the
    CPUs this process may run on)."""
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
    threads (None: ``max_threads()``); specialize: a kernel per feature set (False: the
    generic kernel with every feature, to show what specialization buys).
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


def render_threads(options: Options) -> int:
    threads = options.threads or max_threads()
    if threads < 1:
        raise ValueError(f"numba: threads={threads}: need at least one")
    return int(threads)


def packed_for_render(w: World, options: Options, caller: str = "render") -> Packed:
    packed = pack_world(w, options.dtype)
    if w.light is None and len(packed.shapes):
        raise PackError(f"{caller}: the world has no light source")
    return packed


class Scratch:
    """Every thread's scratch for one render: the ray stack, CSG lists and one t per ball
    (floats), and the CSG lists, shadow memo and ray counters (ints), each thread's on
    pages of its own."""

    def __init__(self, threads: int, depth: int, packed: Packed, dtype: Any) -> None:
        entries = max(packed.cs_size, packed.cs_prims, L.MIN_SCRATCH)
        itemsize = np.dtype(dtype).itemsize
        self.stack_size = (depth + 2) * L.STACK_WIDTH
        self.sf_size = entries * L.NSF
        floats = self.stack_size + self.sf_size + max(packed.balls.shape[1], 1)
        ints = entries * L.NSI
        self.float_stride = -(-floats * itemsize // PAGE) * PAGE // itemsize
        self.int_stride = -(-ints * 8 // PAGE) * PAGE // 8
        self.floats = np.zeros(threads * self.float_stride + PAGE // itemsize, dtype=dtype)
        self.ints = np.zeros(threads * self.int_stride + PAGE // 8, dtype=np.int64)
        self.float_base = _page_offset(self.floats)
        self.int_base = _page_offset(self.ints)
        for k in range(threads):
            self.ints[self.int_base + k * self.int_stride + L.MEMO] = -1

    def addresses(self, k: int) -> tuple[int, int, int, int]:
        """Thread k's (stack, sf, si, tb) addresses."""
        size = self.floats.itemsize
        f = self.floats.ctypes.data + (self.float_base + k * self.float_stride) * size
        i = self.ints.ctypes.data + (self.int_base + k * self.int_stride) * 8
        sf = f + self.stack_size * size
        return f, sf, i, sf + self.sf_size * size

    def rays(self, k: int) -> list[int]:
        """Thread k's ray counters (counting kernels): traced, shadow, n1/n2 passes."""
        base = self.int_base + k * self.int_stride
        return [int(self.ints[base + j * L.NSI + L.RAYS]) for j in range(3)]


def _page_offset(array: np.ndarray) -> int:
    """How many elements into ``array`` the first page boundary is."""
    return (-array.ctypes.data % PAGE) // array.itemsize


def run_rows(
    renderer: Renderer,
    threads: int,
    out: np.ndarray,
    camera: PackedCamera,
    packed: Packed,
    settings: RenderSettings,
    scratch: Scratch,
) -> None:
    """Render every row of ``out`` (height, width, 3) on ``threads`` threads, thread k
    taking rows k, k + threads, ... (the calling thread is thread 0)."""
    pf, pi, items, n_items, boxes, csg, balls, n_balls = packed.flat()
    seed_key = (settings.seed * GAMMA) & MASK64
    height, width = out.shape[0], out.shape[1]
    common = (
        camera.array.ctypes.data, pf.ctypes.data, pi.ctypes.data, items.ctypes.data, n_items,
        boxes.ctypes.data, csg.ctypes.data, balls.ctypes.data, n_balls,
        packed.light.ctypes.data, settings.depth, settings.samples, seed_key,
        float(settings.epsilon),
    )  # fmt: skip
    errors: list[BaseException] = []

    def rows(k: int) -> None:
        try:
            done = renderer.function(
                out.ctypes.data, height, width, k, threads, *common, *scratch.addresses(k)
            )
            expected = len(range(k, height, threads))
            if done != expected:
                raise RuntimeError(f"numba render: thread {k} did {done} of {expected} rows")
        except BaseException as error:  # reported on the calling thread
            errors.append(error)

    helpers = [threading.Thread(target=rows, args=(k,), daemon=True) for k in range(1, threads)]
    for helper in helpers:
        helper.start()
    rows(0)
    for helper in helpers:
        helper.join()
    if errors:
        raise errors[0]


def _render(
    options: Options,
    c: Camera,
    w: World,
    settings: RenderSettings | None,
    count_rays: bool,
) -> tuple[ArrayCanvas, Scratch, int]:
    settings = settings if settings is not None else RenderSettings()
    camera = pack_camera(c, options.dtype)
    packed = packed_for_render(w, options)
    renderer = load_renderer(options.config(analyse(packed), count_rays))
    threads = min(render_threads(options), max(camera.vsize, 1))
    out = np.zeros((camera.vsize, camera.hsize, 3), dtype=options.dtype)
    scratch = Scratch(threads, settings.depth, packed, options.dtype)
    run_rows(renderer, threads, out, camera, packed, settings, scratch)
    return ArrayCanvas(out), scratch, threads


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
    image, _, _ = _render(options, c, w, settings, False)
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
    _, scratch, threads = _render(options, c, w, settings, True)
    counted = [scratch.rays(k) for k in range(threads)]
    traced, shadow, n1n2 = (sum(column) for column in zip(*counted, strict=True))
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
    balls = int(packed.pi[:, L.WORLD_SPHERE].sum()) if len(packed.pi) else 0
    lines = [
        f"numba: this world has {len(packed.shapes)} primitives ({counted or 'none'}) and needs",
        *[f"  {line}" for line in found.describe()],
    ]
    if balls:
        lines.append(f"  spheres tested in world space (similarity transforms): {balls}")
    if options.specialize:
        left_out = ", ".join(found.left_out()) or "nothing"
        lines.append(f"  kernel: specialized to these features; left out: {left_out}")
    else:
        lines.append("  kernel: generic, every feature compiled in (specialize=off)")
    lines.append(f"  precision: {config.describe()}")
    library = library_path(config)
    state = "built" if library.is_file() else "built by the first render, a few seconds"
    lines.append(f"  compiled render: {library} ({state})")
    threads = render_threads(options)
    lines.append(
        f"  threads: {threads}"
        + (
            f" (thread k renders rows k, k + {threads}, k + {2 * threads}, ...)"
            if threads > 1
            else ""
        )
    )
    return "\n".join(lines)
