"""The book's shading pipeline and render loop as one interface (chapters 6-11), after
pbrt-v4's ``Integrator``: methods that reach each other through ``self``, so a variant
overrides only the step it changes and every other step calls the override.

::

    render ─> render_into ─> render_region ─> prepare (once a frame) ─> pixel_color
    pixel_color ─> ray_for_pixel, color_at
    color_at ─> intersect_world, prepare_computations, shade_hit
    shade_hit ─> light_for_sample, intensity_at, lighting, reflected_color,
                 refracted_color, schlick
    intensity_at ─> is_shadowed (once per point light, once per cell of an area light)
    reflected_color, refracted_color ─> color_at (one level deeper)

The path integrator (chapter 21 here, beyond the book; ``raytracer.path``), which
``pixel_color`` calls instead of ``color_at`` when ``settings.integrator`` is "path"::

    path_color_at ─> intersect_world, prepare_computations, scatter, direct_light,
                     path_color_at (the next bounce)
    scatter ─> schlick;  direct_light ─> is_shadowed

Area lights (the bonus chapter "Rendering soft shadows", 18 here): ``shade_hit`` asks, for
light number k of the world, ``light_k = light_for_sample(light, k)``, then ``intensity =
intensity_at(light_k, over_point, w)`` and ``lighting(..., light_k, ..., intensity,
ambient=k == 0)``. ``intensity_at`` and ``lighting`` each walk the cells v outer, u inner,
and take two values of ``light_k.jitter_by`` per cell, so they see the same points when
the sequence's length divides ``2 * samples``.

Random jitter, the contract every variant follows (``AreaLight.jitter``, a scene file's
``jitter: true``): the tracer keeps the sample being traced in ``_sample`` = (seed, x, y,
i), which ``pixel_color`` sets before each sample (i = 0 with one sample per pixel) and
which is (0, 0, 0, 0) outside a render. ``light_for_sample`` gives a jittered light a copy
whose ``jitter_by`` is ``sequence(ju(0, 0), jv(0, 0), ju(1, 0), jv(1, 0), ...)``: the
values of ``raytracer.sampling.light_jitter(seed, x, y, i, k, u, v)`` in cell order, a
fresh sequence at every shaded point. So where a cell is sampled depends on the seed, the
pixel, the sample, the light's index and the cell, never on the order rays are traced
(reflected and refracted rays of a sample see the same points); intensity_at and lighting
take exactly ``2 * samples`` values each, so both see the same points. Any other light is
used as it is.

The book's module-level names (``raytracer.color_at`` ...) are the bound methods of
``TRACER``, the default instance, so ``color_at(w, r)`` means what it always meant. The
leaf steps are their chapter's functions, kept beside the values they work on
(``lighting`` in ``materials``, ``prepare_computations`` and ``schlick`` in
``intersections``, ``ray_for_pixel`` in ``camera``); a variant overrides them as methods.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from raytracer import path
from raytracer.camera import PATH, Camera, RenderSettings
from raytracer.camera import ray_for_pixel as camera_ray
from raytracer.canvas import Canvas, canvas
from raytracer.colors import BLACK, Color
from raytracer.intersections import (
    Computations,
    Intersection,
    hit,
    intersections,
    refraction_direction,
)
from raytracer.intersections import prepare_computations as computations_for
from raytracer.intersections import schlick as schlick_reflectance
from raytracer.lights import AreaLight, CyclicSequence, Light, describe_lights, point_on_light
from raytracer.materials import lighting as phong
from raytracer.rays import Ray, ray
from raytracer.sampling import light_jitters, sample_offset
from raytracer.shapes.shape import Shape, intersect
from raytracer.space import Placed
from raytracer.tolerance import using_epsilon
from raytracer.tuples import Tuple, magnitude, normalize
from raytracer.world import World

Region = tuple[int, int, int, int]
"""x0, y0, x1, y1: the pixels x0 <= x < x1, y0 <= y < y1 of an image (a row, a tile)."""

Progress = Callable[[int], object]
"""Called with the number of image rows just finished."""

Sample = tuple[int, int, int, int]
"""seed, x, y, i: sample i of pixel (x, y) of a render with that seed."""

NO_SAMPLE: Sample = (0, 0, 0, 0)
"""The sample outside a render."""

BOOK_STEPS = (
    "lighting", "intersect_world", "prepare_computations", "shade_hit", "is_shadowed",
    "color_at", "reflected_color", "refracted_color", "schlick", "ray_for_pixel", "render",
    "intensity_at",
)  # fmt: skip
"""The methods that are book names (``raytracer.api.BOOK_API``)."""

PATH_STEPS = ("path_color_at", "scatter", "direct_light")
"""The path integrator's methods (``raytracer.path``), names of the book's API too (chapter
21 here, beyond the book)."""

STEPS = (
    *BOOK_STEPS, *PATH_STEPS, "pixel_color", "prepare", "render_region", "render_into",
    "new_canvas", "write_region", "light_for_sample", "world_for", "check_settings",
)  # fmt: skip
"""Every overridable step of the interface, book names first."""

RENDER_LOOP = ("pixel_color", "prepare", "render_region", "render_into")
"""The steps of chapter 7's ``render`` below it: a variant that overrides one renders with
code of its own."""


def shape_lit(obj: Placed) -> Shape:
    """``lighting``'s object as the shape it is, for a tracer that needs the whole shape (to
    pack it); the reference's ``lighting`` reads only its placement (``Placed``)."""
    if not isinstance(obj, Shape):
        raise TypeError(f"lighting: expected the shape being lit, got {type(obj).__name__}")
    return obj


