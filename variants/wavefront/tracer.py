"""``WavefrontTracer``: the Tracer interface (``raytracer.tracer``) answered by whole passes
of rays (chapters 5-16).

Overridden steps: ``prepare`` (the world packed and indexed once per frame),
``render_region`` and ``render_into`` (passes of pixels, on this tracer's threads),
``new_canvas``/``write_region`` (an array-backed canvas), and the book's
``intersect_world``, ``is_shadowed`` and ``color_at``, each a pass of one ray. The other
book steps (``shade_hit``, ``lighting``, ``reflected_color`` ...) are the reference's; they
call ``color_at`` and ``is_shadowed`` through ``self``, so the book's scenarios exercise
the passes too.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from raytracer.camera import PATH, WHITTED, Camera, RenderSettings
from raytracer.canvas import Canvas
from raytracer.colors import Color
from raytracer.intersections import Intersection
from raytracer.rays import Ray
from raytracer.tolerance import epsilon
from raytracer.tracer import Progress, Region, light_and_point
from raytracer.tuples import Tuple, magnitude, normalize
from raytracer.world import World
from variants.arrays.canvas import ArrayCanvas, ArrayCanvasTracer
from variants.wavefront.allocator import keep_freed_arrays
from variants.wavefront.camera import lens
from variants.wavefront.handoff import quick_handoffs
from variants.wavefront.hits import blocked, index, records
from variants.wavefront.pack import pack, pack_scene
from variants.wavefront.scene import KIND_NAMES, Scene, Unsupported
from variants.wavefront.wave import Frame, blocks, render_block, trace

MIB = 1 << 20
BYTES_PER_RAY = {8: 2048, 4: 1280}
"""What one ray of a batch costs at the peak of a pass, by float size (the batch's arrays,
the temporaries of its queries and shading, the batches waiting on the stack): measured
with ``tracemalloc`` on the reference scene, rounded up. A path-traced pass takes about a
third of it (its batch only shrinks from bounce to bounce, and nothing waits on a stack)."""
CSG_BYTES_PER_RAY = {8: 2560, 4: 2048}
"""The same in a scene with CSG trees (chapter 16), whose rays keep every intersection of a
tree's primitives until the tree's rules pick: measured on ``scenes/csg.yml``, rounded up."""
MIN_CAP = 64  # rays per batch at the least, whatever max_mb says


@dataclass(frozen=True)
class Options:
    """max_mb: the most MiB one pass's arrays may take (all threads together);
    float32: rays and tables in 32-bit floats; threads: passes traced at once."""

    max_mb: int = 256
    float32: bool = False
    threads: int = 1

    @property
    def dtype(self) -> Any:
        return np.dtype(np.float32 if self.float32 else np.float64)

    def cap(self, csg: bool = False) -> int:
        """Rays per batch: the pass budget shared by the threads (``csg``: the scene has
        CSG trees)."""
        per_ray = (CSG_BYTES_PER_RAY if csg else BYTES_PER_RAY)[self.dtype.itemsize]
        return max(MIN_CAP, self.max_mb * MIB // (self.threads * per_ray))


class WavefrontTracer(ArrayCanvasTracer):
    """The book's tracer as data-oriented passes over NumPy arrays."""

    __slots__ = ("options",)

    def __init__(self, options: Options | None = None) -> None:
        super().__init__()
        self.options = options if options is not None else Options()

    def world_for(self, scene: Any) -> Scene:
        """The scene's tables, packed straight from its description (``pack_scene``): no
        book shape is built; ``bvh`` builds a hierarchy of its own in ``prepare``."""
        return pack_scene(scene, self.options.dtype)

    def _make_frame(
        self, w: World | Scene, settings: RenderSettings, c: Camera | None = None,
        shading: bool = True,
    ) -> Frame:  # fmt: skip
        scene = w if isinstance(w, Scene) else pack(w, self.options.dtype, shading)
        if settings.integrator == WHITTED:
            scene.refuse_for_whitted()
        return Frame(
            index(scene),
            lens(c) if c is not None else None,
            settings,
            self.options.dtype,
            float(settings.epsilon),
            self.options.cap(csg=bool(scene.trees)),
        )

    def _book_frame(self, w: World, shading: bool = True) -> Frame:
        return self._make_frame(w, RenderSettings(epsilon=epsilon()), shading=shading)

    def _ray(self, r: Ray) -> tuple[np.ndarray, ...]:
        o, d = r.origin, r.direction
        values = (o.x, o.y, o.z, d.x, d.y, d.z)
        return tuple(np.array([v], dtype=self.options.dtype) for v in values)

    # -- the book's steps, one ray at a time

    def intersect_world(self, w: World, r: Ray) -> list[Intersection]:
        """Chapter 7: every intersection of ``r`` with the world, sorted by t (ties in the
        world's order)."""
        frame = self._book_frame(w, shading=False)
        with np.errstate(all="ignore"):
            found = records(frame.idx, self._ray(r), frame.eps, frame.cap)  # type: ignore[arg-type]
        order = np.lexsort((found.slot, found.prim, found.t))
        shapes = frame.idx.scene.shapes
        xs: list[Intersection] = []
        for k in order.tolist():
            shape: Any = shapes[int(found.prim[k])]
            t = float(found.t[k])
            if hasattr(shape, "intersection_at"):
                xs.append(shape.intersection_at(t, float(found.u[k]), float(found.v[k])))
            else:
                xs.append(Intersection(t, shape))
        return xs

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        """Chapter 8: is a shadow-casting object between a point and a light?
        ``is_shadowed(w, point)`` (the first light) or ``is_shadowed(w, light, point)``."""
        light, p = light_and_point(w, first, second, "is_shadowed")
        v = light - p
        distance = magnitude(v)
        frame = self._book_frame(w, shading=False)
        ray = self._ray(Ray(p, normalize(v)))
        limit = np.array([distance], dtype=self.options.dtype)
        with np.errstate(all="ignore"):
            return bool(blocked(frame.idx, ray, limit, frame.eps, frame.cap)[0])  # type: ignore[arg-type]

    def color_at(self, w: World, r: Ray, remaining: int = 5) -> Color:
        """Chapter 7: the color seen along ``r`` (reflections and refractions to depth
        ``remaining``), black when it meets nothing. A world with what the passes do not
        vectorize (an area light, a texture map) gets the reference's ``color_at``, which
        still calls this tracer's ``intersect_world`` and ``is_shadowed``; a render of it
        is refused (``prepare``)."""
        try:
            frame = self._book_frame(w)
        except Unsupported:
            return super().color_at(w, r, remaining)
        weight = np.ones(1, dtype=self.options.dtype)
        total = trace(frame, self._ray(r), weight, np.zeros(1, dtype=np.int64), remaining, 1)
        return Color(float(total[0, 0]), float(total[0, 1]), float(total[0, 2]))

    # -- chapter 7: the render

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Frame:
        """The frame: the world packed and indexed, the camera's numbers, the batch size
        (either integrator: ``render_block`` follows ``settings.integrator``). The passes'
        freed arrays are kept for the next ones (``allocator.keep_freed_arrays``)."""
        keep_freed_arrays()
        return self._make_frame(w, settings, c)

    def render_region(
        self, c: Camera, w: World, settings: RenderSettings, region: Region
    ) -> list[float]:
        """The pixels of ``region`` as row-major ``[r, g, b, ...]``, in passes."""
        frame = self.prepared(c, w, settings)
        x0, y0, x1, y1 = region
        n = (x1 - x0) * (y1 - y0)
        out = np.zeros((n, 3))
        for first, end in blocks(n, settings.samples, frame.cap):
            out[first:end] = render_block(frame, region, first, end)
        values: list[float] = out.ravel().tolist()
        return values

    def render_into(
        self,
        image: Canvas,
        c: Camera,
        w: World,
        settings: RenderSettings,
        progress: Progress | None = None,
    ) -> None:
        """The whole image in passes of whole pixels, on ``threads`` threads (each pass
        has its own arrays; the canvas rows they fill do not overlap); ``progress`` with
        the rows finished as passes end."""
        frame = self.prepared(c, w, settings)
        width, height = c.hsize, c.vsize
        whole = (0, 0, width, height)
        direct = isinstance(image, ArrayCanvas)
        out = (
            image.array.reshape(-1, 3)
            if isinstance(image, ArrayCanvas)
            else np.zeros((width * height, 3))
        )
        jobs = list(blocks(width * height, settings.samples, frame.cap, self.options.threads))
        reported = 0
        done = 0

        def finished(first: int, end: int, values: np.ndarray) -> None:
            nonlocal reported, done
            out[first:end] = values
            done += end - first
            rows = done // width
            if progress is not None and rows > reported:
                progress(rows - reported)
                reported = rows

        if self.options.threads == 1 or len(jobs) == 1:
            for first, end in jobs:
                finished(first, end, render_block(frame, whole, first, end))
        else:
            with quick_handoffs(), ThreadPoolExecutor(self.options.threads) as pool:
                futures = [
                    (first, end, pool.submit(render_block, frame, whole, first, end))
                    for first, end in jobs
                ]
                for first, end, future in futures:
                    finished(first, end, future.result())
        if not direct:
            self.write_region(image, whole, out.ravel().tolist())

    def canvas_dtype(self) -> Any:
        """float32 whatever the passes compute in: 8-bit images need no more, and a
        4000x3000 canvas takes 137 MiB instead of 275."""
        return np.float32

    # -- what the harness asks of a tracer

    def explain(self, w: World) -> str:
        """What a render of ``w`` would run (``rtc render --explain``): its packing, which
        holds area lights for the path integrator (the book's refuses them as it renders)."""
        frame = self._make_frame(w, RenderSettings(integrator=PATH))
        scene, hierarchy = frame.idx.scene, frame.idx.hierarchy
        kinds = np.bincount(scene.kind, minlength=len(KIND_NAMES))
        shapes = ", ".join(f"{n} {KIND_NAMES[k]}" for k, n in enumerate(kinds.tolist()) if n)
        trees = f", {len(scene.trees)} CSG trees" if scene.trees else ""
        tree = (
            f"a hierarchy of {hierarchy.nodes} nodes ({hierarchy.leaves} leaves, "
            f"{hierarchy.depth()} levels) over {scene.n_units - len(frame.idx.direct)} of "
            f"them, {len(frame.idx.direct)} tested directly"
            if hierarchy is not None
            else "every one tested directly"
        )
        o = self.options
        return (
            f"WavefrontTracer: passes of up to {frame.cap:,} rays (max_mb={o.max_mb}, "
            f"{o.dtype.name}, {o.threads} thread{'s' if o.threads > 1 else ''}); "
            f"{scene.n_prims} primitives ({shapes or 'none'}{trees}) in {scene.n_units} "
            f"units, {tree}; {len(scene.light_pos)} light"
            f"{'' if len(scene.light_pos) == 1 else 's'}"
        )

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as its options (a prepared frame stays behind)."""
        return (WavefrontTracer, (self.options,))
