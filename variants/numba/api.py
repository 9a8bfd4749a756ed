"""``NumbaTracer``: the book's pipeline and API answered by the kernels (chapters 5-16).

The render (``prepare``, ``render_region``, ``render``) packs the world once per frame and
runs the compiled render entry over regions of the image (``render``). Every other method
packs the objects it is given (a shape, a world, a camera; nothing is cached,
since shapes and worlds are mutable), calls one compiled entry point of the generic kernel
module (every feature on, the variant's precision) and converts the result back to the
reference's values: ``Intersection``, ``Computations``, ``Color``, points and vectors. The
test shape of chapter 9 is packed as a kind that never intersects; its ``saved_ray`` is
the object-space ray the kernel computes, when the ray gets past the boxes around it
(``intersect`` packs a box for every group and CSG shape, as the reference tests them:
the bonus chapter on bounding boxes; ``intersect_world`` uses the variant's ``bvh``).

Everything else (constructors, tuples, matrices, ``hit``, canvases) is the reference's.
"""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import Any

import numpy as np

from raytracer.api import naive_api
from raytracer.camera import Camera, RenderSettings
from raytracer.canvas import Canvas
from raytracer.colors import Color
from raytracer.intersections import Computations, Intersection
from raytracer.lights import AreaLight, Light
from raytracer.materials import Material, light_fraction
from raytracer.patterns import Pattern
from raytracer.rays import Ray
from raytracer.sampling import sample_key
from raytracer.shapes.csg import CSG, OPERATIONS
from raytracer.shapes.group import Group
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.test_shape import TestShape
from raytracer.space import Placed
from raytracer.tolerance import epsilon
from raytracer.tracer import Progress, Region, light_and_point, shape_lit
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.arrays.canvas import ArrayCanvas, ArrayCanvasTracer
from variants.numba import layout as L
from variants.numba.lights import light_rows, move_on
from variants.numba.pack import pack_camera, pack_scene, pack_shapes, pack_surface, pack_world
from variants.numba.packed import Packed
from variants.numba.render import Frame, Options, explain, prepare_frame, run_region, traversals
from variants.numba.specialize import load_kernels
from variants.numba.textures import TextureTable

# the book names answered with compiled code that are not ``Tracer`` steps (extra ``api``
# entries; the steps' names come from the tracer)
EXTRA = frozenset(
    {
        "intersect", "local_intersect", "normal_at", "local_normal_at", "world_to_object",
        "normal_to_world", "pattern_at", "pattern_at_shape", "stripe_at", "stripe_at_object",
        "filter_intersections", "intersection_allowed",
    }
)  # fmt: skip
ALIASES = {"stripe_at": "pattern_at", "stripe_at_object": "pattern_at_shape"}
OPERATION_CODES = {
    "union": L.OP_UNION,
    "intersection": L.OP_INTERSECTION,
    "difference": L.OP_DIFFERENCE,
}


def _ray(r: Ray) -> np.ndarray:
    o, d = r.origin, r.direction
    return np.array([o.x, o.y, o.z, d.x, d.y, d.z], dtype=np.float64)


def _floats(*values: Any) -> tuple[float, ...]:
    """Numbers as floats: an entry point is compiled once per argument types, so a point
    given with integers (``point(1, 0, 0)``) would compile it again."""
    return tuple(float(value) for value in values)


def _xyz(t: Tuple) -> np.ndarray:
    return np.array([t.x, t.y, t.z], dtype=np.float64)


def _point(x: Any, y: Any, z: Any) -> Tuple:
    return Tuple(float(x), float(y), float(z), 1.0)


def _vector(x: Any, y: Any, z: Any) -> Tuple:
    return Tuple(float(x), float(y), float(z), 0.0)


def _color(rgb: Any) -> Color:
    r, g, b = rgb
    return Color(float(r), float(g), float(b))


def _light_table(light: Light, dtype: Any) -> np.ndarray:
    """One light as a light table (``layout``) for one ``lighting`` or ``intensity_at``
    call: an area light's sequence as that call takes it (``lights.light_rows``)."""
    rows, values = light_rows([light], dtype, for_one_call=True)
    return np.concatenate([rows.reshape(-1), values])


def _no_surface(shape: Shape, caller: str) -> None:
    """Groups and CSG shapes have no surface of their own (as in the reference)."""
    if isinstance(shape, Group | CSG):
        kind = "a group" if isinstance(shape, Group) else "a CSG shape"
        raise TypeError(
            f"{caller}({type(shape).__name__}): {kind} has no surface of its own; normals "
            "are computed on the child that was hit"
        )


