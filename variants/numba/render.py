"""Rendering through the kernels (chapter 7), the variant's options, and ``explain``.

A frame (``prepare_frame``, once per camera, world and settings) packs the world, finds
its feature set, loads the compiled render entry for that set (``specialize.
load_renderer``: a shared library, built on first use) and allocates each thread's scratch
(the ray stack and the CSG lists, on pages of its own). A region of the image (a row, a
tile, the whole image) is then rendered by ``run_region`` on T threads: T - 1 Python
threads and the calling one, each taking the next chunk of the region's rows from a shared
counter (``Rows``) and calling the entry for it through ctypes (which releases the GIL).
Nothing is allocated per pixel, nor in compiled code at all, and nothing the threads share
is written while they trace.

Why Python threads rather than numba's ``prange``: a ``parallel=True`` kernel needs numba
imported and its threading layer started in the process, which costs more than the render
of the reference scene (``specialize``); with rows handed out as threads ask and
per-thread scratch, Python threads split the work as evenly as ``prange`` did."""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from compiled.records import built
from raytracer.camera import PATH, Camera, RenderSettings
from raytracer.sampling import GAMMA, MASK64
from raytracer.tracer import Region
from raytracer.world import World
from variants.numba import layout as L
from variants.numba.bvh import DEFAULT
from variants.numba.features import KIND_NAMES, FeatureSet, analyse, generic
from variants.numba.lights import describe as describe_lights
from variants.numba.pack import pack_camera, pack_world
from variants.numba.packed import Packed, PackedCamera
from variants.numba.specialize import KernelConfig, Renderer, library_path, load_renderer

PAGE = 4096  # bytes: each thread's scratch starts on a page of its own (no false sharing)
CHUNK_SECONDS = 0.25  # with progress: each thread's rows in chunks of about this long
CHUNK_GROWTH = 4  # a chunk has at most this many times the rows of the one before
SHARE = 4  # with T threads, a chunk is at most 1 / (SHARE * T) of the rows left (``Rows``)
GENERIC_ONLY = "RTC_NUMBA_SPECIALIZE"
"""``RTC_NUMBA_SPECIALIZE=off``: every render of this process (and of the processes it
starts) runs the generic kernel, as ``specialize=off`` does, whatever the variant's option;
the test suite sets it (tests/conftest.py): one kernel for all its scenes, not one each."""
GENERIC_CALLS = "RTC_NUMBA_GENERIC_CALLS"
"""``RTC_NUMBA_GENERIC_CALLS=on``: a generic kernel (``specialize=off``, or the switch
above) calls its helpers rather than inlining them, as the book API's module does (with
every feature, it is that module): it compiles in two thirds of the CPU time (33 against
48 s for float64's) and runs a little slower. The test suite sets it (tests/conftest.py;
``--thorough`` does not); a timed render, whose ``specialize=off`` step shows what
specialization buys, never should. Without fast math the pictures are the same bits (no
fused multiply-add, so a call boundary changes no rounding)."""


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


class Options(NamedTuple):
    """The variant's options (all off by default).

    float32: compute and store in float32; fastmath: LLVM fast-math; threads: render
    threads (None: ``max_threads()``); specialize: a kernel per feature set (False: the
    generic kernel with every feature, to show what specialization buys); bvh: how the
    items are arranged (``bvh.STRUCTURES``: a hierarchy by the surface area heuristic, the
    scene's groups, or a flat list).
    """

    float32: bool = False
    fastmath: bool = False
    threads: int | None = None
    specialize: bool = True
    bvh: str = DEFAULT

    @property
    def dtype(self) -> Any:
        return np.float32 if self.float32 else np.float64

    @property
    def specializing(self) -> bool:
        """A kernel per feature set: the option, unless ``RTC_NUMBA_SPECIALIZE=off``."""
        return self.specialize and os.environ.get(GENERIC_ONLY, "on") != "off"

    def config(self, features: FeatureSet, count_rays: bool = False) -> KernelConfig:
        if self.specializing:
            return KernelConfig(features, self.float32, self.fastmath, count_rays)
        chosen = generic(features, self.float32 or self.fastmath)
        inline = os.environ.get(GENERIC_CALLS, "off") != "on"
        return KernelConfig(chosen, self.float32, self.fastmath, count_rays, inline)

    def generic(self) -> KernelConfig:
        """The kernel module the book-API calls use: every feature, this precision, its
        helpers called rather than inlined (compiled faster; the calls are not timed)."""
        return KernelConfig(FeatureSet.everything(), self.float32, self.fastmath, inline=False)