def light_and_point(
    w: World, first: Tuple, second: Tuple | None, caller: str
) -> tuple[Tuple, Tuple]:
    """(light position, point) from ``is_shadowed``'s two forms: ``(w, point)``, the
    book's, towards the world's first light; ``(w, light_position, point)``, the soft
    shadows bonus chapter's."""
    if second is not None:
        return first, second
    if w.light is None:
        raise ValueError(f"{caller}: the world has no light source")
    return w.light.position, first


class Tracer:
    """The book's tracer. Subclass it and override a step; wrap it to change where
    ``render_region`` runs (a pool, a cluster)."""

    __slots__ = ("_frame", "_sample")

    def __init__(self) -> None:
        self._frame: tuple[Camera, World, RenderSettings, Any] | None = None
        self._sample: Sample = NO_SAMPLE

    # -- chapter 6

    lighting = staticmethod(phong)
    """Chapters 6, 8, 10: the Phong color of one point lit by one light
    (``raytracer.materials.lighting``)."""

    # -- chapters 7 and 8

    def intersect_world(self, w: World, r: Ray) -> list[Intersection]:
        """Chapter 7: every intersection of ``r`` with every object, in a new list sorted
        by t."""
        xs: list[Intersection] = []
        for obj in w.objects:
            xs.extend(intersect(obj, r))
        return intersections(*xs)

    prepare_computations = staticmethod(computations_for)
    """Chapters 7, 8, 11: the state shading needs for a hit
    (``raytracer.intersections.prepare_computations``)."""

    def shade_hit(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapters 7, 8, 11: the color at a hit: surface (shadowed or not), plus reflection
        and refraction, blended with Schlick's reflectance for reflective, transparent
        surfaces. remaining: how many more reflected or refracted rays may be spawned.

        Several lights (the book's published scenes): each light adds its own diffuse and
        specular with its own shadow test; the ambient term is counted once, with the first
        light (so a one-light world shades as in the book). No light: black surfaces.

        Soft shadows: each light's share is ``lighting`` with the fraction of it that
        reaches the point (``intensity_at``: 0 or 1 for a point light), the light being
        ``light_for_sample``'s (a jittered area light's points for this sample)."""
        m = comps.object.material
        surface = BLACK
        for k, light in enumerate(w.lights):
            light_k = self.light_for_sample(light, k)
            intensity = self.intensity_at(light_k, comps.over_point, w)
            lit = self.lighting(
                m, comps.object, light_k, comps.over_point, comps.eyev, comps.normalv,
                intensity, ambient=k == 0,
            )  # fmt: skip
            surface = lit if k == 0 else surface + lit
        reflected = self.reflected_color(w, comps, remaining)
        refracted = self.refracted_color(w, comps, remaining)
        if m.reflective > 0 and m.transparency > 0:
            reflectance = self.schlick(comps)
            return surface + reflected * reflectance + refracted * (1 - reflectance)
        return surface + reflected + refracted

    def color_at(self, w: World, r: Ray, remaining: int = 5) -> Color:
        """Chapter 7: the color seen along ``r``: black when it hits nothing."""
        xs = self.intersect_world(w, r)
        h = hit(xs)
        if h is None:
            return BLACK
        return self.shade_hit(w, self.prepare_computations(h, r, xs), remaining)

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        """Chapter 8: True when an object that casts shadows lies between a point and a
        light: ``is_shadowed(w, point)`` (the book's, the world's first light) or
        ``is_shadowed(w, light_position, point)`` (any light)."""
        light_position, point = light_and_point(w, first, second, "is_shadowed")
        v = light_position - point
        distance = magnitude(v)
        r = ray(point, normalize(v))
        xs = [i for i in self.intersect_world(w, r) if i.object.casts_shadow]
        h = hit(xs)
        return h is not None and h.t < distance

    # -- soft shadows (the bonus chapter, 18 here)

    def intensity_at(self, light: Light, point: Tuple, w: World) -> float:
        """Soft shadows: the fraction of ``light`` that reaches ``point``: 1.0 or 0.0 for a
        point light (``is_shadowed`` towards its position); for an area light, the fraction
        of its cells (v outer, u inner) whose ``point_on_light`` is not shadowed, a
        multiple of ``1 / samples``."""
        if not isinstance(light, AreaLight):
            return 0.0 if self.is_shadowed(w, light.position, point) else 1.0
        total = 0.0
        for v in range(light.vsteps):
            for u in range(light.usteps):
                if not self.is_shadowed(w, point_on_light(light, u, v), point):
                    total += 1.0
        return total / light.samples

    def light_for_sample(self, light: Light, k: int) -> Light:
        """Soft shadows: light number ``k`` of the world as the current sample
        (``_sample``) sees it: a jittered area light (``jitter`` True) as a copy whose
        ``jitter_by`` is this sample's ``light_jitter`` values in cell order (v outer, u
        inner, u's value then v's); any other light as it is."""
        if not isinstance(light, AreaLight) or not light.jitter:
            return light
        values = light_jitters(*self._sample, k, light.usteps, light.vsteps)
        return replace(light, jitter_by=CyclicSequence(values))

    # -- chapter 11

    def reflected_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: the color reflected at the hit, scaled by the material's
        reflectivity; black at ``remaining`` 0."""
        reflective = comps.object.material.reflective
        if reflective == 0 or remaining <= 0:
            return BLACK
        reflect_ray = ray(comps.over_point, comps.reflectv)
        return self.color_at(w, reflect_ray, remaining - 1) * reflective

    def refracted_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: the color seen through the surface (Snell's law), scaled by
        transparency; black at ``remaining`` 0 and under total internal reflection."""
        transparency = comps.object.material.transparency
        if transparency == 0 or remaining <= 0:
            return BLACK
        direction = refraction_direction(comps)
        if direction is None:
            return BLACK  # total internal reflection
        refract_ray = ray(comps.under_point, direction)
        return self.color_at(w, refract_ray, remaining - 1) * transparency

    schlick = staticmethod(schlick_reflectance)
    """Chapter 11: Schlick's reflectance at a hit (``raytracer.intersections.schlick``)."""

    # -- chapter 21 (beyond the book): the path integrator, ``raytracer.path``'s functions
    # bound as methods (the tracer is their first argument)

    path_color_at = path.path_color_at
    scatter = path.scatter
    direct_light = path.direct_light
    crossed_lights = path.crossed_lights

    # -- chapter 7: the camera and the render loop

    ray_for_pixel = staticmethod(camera_ray)
    """Chapter 7: the ray through pixel (px, py) (``raytracer.camera.ray_for_pixel``)."""

    def pixel_color(self, c: Camera, w: World, x: int, y: int, settings: RenderSettings) -> Color:
        """The color of pixel (x, y): one ray through its centre (the book), or the mean of
        ``settings.samples`` rays placed by ``raytracer.sampling`` (summed in order, then
        multiplied by 1 / samples). Sets ``_sample`` before each (jittered area lights, the
        path integrator's random numbers). Each ray's color is ``color_at``'s (the book's
        integrator) or ``path_color_at``'s (``settings.integrator`` "path")."""
        trace = self.color_at if settings.integrator != PATH else self._path_trace(settings)
        if settings.samples == 1:
            self._sample = (settings.seed, x, y, 0)
            return trace(w, self.ray_for_pixel(c, x, y), settings.depth)
        total = BLACK
        for i in range(settings.samples):
            self._sample = (settings.seed, x, y, i)
            dx, dy = sample_offset(settings.seed, x, y, i)
            sample = self.ray_for_pixel(c, x + dx - 0.5, y + dy - 0.5)
            total = total + trace(w, sample, settings.depth)
        return total * (1.0 / settings.samples)

    def _path_trace(self, settings: RenderSettings) -> Callable[[World, Ray, int], Color]:
        """``path_color_at`` for a camera ray, with the settings' roulette and light
        sampling."""

        def trace(w: World, r: Ray, depth: int) -> Color:
            return self.path_color_at(
                w, r, depth, settings.roulette, light_sampling=settings.light_sampling
            )

        return trace

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Any:
        """What ``render_region`` needs for every region of one frame, made once per frame
        (``prepared``). The reference's: a function from (x, y) to the pixel's color. A
        variant that keeps per-render state (buffers, packed arrays) returns its own."""

        def pixel(x: int, y: int) -> Color:
            return self.pixel_color(c, w, x, y, settings)

        return pixel

    def prepared(self, c: Camera, w: World, settings: RenderSettings) -> Any:
        """``prepare(c, w, settings)``, reused while the same three objects come back (a
        worker renders many regions of one frame). The world must not change between the
        regions of one frame; ``render`` prepares afresh on every call."""
        frame = self._frame
        if frame is not None and frame[0] is c and frame[1] is w and frame[2] is settings:
            return frame[3]
        state = self.prepare(c, w, settings)
        self._frame = (c, w, settings, state)
        return state

    def forget(self) -> None:
        """Drop the prepared frame (the next region prepares anew) and the current sample
        (back to ``NO_SAMPLE``)."""
        self._frame = None
        self._sample = NO_SAMPLE

    def render_region(
        self, c: Camera, w: World, settings: RenderSettings, region: Region
    ) -> Sequence[float]:
        """The pixels of ``region`` (x1, y1 exclusive) as row-major ``[r, g, b, r, g, b,
        ...]``: the unit that ``render``, pools and clusters hand out. The one pixel loop."""
        pixel = self.prepared(c, w, settings)
        x0, y0, x1, y1 = region
        values: list[float] = []
        with using_epsilon(settings.epsilon):
            for y in range(y0, y1):
                for x in range(x0, x1):
                    color = pixel(x, y)
                    values += (color.red, color.green, color.blue)
        return values

    def render(
        self,
        c: Camera,
        w: World,
        settings: RenderSettings | None = None,
        progress: Progress | None = None,
    ) -> Canvas:
        """Chapter 7: render ``w`` as seen by ``c`` into a new canvas.

        settings: depth, samples per pixel, seed and epsilon (default ``RenderSettings()``);
        progress: called with the number of rows just finished.
        """
        settings = settings if settings is not None else RenderSettings()
        self.check_settings(settings)
        image = self.new_canvas(c)
        self.forget()
        try:
            self.render_into(image, c, w, settings, progress)
        finally:
            self.forget()
        return image

    def render_into(
        self,
        image: Canvas,
        c: Camera,
        w: World,
        settings: RenderSettings,
        progress: Progress | None = None,
    ) -> None:
        """Fill ``image`` region by region: here one row at a time, in this process (where
        the regions are traced is what a pool or a cluster changes)."""
        for y in range(c.vsize):
            row = (0, y, c.hsize, y + 1)
            self.write_region(image, row, self.render_region(c, w, settings, row))
            if progress is not None:
                progress(1)

    def new_canvas(self, c: Camera) -> Canvas:
        """Chapter 2: the canvas a render of ``c`` fills, every pixel black."""
        return canvas(c.hsize, c.vsize)

    def write_region(self, image: Canvas, region: Region, values: Sequence[float]) -> None:
        """Write a region's pixels, as ``render_region`` returns them, into ``image``."""
        write_region(image, region, values)

    # -- what the harness asks of a tracer

    def check_settings(self, settings: RenderSettings) -> None:
        """Raise an error naming this tracer (a ``ValueError``) when it cannot render with
        ``settings``; ``render`` asks before it starts, so a pool or a cluster asks here,
        not in its workers. The reference renders with any: both integrators."""

    def world_for(self, scene: Any) -> Any:
        """What a render of a loaded scene file (``scene.Scene``: a description, nothing
        built) runs on: the world ``render`` is then given. The reference's is the book's
        ``World``, built through the scene's API, with every top-level group, OBJ model and
        CSG shape divided (the bonus chapter 'Bounding boxes and hierarchies'), since a
        Python tracer walks the book's groups. A tracer that packs a scene its own way
        returns its own world, and no book shape need be built."""
        return scene.book_world(divide=True)

    def explain(self, w: World) -> str:
        """What a render of ``w`` would run (``rtc render --explain``)."""
        return (
            f"{type(self).__name__}: the book's pipeline in Python, one pixel at a time; "
            f"{len(w.objects)} objects at the top of the world, {describe_lights(w.lights)}"
        )


def write_region(image: Canvas, region: Region, values: Sequence[float]) -> None:
    """Write a region's row-major ``[r, g, b, ...]`` values into ``image`` (a reference
    canvas: one slice of its pixel list per row)."""
    x0, y0, x1, y1 = region
    width = x1 - x0
    if not (0 <= x0 <= x1 <= image.width and 0 <= y0 <= y1 <= image.height):
        raise ValueError(
            f"write_region: region {region} is outside the {image.width}x{image.height} canvas"
        )
    if len(values) != 3 * width * (y1 - y0):
        raise ValueError(f"write_region: {len(values)} values for the {region} region")
    for row, y in enumerate(range(y0, y1)):
        start = 3 * width * row
        image.pixels[y * image.width + x0 : y * image.width + x1] = [
            Color(values[k], values[k + 1], values[k + 2])
            for k in range(start, start + 3 * width, 3)
        ]


def overridden_steps(tracer: Tracer) -> tuple[str, ...]:
    """The steps whose code in ``type(tracer)`` is not the reference ``Tracer``'s."""
    cls = type(tracer)
    return tuple(name for name in STEPS if getattr(cls, name) is not getattr(Tracer, name))


TRACER = Tracer()
"""The default instance: the book's module-level names are its bound methods."""

lighting = TRACER.lighting  # the leaf steps are their chapter's functions themselves
intersect_world = TRACER.intersect_world
prepare_computations = TRACER.prepare_computations
shade_hit = TRACER.shade_hit
color_at = TRACER.color_at
is_shadowed = TRACER.is_shadowed
intensity_at = TRACER.intensity_at
reflected_color = TRACER.reflected_color
refracted_color = TRACER.refracted_color
schlick = TRACER.schlick
ray_for_pixel = TRACER.ray_for_pixel
pixel_color = TRACER.pixel_color
path_color_at = TRACER.path_color_at
scatter = TRACER.scatter
direct_light = TRACER.direct_light
crossed_lights = TRACER.crossed_lights
render = TRACER.render