def _uv(shape: Shape, hit: Intersection | None, caller: str) -> tuple[float, float]:
    if not isinstance(shape, SmoothTriangle):
        return 0.0, 0.0
    if hit is None or hit.u is None or hit.v is None:
        raise ValueError(
            f"{caller}(SmoothTriangle): needs the hit with its u and v "
            "(an intersection from local_intersect or intersection_with_uv)"
        )
    return float(hit.u), float(hit.v)


class NumbaTracer(ArrayCanvasTracer):
    """The book's tracer through the kernels, for one set of options (chapters 5-16)."""

    __slots__ = ("_kernels", "dtype", "options")

    def __init__(self, options: Options) -> None:
        super().__init__()
        self.options = options
        self.dtype = options.dtype
        self._kernels: ModuleType | None = None

    def world_for(self, scene: Any) -> Packed:
        """The scene packed straight from its description (``pack_scene``): no book shape
        is built, an OBJ model's triangles go from its arrays to the tables. With
        ``bvh=groups`` the book's world is built and divided first (its groups' boxes are
        the hierarchy); else every group is flattened (``sah``: into a hierarchy of its
        own; ``off``: a flat loop)."""
        if self.options.bvh == "groups":
            world = scene.book_world(divide=True)
            return pack_world(world, self.dtype, structure="groups", compact=True)
        return pack_scene(scene, self.dtype, structure=self.options.bvh)

    @property
    def k(self) -> ModuleType:
        """The generic kernel module (loaded, or compiled and cached, on first use)."""
        if self._kernels is None:
            self._kernels = load_kernels(self.options.generic())
        return self._kernels

    # -- chapters 5, 9, 14, 16: intersections

    def _intersections(self, packed: Packed, r: Ray, sort: bool) -> list[Intersection]:
        ray = _ray(r)
        n, ts, rows, us, vs, reached = self.k.api_intersections(
            *packed.flat(), ray, epsilon(), sort, packed.capacity, packed.cs_size,
            packed.cs_prims,
        )  # fmt: skip
        for row, shape in enumerate(packed.shapes):
            # the test shape records the ray when it gets there: past its groups' boxes
            if isinstance(shape, TestShape) and reached[row]:
                o = self.k.api_local_ray(packed.flat()[0], row, ray)
                shape.saved_ray = Ray(_point(*o[:3]), _vector(*o[3:]))
        found: list[Intersection] = []
        for j in range(n):
            shape = packed.shapes[rows[j]]
            if isinstance(shape, SmoothTriangle):
                found.append(Intersection(float(ts[j]), shape, float(us[j]), float(vs[j])))
            else:
                found.append(Intersection(float(ts[j]), shape))
        return found

    def intersect(self, shape: Shape, r: Ray) -> list[Intersection]:
        """Chapters 5, 9, 14, 16: a world-space ray against ``shape`` (its own transform)."""
        packed = pack_shapes([shape], self.dtype, structure="groups", every_box=True)
        return self._intersections(packed, r, _composite(shape))

    def local_intersect(self, shape: Shape, local_ray: Ray) -> list[Intersection]:
        """Chapter 9: an object-space ray against ``shape``."""
        packed = pack_shapes(
            [shape], self.dtype, own_transform=False, structure="groups", every_box=True
        )
        return self._intersections(packed, local_ray, _composite(shape))

    def intersect_world(self, w: World, r: Ray) -> list[Intersection]:
        """Chapter 7: every intersection with every object, sorted by t."""
        packed = pack_world(w, self.dtype, allow_test_shape=True, structure=self.options.bvh)
        return self._intersections(packed, r, True)

    def filter_intersections(self, c: CSG, xs: Sequence[Intersection]) -> list[Intersection]:
        """Chapter 16: the intersections ``c``'s operation keeps."""
        packed = pack_shapes([c], self.dtype, own_transform=False)
        mid = int(packed.csg[-1, L.CSG_MID])  # the root operation comes last (post-order)
        lhits = np.array([0 <= packed.row_of(i.object) < mid for i in xs], dtype=np.bool_)
        keep = self.k.api_filter(OPERATION_CODES[c.operation], lhits)
        return [i for i, kept in zip(xs, keep, strict=True) if kept]

    def intersection_allowed(self, operation: str, lhit: bool, inl: bool, inr: bool) -> bool:
        """Chapter 16: whether an intersection is on the combined surface."""
        if operation not in OPERATIONS:
            known = ", ".join(repr(name) for name in OPERATIONS)
            raise ValueError(
                f"intersection_allowed: unknown CSG operation {operation!r}; choose {known}"
            )
        return bool(self.k.api_allowed(OPERATION_CODES[operation], lhit, inl, inr))

    # -- chapters 6, 9, 14, 15: normals and spaces

    def normal_at(self, shape: Shape, world_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapters 6, 9, 14, 15: the world-space normal."""
        _no_surface(shape, "normal_at")
        u, v = _uv(shape, hit, "normal_at")
        pf, pi = pack_surface(shape, self.dtype)
        p = world_point
        normal = self.k.api_normal(pf, pi, 0, *_floats(p.x, p.y, p.z, u, v), epsilon(), True)
        return _vector(*normal)

    def local_normal_at(
        self, shape: Shape, local_point: Tuple, hit: Intersection | None = None
    ) -> Tuple:
        """Chapter 9: the object-space normal (not normalized)."""
        _no_surface(shape, "local_normal_at")
        u, v = _uv(shape, hit, "local_normal_at")
        pf, pi = pack_surface(shape, self.dtype)
        p = local_point
        normal = self.k.api_normal(pf, pi, 0, *_floats(p.x, p.y, p.z, u, v), epsilon(), False)
        return _vector(*normal)

    def world_to_object(self, shape: Shape, p: Tuple) -> Tuple:
        """Chapter 14: a world-space point in ``shape``'s object space."""
        pf, _ = pack_surface(shape, self.dtype, leaf=False)
        x, y, z = self.k.api_world_to_object(pf, 0, *_floats(p.x, p.y, p.z, p.w))
        return Tuple(float(x), float(y), float(z), float(p.w))

    def normal_to_world(self, shape: Shape, n: Tuple) -> Tuple:
        """Chapter 14: an object-space normal in world space, normalized."""
        pf, _ = pack_surface(shape, self.dtype, leaf=False)
        return _vector(*self.k.api_normal_to_world(pf, 0, *_floats(n.x, n.y, n.z)))

    # -- chapters 6, 10: lighting and patterns

    def lighting(
        self,
        material: Material,
        object: Placed | None,
        light: Light,
        point: Tuple,
        eyev: Tuple,
        normalv: Tuple,
        in_shadow: bool | float = False,
        ambient: bool = True,
    ) -> Color:
        """Chapters 6, 8, 10 and the bonus chapter on soft shadows: the Phong color at one
        point lit by a point light or an area light; ``in_shadow``: True, False, or the
        fraction of the light that arrives (``intensity_at``); ``ambient`` False: without
        the ambient term, as a world's second and later lights add theirs. An area light's
        sequence moves on by the values the call takes, as the reference's does."""
        intensity = light_fraction(in_shadow)
        textures = TextureTable()
        shape = None if object is None else shape_lit(object)
        pf, pi = pack_surface(shape, self.dtype, material=material, textures=textures)
        rgb = self.k.api_lighting(
            pf, pi, *textures.arrays(self.dtype), 0, _light_table(light, self.dtype), 1, 0,
            np.uint64(0), _xyz(point), _xyz(eyev), _xyz(normalv), intensity, bool(ambient),
        )  # fmt: skip
        move_on(light)
        return _color(rgb)

    def pattern_at(self, pattern: Pattern, p: Tuple) -> Color:
        """Chapter 10: the color at a pattern-space point."""
        textures = TextureTable()
        pf, pi = pack_surface(None, self.dtype, pattern=pattern, textures=textures)
        ti, tf = textures.arrays(self.dtype)
        return _color(self.k.api_pattern(pf, pi, ti, tf, 0, *_floats(p.x, p.y, p.z), False))

    def pattern_at_shape(self, pattern: Pattern, shape: Shape, p: Tuple) -> Color:
        """Chapters 10, 14: the color on ``shape`` at a world-space point."""
        textures = TextureTable()
        pf, pi = pack_surface(shape, self.dtype, pattern=pattern, leaf=False, textures=textures)
        ti, tf = textures.arrays(self.dtype)
        return _color(self.k.api_pattern(pf, pi, ti, tf, 0, *_floats(p.x, p.y, p.z), True))

    # -- chapters 7, 8, 11: shading

    def prepare_computations(
        self, hit: Intersection, r: Ray, xs: Sequence[Intersection] | None = None
    ) -> Computations:
        """Chapters 7, 8, 11: what shading needs to know about ``hit``."""
        shape = hit.object
        _no_surface(shape, "normal_at")
        u, v = _uv(shape, hit, "normal_at")
        pf, pi = pack_surface(shape, self.dtype)
        values = self.k.api_prepare(pf, pi, 0, _ray(r), *_floats(hit.t, u, v), epsilon())
        px, py, pz, ex, ey, ez, nx, ny, nz, inside, ox, oy, oz, ux, uy, uz, rx, ry, rz = values
        n1, n2 = self._refractive_indices(hit, [hit] if xs is None else xs)
        return Computations(
            t=hit.t, object=shape, point=_point(px, py, pz), eyev=_vector(ex, ey, ez),
            normalv=_vector(nx, ny, nz), inside=bool(inside), over_point=_point(ox, oy, oz),
            under_point=_point(ux, uy, uz), reflectv=_vector(rx, ry, rz), n1=float(n1),
            n2=float(n2),
        )  # fmt: skip

    def _refractive_indices(
        self, hit: Intersection, xs: Sequence[Intersection]
    ) -> tuple[float, float]:
        numbers: dict[int, int] = {}
        ids = np.array([numbers.setdefault(id(i.object), len(numbers)) for i in xs], np.int64)
        indices = np.array([i.object.material.refractive_index for i in xs], dtype=self.dtype)
        hit_index = next(
            (k for k, i in enumerate(xs) if i is hit or (i.t == hit.t and i.object is hit.object)),
            -1,
        )
        n1, n2 = self.k.api_containers_indices(ids, indices, hit_index)
        return float(n1), float(n2)

    def _world_with(self, w: World, shape: Shape, caller: str) -> tuple[Packed, int]:
        """``w`` packed, and the row of ``shape`` (appended, unreachable by rays, when it
        is not in the world)."""
        packed = pack_world(w, self.dtype, allow_test_shape=True, structure=self.options.bvh)
        row = packed.row_of(shape)
        if row < 0:
            _no_surface(shape, caller)
            pf, pi = pack_surface(shape, self.dtype, textures=packed.textures)
            packed.pf = np.vstack([packed.pf, pf.reshape(1, L.NF)])
            packed.pi = np.vstack([packed.pi, pi.reshape(1, L.NI)])
            row = len(packed.pf) - 1
        return packed, row

    def _shade(
        self, mode: int, w: World, comps: Computations, remaining: int, caller: str
    ) -> Color:
        packed, row = self._world_with(w, comps.object, caller)
        c = comps
        values = np.array(
            [
                c.eyev.x, c.eyev.y, c.eyev.z, c.normalv.x, c.normalv.y, c.normalv.z,
                c.over_point.x, c.over_point.y, c.over_point.z,
                c.under_point.x, c.under_point.y, c.under_point.z,
                c.reflectv.x, c.reflectv.y, c.reflectv.z, c.n1, c.n2,
            ],
            dtype=np.float64,
        )  # fmt: skip
        rgb = self.k.api_shade(
            *packed.flat(), *packed.light_table(), *packed.texture_table(), row, values, mode,
            int(remaining), epsilon(), packed.cs_size, packed.cs_prims, self._key(),
        )  # fmt: skip
        return _color(rgb)

    def _key(self) -> np.uint64:
        """The key of the sample being traced (``Tracer._sample``: set by ``pixel_color``;
        (0, 0, 0, 0) outside a render): where jittered area lights sample their cells."""
        return np.uint64(sample_key(*self._sample))

    def shade_hit(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapters 7, 8, 11: the color at a prepared hit."""
        return self._shade(0, w, comps, remaining, "shade_hit")

    def reflected_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: the reflected color at a prepared hit."""
        return self._shade(1, w, comps, remaining, "reflected_color")

    def refracted_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: the refracted color at a prepared hit."""
        return self._shade(2, w, comps, remaining, "refracted_color")

    def _trace(
        self, mode: int, w: World, values: list[float], remaining: int, light: Light | None = None
    ) -> Any:
        """``api_shade`` in ``mode`` over ``w`` packed (with its lights, or ``light`` alone:
        ``intensity_at``)."""
        packed = pack_world(w, self.dtype, allow_test_shape=True, structure=self.options.bvh)
        lights = packed.light_table() if light is None else (_light_table(light, self.dtype), 1)
        return self.k.api_shade(
            *packed.flat(), *lights, *packed.texture_table(), 0,
            np.array(values, dtype=np.float64), mode, int(remaining), epsilon(),
            packed.cs_size, packed.cs_prims, self._key(),
        )  # fmt: skip

    def color_at(self, w: World, r: Ray, remaining: int = 5) -> Color:
        """Chapter 7: the color seen along ``r`` (black surfaces in a world with no light)."""
        o, d = r.origin, r.direction
        return _color(self._trace(3, w, [o.x, o.y, o.z, d.x, d.y, d.z], remaining))

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        """Chapter 8: is something between a point and a light? ``is_shadowed(w, point)``
        (the world's first light) or ``is_shadowed(w, light_position, point)``."""
        light, p = light_and_point(w, first, second, "is_shadowed")
        red, _, _ = self._trace(4, w, [p.x, p.y, p.z, light.x, light.y, light.z], 0)
        return bool(red > 0.5)

    def intensity_at(self, light: Light, point: Tuple, w: World) -> float:
        """The bonus chapter on soft shadows: the fraction of ``light`` that reaches
        ``point``: 1.0 or 0.0 for a point light (``is_shadowed``); for an area light, the
        fraction of its cells whose point no shadow-casting object hides (its sequence moves
        on by the values the call takes, as the reference's does)."""
        if not isinstance(light, AreaLight):
            return 0.0 if self.is_shadowed(w, light.position, point) else 1.0
        p = point
        red, _, _ = self._trace(5, w, [p.x, p.y, p.z], 0, light)
        move_on(light)
        return float(red)

    def schlick(self, comps: Computations) -> float:
        """Chapter 11: Schlick's reflectance at a prepared hit."""
        return float(self.k.api_schlick(_xyz(comps.eyev), _xyz(comps.normalv), comps.n1, comps.n2))

    # -- chapter 7: the camera and the render

    def ray_for_pixel(self, c: Camera, px: float, py: float) -> Ray:
        """Chapter 7: the ray through pixel (px, py)."""
        camera = pack_camera(c, self.dtype)
        ox, oy, oz, dx, dy, dz = self.k.api_camera_ray(camera.array, float(px), float(py))
        return Ray(_point(ox, oy, oz), _vector(dx, dy, dz))

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Frame:
        """Chapter 7: a frame's state: camera and world packed, the render entry of ``w``'s
        feature set loaded, the threads' scratch (``prepared`` keeps it for the regions).
        Either integrator: the path integrator's kernel is ``kernels_path``."""
        self.check_settings(settings)
        return prepare_frame(self.options, c, w, settings)

    def render_region(
        self, c: Camera, w: World, settings: RenderSettings, region: Region
    ) -> list[float]:
        """Chapter 7: the pixels of ``region`` as row-major ``[r, g, b, ...]``, from the
        frame prepared once for ``c``, ``w`` and ``settings``."""
        values: list[float] = run_region(self.prepared(c, w, settings), region).ravel().tolist()
        return values

    def render_into(
        self,
        image: Canvas,
        c: Camera,
        w: World,
        settings: RenderSettings,
        progress: Progress | None = None,
    ) -> None:
        """Chapter 7: the whole image as one region, through a kernel specialized to ``w``
        (on this variant's threads); ``progress`` with the rows finished, as each thread's
        chunks of rows end (``render.run_region``)."""
        frame, whole = self.prepared(c, w, settings), (0, 0, c.hsize, c.vsize)
        if isinstance(image, ArrayCanvas) and image.array.dtype == frame.dtype:
            run_region(frame, whole, out=image.array, progress=progress)  # into the canvas
        else:
            values = run_region(frame, whole, progress=progress).ravel().tolist()
            self.write_region(image, whole, values)

    def canvas_dtype(self) -> Any:
        """This variant's precision (``float32``)."""
        return self.dtype

    # -- what the harness asks of a tracer

    def count_rays(
        self, c: Camera, w: World, settings: RenderSettings | None = None
    ) -> dict[str, int]:
        """Every ray one render casts, by kind: camera rays, shadow rays (none is cast where
        the light is behind the surface: it could not change the color) and reflected or
        refracted ones. Runs a counting kernel, never a timed one."""
        counted = traversals(self.options, c, w, settings)
        return {kind: n for kind, n in counted.items() if kind != "n1n2"}

    def explain(self, w: World) -> str:
        """What a render of ``w`` would run (for ``rtc render --explain``)."""
        return explain(self.options, w)

    def book_api(self) -> dict[str, Any]:
        """The reference's API with the names in ``EXTRA`` answered by this tracer
        (``tracer_variant`` binds the pipeline's names)."""
        api = dict(naive_api())
        for name in EXTRA:
            api[name] = getattr(self, ALIASES.get(name, name))
        return api

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as its options (the kernels and a prepared frame stay behind)."""
        return (NumbaTracer, (self.options,))


def _composite(shape: Shape) -> bool:
    """Groups and CSG shapes return their intersections sorted (as the reference's do)."""
    return isinstance(shape, Group | CSG)