def render_threads(options: Options) -> int:
    threads = options.threads or max_threads()
    if threads < 1:
        raise ValueError(f"numba: threads={threads}: need at least one")
    return int(threads)


def packed_for_render(w: World | Packed, options: Options) -> Packed:
    """``w`` packed for a render (a world with no light renders black, as the reference
    shades it); a world packed already (``NumbaTracer.world_for``) as it is."""
    if isinstance(w, Packed):
        return w
    return pack_world(w, options.dtype, structure=options.bvh, compact=True)


class Scratch:
    """Every thread's scratch for one frame: the ray stack, CSG lists and one t per ball
    (floats), and the CSG lists, shadow memo and ray counters (ints), each thread's on
    pages of its own."""

    def __init__(self, threads: int, depth: int, packed: Packed, dtype: Any) -> None:
        entries = max(packed.cs_size, packed.cs_prims, L.MIN_SCRATCH)
        itemsize = np.dtype(dtype).itemsize
        self.stack_size = (depth + 2) * L.STACK_WIDTH + 6 * L.RAY_BLOCK  # and the camera rays
        self.sf_size = entries * L.NSF
        floats = self.stack_size + self.sf_size + max(packed.balls.shape[1], 1)
        ints = entries * L.NSI
        self.float_stride = -(-floats * itemsize // PAGE) * PAGE // itemsize
        self.int_stride = -(-ints * 8 // PAGE) * PAGE // 8
        self.floats = np.zeros(threads * self.float_stride + PAGE // itemsize, dtype=dtype)
        self.ints = np.zeros(threads * self.int_stride + PAGE // 8, dtype=np.int64)
        self.float_base = _page_offset(self.floats)
        self.int_base = _page_offset(self.ints)
        for k in range(threads):  # every light's shadow memo: none yet
            base = self.int_base + k * self.int_stride
            self.ints[base + L.MEMO : base + entries * L.NSI : L.NSI] = -1

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


@dataclass(eq=False)  # arrays and a lock: compared by identity
class Frame:
    """What every region of one frame needs (``NumbaTracer.prepare``): the packed camera
    and world, the loaded render entry, the threads' scratch and the entry's arguments
    that do not change from region to region. The scratch is the frame's: one region at
    a time (``lock``)."""

    camera: PackedCamera
    packed: Packed
    renderer: Renderer
    threads: int
    scratch: Scratch
    common: tuple[Any, ...]
    dtype: Any
    # thread k's last arguments: its scratch (stack, sf, si, tb), the sky, the integrator and
    # the roulette's first bounce (``kernels_entry.render_entry``)
    addresses: list[tuple[int, int, int, int, int, int, int]] = field(default_factory=list)
    lock: threading.Lock = field(default_factory=threading.Lock)
    arrays: tuple[Any, ...] = ()  # the arrays ``common`` points into, kept alive


def prepare_frame(
    options: Options, c: Camera, w: World, settings: RenderSettings, count_rays: bool = False
) -> Frame:
    """Pack ``c`` and ``w``, load the render entry for ``w``'s feature set (``count_rays``:
    the counting kernel) and allocate every thread's scratch."""
    camera = pack_camera(c, options.dtype)
    packed = packed_for_render(w, options)
    features = analyse(packed)
    path = settings.integrator == PATH
    renderer = load_renderer(options.config(features.with_path() if path else features, count_rays))
    threads = min(render_threads(options), max(camera.vsize, 1))
    scratch = Scratch(threads, settings.depth, packed, options.dtype)
    pf, pi, items, n_items, boxes, csg, balls, n_balls = packed.flat()
    lights, n_lights = packed.light_table()
    ti, tf = packed.texture_table()
    tg, tn = packed.triangle_tables()
    common = (
        camera.array.ctypes.data, pf.ctypes.data, pi.ctypes.data, items.ctypes.data, n_items,
        boxes.ctypes.data, csg.ctypes.data, balls.ctypes.data, n_balls, lights.ctypes.data,
        n_lights, ti.ctypes.data, tf.ctypes.data, tg.ctypes.data, tn.ctypes.data,
        settings.depth, settings.samples, (settings.seed * GAMMA) & MASK64,
        float(settings.epsilon),
    )  # fmt: skip
    sky = np.ascontiguousarray(packed.sky, dtype=options.dtype)
    integrator = L.INTEGRATOR_WHITTED
    if path:
        integrator = L.INTEGRATOR_PATH if settings.light_sampling else L.INTEGRATOR_PATH_CROSSED
    last = (sky.ctypes.data, integrator, settings.roulette)
    addresses = [(*scratch.addresses(k), *last) for k in range(threads)]
    arrays = (pf, pi, items, boxes, csg, balls, lights, ti, tf, tg, tn, sky)
    return Frame(
        camera, packed, renderer, threads, scratch, common, options.dtype, addresses,
        arrays=arrays,
    )  # fmt: skip


def chunk_rows(left: int, last_rows: int, last_seconds: float) -> int:
    """With progress: the most rows a thread's next chunk may have (``Rows.take``), ``left``
    being still to do, after a chunk of ``last_rows`` rows that took ``last_seconds`` (0 rows:
    the first chunk, one row). The others aim at ``CHUNK_SECONDS`` each at the rate the
    last one ran, growing at most ``CHUNK_GROWTH`` times a chunk (a first row of empty sky
    is fast and says little of the rows below it)."""
    if last_rows <= 0:
        return min(left, 1)
    rate = last_rows / max(last_seconds, 1e-9)
    return max(1, min(int(rate * CHUNK_SECONDS), CHUNK_GROWTH * last_rows, left))


class Rows:
    """A region's rows, handed out in chunks of consecutive rows to whichever thread asks
    next (guided self-scheduling): a chunk is at most ``1 / (SHARE * threads)`` of the rows
    still left, so the chunks shrink as the region ends and the threads finish together
    however the rows' costs differ, whichever thread the machine slows. One thread takes
    every row at once. The only state the threads share, taken under a lock once a chunk."""

    def __init__(self, height: int, threads: int) -> None:
        self.height = height
        self.share = SHARE * threads if threads > 1 else 1
        self.next = 0
        self.lock = threading.Lock()

    def take(self, most: int | None = None) -> tuple[int, int]:
        """(first, end) of the next chunk (at most ``most`` rows if given); first == end
        once every row has been handed out."""
        with self.lock:
            left = self.height - self.next
            rows = min(left, max(1, -(-left // self.share)))
            if most is not None:
                rows = min(rows, most)
            first = self.next
            self.next += rows
            return first, first + rows


def run_region(
    frame: Frame,
    region: Region,
    out: np.ndarray | None = None,
    progress: Callable[[int], object] | None = None,
) -> np.ndarray:
    """Chapter 7: the pixels of ``region`` (x0, y0, x1, y1) as a (y1 - y0, x1 - x0, 3)
    array (``out`` if given: C-contiguous, the frame's dtype), on up to ``frame.threads``
    threads (the calling thread is thread 0), each taking chunks of consecutive rows from
    ``Rows`` until none is left: a kernel call a chunk, on the thread's own scratch, into
    its own rows of ``out``. A pixel is the same whichever thread renders it.

    progress: called with the rows just finished, on the calling thread. Each thread's
    chunks are then also at most ``chunk_rows`` long (a report about every
    ``CHUNK_SECONDS``); the calling thread reports every thread's rows done after each of
    its chunks, and the rest once all have ended."""
    x0, y0, x1, y1 = (int(v) for v in region)
    height, width = max(y1 - y0, 0), max(x1 - x0, 0)
    if out is None:
        out = np.zeros((height, width, 3), dtype=frame.dtype)
    elif out.shape != (height, width, 3) or out.dtype != frame.dtype or not out.flags.c_contiguous:
        raise ValueError(f"numba render: out must be a C-contiguous {height}x{width}x3 array")
    if height == 0 or width == 0:
        return out
    threads = min(frame.threads, height)
    rows = Rows(height, threads)
    errors: list[BaseException] = []
    finished = [0] * threads  # rows done, by thread (each writes its own)
    reported = 0
    base, row_bytes = out.ctypes.data, width * 3 * out.itemsize

    def report() -> None:
        nonlocal reported
        done = sum(finished)
        if progress is not None and done > reported:
            progress(done - reported)
            reported = done

    def work(k: int) -> None:
        try:
            last_rows, last_seconds = 0, 0.0
            while True:
                most = None if progress is None else chunk_rows(height, last_rows, last_seconds)
                first, end = rows.take(most)
                if first == end:
                    return
                began = time.perf_counter()
                done = frame.renderer.function(
                    base + first * row_bytes, x0, y0 + first, x1, y0 + end, 0, 1,
                    *frame.common, *frame.addresses[k],
                )  # fmt: skip
                last_rows, last_seconds = end - first, time.perf_counter() - began
                if done != end - first:
                    raise RuntimeError(f"numba render: thread {k} did {done} of {end - first} rows")
                finished[k] += done
                if k == 0:
                    report()
        except BaseException as error:  # reported on the calling thread
            errors.append(error)

    with frame.lock:
        helpers = [threading.Thread(target=work, args=(k,), daemon=True) for k in range(1, threads)]
        for helper in helpers:
            helper.start()
        work(0)
        for helper in helpers:
            helper.join()
    if errors:
        raise errors[0]
    report()
    return out


def traversals(
    options: Options, c: Camera, w: World, settings: RenderSettings | None = None
) -> dict[str, int]:
    """Every ray one render casts, by kind (``NumbaTracer.count_rays``), plus ``n1n2``: the
    extra passes over the world that find n1 and n2 at transparent hits (the reference
    reads them off the hit's intersection list). Runs a counting kernel, never a timed
    one."""
    settings = settings if settings is not None else RenderSettings()
    frame = prepare_frame(options, c, w, settings, count_rays=True)
    run_region(frame, (0, 0, c.hsize, c.vsize))
    counted = [frame.scratch.rays(k) for k in range(frame.threads)]
    traced, shadow, n1n2 = (sum(column) for column in zip(*counted, strict=True))
    camera = c.hsize * c.vsize * settings.samples
    return {"camera": camera, "shadow": shadow, "secondary": traced - camera, "n1n2": n1n2}


def explain(options: Options, w: World) -> str:
    """What a render of ``w`` runs: the feature set found, the kernel, the threads."""
    packed = packed_for_render(w, options)
    found = analyse(packed)
    config = options.config(found)
    runs = packed.pi[:, L.TRI_FIRST] >= 0
    weights = np.where(runs, packed.pi[:, L.TRI_COUNT], 1)
    counts = np.bincount(packed.pi[:, L.KIND], weights=weights).astype(int)
    counted = ", ".join(f"{KIND_NAMES[k]} x{n}" for k, n in enumerate(counts.tolist()) if n)
    balls = int(packed.pi[:, L.WORLD_SPHERE].sum()) if len(packed.pi) else 0
    lines = [
        f"numba: this world has {packed.triangles()} primitives ({counted or 'none'}) and needs",
        *[f"  {line}" for line in found.describe()],
    ]
    if balls:
        lines.append(f"  spheres tested in world space (similarity transforms): {balls}")
    n_balls = packed.balls.shape[1]
    if n_balls:
        lines.append(f"  of them tested all at once, outside the items: {n_balls}")
    n_lights = len(packed.lights)
    lines.append(
        f"  lights: {n_lights}"
        + (" (every surface black)" if n_lights == 0 else "")
        + (" (each with its own shadow rays; the ambient term once)" if n_lights > 1 else "")
    )
    lines.extend(f"    {line}" for line in describe_lights(packed.lights))
    if packed.textures.uv_kinds:
        lines.append(f"  {packed.textures.describe()}")
    lines.append(f"  {packed.hierarchy.describe()}")
    lines.append(
        f"  packed in {packed.seconds:.3g} s ({len(packed.items):,} items, "
        f"{packed.pf.nbytes + packed.items.nbytes + packed.boxes.nbytes:,} bytes)"
    )
    if options.specializing:
        left_out = ", ".join(found.left_out()) or "nothing"
        lines.append(f"  kernel: specialized to these features; left out: {left_out}")
    else:
        why = "specialize=off" if not options.specialize else f"{GENERIC_ONLY}=off"
        everything = config.features == FeatureSet.everything()
        held = "every feature" if everything else config.features.key
        lines.append(f"  kernel: generic, {held} compiled in ({why})")
    lines.append(
        "  path integrator (--integrator path): a kernel of its own, these features and the "
        "path code; the one below is the book's integrator's, which leaves the path code out"
    )
    lines.append(f"  precision: {config.describe()}")
    library = library_path(config)
    state = "built" if built(library) is not None else "built by the first render, a few seconds"
    lines.append(f"  compiled render: {library} ({state})")
    threads = render_threads(options)
    lines.append(
        f"  threads: {threads}"
        + (
            " (each takes the next chunk of rows left, the chunks shrinking to the end)"
            if threads > 1
            else ""
        )
    )
    return "\n".join(lines)
