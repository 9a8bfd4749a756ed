"""The ``prealloc`` variant gives the reference's answers bit for bit (chapters 5-16).

Renders are compared with ``naive`` pixel for pixel with ``==`` (no tolerance): the default
world, a scene with every shape, pattern and shading stage, antialiased with a seed and a
larger epsilon, and the reference scene. Random rays compare intersections, normals and
computations exactly with the reference's functions, shape by shape (on ``cached``'s twins
of the shapes, whose inverses are the same matrices, computed once). Then the variant's
contract: clear errors for what it cannot run, reused buffers, the registry entry.
"""

from __future__ import annotations

import dataclasses
import math
import random
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import pytest

import raytracer as rt
from raytracer.camera import RenderSettings
from raytracer.tracer import BOOK_STEPS
from scene import load_scene
from variants.cached import to_twins
from variants.prealloc import api as pa
from variants.prealloc.buffers import IntersectionBuffer, new_ray
from variants.prealloc.context import TraceContext
from variants.prealloc.errors import PreallocUnsupported
from variants.prealloc.render import PixelTracer
from variants.prealloc.shading import intersect_world_into
from variants.prealloc.tracer import PreallocTracer
from variants.registry import VariantError, load_variant

REFERENCE_SCENE = Path(__file__).resolve().parents[1] / "scenes" / "reference.yml"
Api = Mapping[str, Any]
PT = PreallocTracer()  # the pipeline's steps, each converting at the boundary


@pytest.fixture(scope="module")
def naive() -> Api:
    return load_variant("naive").api


@pytest.fixture(scope="module")
def prealloc() -> Api:
    return load_variant("prealloc").api


def assert_same_pixels(a: rt.Canvas, b: rt.Canvas) -> None:
    """Every pixel equal with ``==`` (float64, no tolerance); the first difference shown."""
    assert (a.width, a.height) == (b.width, b.height)
    for index, (p, q) in enumerate(zip(a.pixels, b.pixels, strict=True)):
        assert p == q, f"pixel ({index % a.width}, {index // a.width}): naive {p}, prealloc {q}"


def aimed_camera(api: Api, hsize: int, vsize: int, eye: rt.Tuple, at: rt.Tuple) -> Any:
    c = api["camera"](hsize, vsize, math.pi / 3)
    return dataclasses.replace(c, transform=rt.view_transform(eye, at, rt.vector(0, 1, 0)))


def every_feature_world(api: Api) -> Any:
    """Every shape, pattern and shading stage of chapters 5-16, built through ``api``:
    reflective checkered floor, striped wall, a glass sphere with an air bubble (Schlick,
    n1/n2 through containers), gradient, ring and test patterns, a cube, capped cylinder
    and cone, a transformed group, a flat and a smooth triangle, a CSG difference, and an
    object that casts no shadow."""
    material = api["material"]
    w = api["world"]()
    w.light = api["point_light"](rt.point(-4, 6, -6), rt.color(1, 1, 0.9))

    def add(shape: Any, transform: rt.Matrix | None = None, **looks: Any) -> Any:
        if transform is not None:
            api["set_transform"](shape, transform)
        if looks:
            shape.material = material(**looks)
        w.objects.append(shape)
        return shape

    def patterned(kind: str, a: rt.Color, b: rt.Color, transform: rt.Matrix) -> Any:
        p = api[kind](a, b)
        api["set_pattern_transform"](p, transform)
        return p

    white, black = rt.color(1, 1, 1), rt.color(0, 0, 0)
    floor_pattern = patterned("checkers_pattern", white, black, rt.scaling(0.5, 0.5, 0.5))
    add(api["plane"](), None, pattern=floor_pattern, reflective=0.3, specular=0.2)
    stripes = patterned(
        "stripe_pattern", rt.color(0.9, 0.2, 0.2), white, rt.rotation_y(0.5) * rt.scaling(0.3, 1, 1)
    )
    add(api["plane"](), rt.translation(0, 0, 6) * rt.rotation_x(math.pi / 2), pattern=stripes)
    add(
        api["sphere"](),
        rt.translation(0, 1, 0),
        color=rt.color(0.1, 0.1, 0.2),
        diffuse=0.1,
        reflective=0.9,
        transparency=0.9,
        refractive_index=1.5,
        shininess=300,
    )
    add(
        api["sphere"](),
        rt.translation(0, 1, 0) * rt.scaling(0.4, 0.4, 0.4),
        transparency=1.0,
        refractive_index=1.0,
        diffuse=0.0,
        ambient=0.0,
    )
    gradient = patterned("gradient_pattern", rt.color(0, 0.5, 1), white, rt.translation(-1, 0, 0))
    add(api["sphere"](), rt.translation(-2.2, 0.7, 1) * rt.scaling(0.7, 0.7, 0.7), pattern=gradient)
    rings = patterned("ring_pattern", rt.color(0.2, 0.8, 0.2), white, rt.scaling(0.2, 0.2, 0.2))
    add(
        api["cube"](),
        rt.translation(2.2, 0.5, 1) * rt.rotation_y(0.6) * rt.scaling(0.5, 0.5, 0.5),
        pattern=rings,
    )
    test_pattern = api["test_pattern"]()
    add(api["sphere"](), rt.translation(1.2, 0.3, -1.2) * rt.scaling(0.3, 0.3, 0.3),
        pattern=test_pattern)  # fmt: skip
    cyl = api["cylinder"]()
    cyl.minimum, cyl.maximum, cyl.closed = -1, 1, True
    add(cyl, rt.translation(-1.2, 0.4, -1.5) * rt.scaling(0.3, 0.4, 0.3),
        color=rt.color(1, 0.8, 0.4), reflective=0.2)  # fmt: skip
    cone = api["cone"]()
    cone.minimum, cone.maximum, cone.closed = -1, 0, True
    add(cone, rt.translation(0.2, 1, -2) * rt.scaling(0.3, 1, 0.3), color=rt.color(0.6, 0.3, 0.9))
    g = api["group"]()
    api["set_transform"](g, rt.translation(-1.5, 2.6, 2) * rt.rotation_z(0.4))
    for dx in (-0.6, 0.6):
        child = api["sphere"]() if dx < 0 else api["cube"]()
        api["set_transform"](child, rt.translation(dx, 0, 0) * rt.scaling(0.3, 0.3, 0.3))
        child.material = material(color=rt.color(0.3, 0.9, 0.9))
        api["add_child"](g, child)
    w.objects.append(g)
    add(
        api["triangle"](rt.point(1, 2, 2), rt.point(2.5, 2.5, 2.5), rt.point(1.5, 3.2, 1.8)),
        color=rt.color(1, 1, 0.3),
    )
    add(
        api["smooth_triangle"](
            rt.point(-0.5, 2.4, 3), rt.point(0.8, 2.6, 3), rt.point(0.2, 3.6, 3),
            rt.vector(-0.5, 0, -1), rt.vector(0.5, 0, -1), rt.vector(0, 0.6, -1),
        ),
        color=rt.color(0.9, 0.5, 0.5),
    )  # fmt: skip
    outer, hole = api["cube"](), api["sphere"]()
    api["set_transform"](hole, rt.scaling(1.3, 1.3, 1.3))
    carved = api["csg"]("difference", outer, hole)
    add(
        carved,
        rt.translation(2.8, 2.2, 3) * rt.scaling(0.5, 0.5, 0.5),
        color=rt.color(0.8, 0.8, 0.8),
    )
    ghost = add(
        api["sphere"](), rt.translation(-0.5, 3.5, -3) * rt.scaling(0.5, 0.5, 0.5),
        transparency=0.5,
    )  # fmt: skip
    ghost.casts_shadow = False
    return w


def render_both(
    naive: Api, prealloc: Api, build: Callable[[Api], tuple[Any, Any]], settings: Any = None
) -> tuple[rt.Canvas, rt.Canvas]:
    images = []
    for api in (naive, prealloc):
        camera, world = build(api)
        images.append(api["render"](camera, world, settings))
    return images[0], images[1]


def test_the_default_world_renders_as_naive_does(naive: Api, prealloc: Api) -> None:
    def build(api: Api) -> tuple[Any, Any]:
        c = aimed_camera(api, 24, 16, rt.point(0, 0.5, -5), rt.point(0, 0, 0))
        return c, api["default_world"]()

    assert_same_pixels(*render_both(naive, prealloc, build))


def test_every_shape_pattern_and_shading_stage_renders_as_naive_does(
    naive: Api, prealloc: Api
) -> None:
    def build(api: Api) -> tuple[Any, Any]:
        c = aimed_camera(api, 12, 9, rt.point(0, 2.5, -6), rt.point(0, 1.2, 1))
        return c, every_feature_world(api)

    a, b = render_both(naive, prealloc, build)
    assert_same_pixels(a, b)
    assert len(set(a.pixels)) > 40, "the scene should show many different colours"


def test_samples_seed_depth_and_epsilon_are_the_reference_s(naive: Api, prealloc: Api) -> None:
    settings = RenderSettings(depth=2, samples=2, seed=7, epsilon=0.001)

    def build(api: Api) -> tuple[Any, Any]:
        c = aimed_camera(api, 6, 4, rt.point(0, 2.5, -6), rt.point(0, 1.2, 1))
        return c, every_feature_world(api)

    a, b = render_both(naive, prealloc, build, settings)
    assert_same_pixels(a, b)
    one_sample = prealloc["render"](*build(prealloc), dataclasses.replace(settings, samples=1))
    assert one_sample.pixels != b.pixels, "two samples should differ from one"


def test_the_reference_scene_renders_as_naive_does(naive: Api, prealloc: Api) -> None:
    def build(api: Api) -> tuple[Any, Any]:
        scene = load_scene(REFERENCE_SCENE, api).resized(10, 8)
        return scene.camera, scene.world

    assert_same_pixels(*render_both(naive, prealloc, build))


def test_a_pixel_tracer_carries_nothing_from_one_pixel_to_the_next(prealloc: Api) -> None:
    """Pixels traced in any order (as a pool worker might) match the render's."""
    c = aimed_camera(prealloc, 8, 6, rt.point(0, 2.5, -6), rt.point(0, 1.2, 1))
    w = every_feature_world(prealloc)
    image = prealloc["render"](c, w)
    tracer = PixelTracer(c, w)
    for index in reversed(range(8 * 6)):
        x, y = index % 8, index // 8
        assert tracer(x, y) == rt.pixel_at(image, x, y), f"pixel ({x}, {y})"


class CountingTracer(PreallocTracer):
    """Counts the frames it prepares (each a ``PixelTracer``)."""

    __slots__ = ("frames",)

    def __init__(self) -> None:
        super().__init__()
        self.frames: list[PixelTracer] = []

    def prepare(self, c: Any, w: Any, settings: RenderSettings) -> PixelTracer:
        self.frames.append(super().prepare(c, w, settings))
        return self.frames[-1]


def test_a_render_prepares_one_pixel_tracer_per_frame(prealloc: Api) -> None:
    """The reference's pixel loop asks ``prepare`` once a frame: one set of records and
    buffers for every row."""
    c = aimed_camera(prealloc, 5, 4, rt.point(0, 0, -5), rt.point(0, 0, 0))
    w = prealloc["default_world"]()
    tracer = CountingTracer()
    image = tracer.render(c, w)
    assert len(tracer.frames) == 1 and isinstance(tracer.frames[0], PixelTracer)
    assert image.pixels == prealloc["render"](c, w).pixels
    tracer.render(c, w)
    assert len(tracer.frames) == 2, "each render prepares afresh"


def test_progress_is_called_once_per_row(prealloc: Api) -> None:
    rows: list[int] = []
    c = aimed_camera(prealloc, 5, 4, rt.point(0, 0, -5), rt.point(0, 0, 0))
    prealloc["render"](c, prealloc["default_world"](), None, rows.append)
    assert rows == [1, 1, 1, 1]


# ------------------------------------------------------------ random rays, shape by shape


def reference_shapes() -> list[rt.Shape]:
    """One of each shape, transformed, and some inside a transformed group: ``cached``'s
    twins, so that the reference's functions (which only read their inverses) run fast."""
    cyl = rt.cylinder()
    cyl.minimum, cyl.maximum, cyl.closed = -1, 2, True
    cone = rt.cone()
    cone.minimum, cone.maximum, cone.closed = -1.5, 1, True
    shapes: list[rt.Shape] = [
        rt.sphere(), rt.plane(), rt.cube(), cyl, cone,
        rt.triangle(rt.point(0, 1, 0), rt.point(-1, 0, 0), rt.point(1, 0, 0.5)),
        rt.smooth_triangle(
            rt.point(0, 1, 0), rt.point(-1, 0, 0), rt.point(1, 0, 0),
            rt.vector(0, 1, 0), rt.vector(-1, 0, 0), rt.vector(1, 0, 0),
        ),
        rt.csg("intersection", rt.cube(), rt.sphere()),
        rt.csg("union", rt.sphere(), rt.cube()),
    ]  # fmt: skip
    transforms = [rt.rotation_x(0.3) * rt.scaling(1, 0.5, 2), rt.translation(0.2, -0.1, 0.3)]
    for shape, m in zip(shapes, transforms * len(shapes), strict=False):
        rt.set_transform(shape, m)
    g = rt.group()
    rt.set_transform(g, rt.rotation_y(0.7) * rt.scaling(2, 2, 2))
    inner = rt.group()
    rt.set_transform(inner, rt.translation(0.5, 0, 0))
    rt.add_child(g, inner)
    rt.add_child(inner, rt.sphere())
    rt.add_child(g, rt.cube())
    return [to_twins(shape) for shape in [*shapes, g]]


def random_rays(count: int, seed: int) -> list[rt.Ray]:
    rng = random.Random(seed)
    rays = []
    for _ in range(count):
        origin = rt.point(*(rng.uniform(-4, 4) for _ in range(3)))
        target = rt.point(*(rng.uniform(-1, 1) for _ in range(3)))
        rays.append(rt.ray(origin, rt.normalize(target - origin)))
    return rays


def same_intersections(a: list[rt.Intersection], b: list[rt.Intersection]) -> bool:
    return len(a) == len(b) and all(
        i.t == j.t and i.object is j.object and (i.u, i.v) == (j.u, j.v)
        for i, j in zip(a, b, strict=True)
    )


@pytest.mark.parametrize("shape", reference_shapes(), ids=lambda s: type(s).__name__)
def test_random_rays_give_the_reference_s_intersections_and_normals(shape: rt.Shape) -> None:
    hits = 0
    for r in random_rays(200, seed=5):
        expected, got = rt.intersect(shape, r), pa.intersect(shape, r)
        assert same_intersections(expected, got), f"{r}: {expected} != {got}"
        for i in expected:
            point = rt.position(r, i.t)
            assert pa.normal_at(i.object, point, i) == rt.normal_at(i.object, point, i)
            hits += 1
    assert hits >= 10, "too few rays hit the shape to test its normals"


def test_random_rays_give_the_reference_s_computations_in_the_every_feature_world() -> None:
    w = every_feature_world(load_variant("cached").api)  # the reference's code, fast inverses
    shaded = 0
    for r in random_rays(120, seed=9):
        expected, got = rt.intersect_world(w, r), PT.intersect_world(w, r)
        assert same_intersections(expected, got)
        h = rt.hit(expected)
        assert pa.hit(expected) is h
        if h is None:
            continue
        comps = rt.prepare_computations(h, r, expected)
        assert PT.prepare_computations(h, r, expected) == comps
        assert PT.shade_hit(w, comps, 3) == rt.shade_hit(w, comps, 3)
        assert PT.is_shadowed(w, comps.over_point) == rt.is_shadowed(w, comps.over_point)
        shaded += 1
    assert shaded > 30


# --------------------------------------------------------------------- the contract


@dataclasses.dataclass(slots=True, eq=True, kw_only=True)
class Blob(rt.Shape):
    """A shape the prealloc variant does not know."""

    def local_intersect(self, local_ray: rt.Ray) -> list[rt.Intersection]:
        return []

    def local_normal_at(self, local_point: rt.Tuple, hit: Any = None) -> rt.Tuple:
        return rt.vector(0, 1, 0)


@dataclasses.dataclass(slots=True, eq=True, kw_only=True)
class BumpySphere(rt.Sphere):
    """A sphere subclass with its own normal: prealloc must not use the sphere's."""

    def local_normal_at(self, local_point: rt.Tuple, hit: Any = None) -> rt.Tuple:
        return rt.vector(0, 1, 0)


def test_an_unknown_shape_type_is_refused_by_name() -> None:
    w = rt.world()
    w.objects.append(Blob())
    w.light = rt.point_light(rt.point(0, 5, -5), rt.color(1, 1, 1))
    with pytest.raises(PreallocUnsupported, match="shape type Blob"):
        PreallocTracer().render(rt.camera(4, 3, 1.0), w)
    with pytest.raises(PreallocUnsupported, match="shape type Blob"):
        pa.intersect(Blob(), rt.ray(rt.point(0, 0, -5), rt.vector(0, 0, 1)))


def test_a_subclass_that_replaces_a_reimplemented_method_is_refused() -> None:
    with pytest.raises(PreallocUnsupported, match=r"BumpySphere overrides Sphere\.local_normal_at"):
        pa.normal_at(BumpySphere(), rt.point(1, 0, 0))


def test_the_intersection_buffer_is_reset_not_rebuilt() -> None:
    w = rt.default_world()
    ctx = TraceContext.for_world(w, rt.EPSILON)
    xs = IntersectionBuffer()
    ray = new_ray()
    ray[:] = [0.0, 0.0, -5.0, 1.0, 0.0, 0.0, 1.0, 0.0]
    intersect_world_into(ctx, ray, xs)
    storage = xs.ts
    assert xs.count == 4 and xs.ts[:4] == [4.0, 4.5, 5.5, 6.0]
    ray[4:8] = [0.0, 1.0, 0.0, 0.0]  # pointing up: misses both spheres
    intersect_world_into(ctx, ray, xs)
    assert xs.count == 0 and xs.ts is storage and len(storage) == 4


def test_the_registry_entry_builds_on_cached_and_overrides_the_hot_path() -> None:
    v = load_variant("prealloc")
    cached = load_variant("cached")
    assert v.name == "prealloc" and v.base == "cached"
    assert isinstance(v.tracer, PreallocTracer)
    pipeline = set(BOOK_STEPS) - {"render"}  # the one render loop is the reference's
    assert set(v.steps) == pipeline | {"prepare"}
    # render's loop is the reference's, over prealloc's prepared buffers: its own code
    assert v.overrides == pa.OVERRIDES | pipeline | {"render"} | cached.overrides
    for name in pa.OVERRIDES:
        assert v.api[name] is pa.API[name]
    for name in BOOK_STEPS:
        assert v.api[name].__self__ is v.tracer, name
    assert type(v.api["sphere"]()) is type(cached.api["sphere"]())


@pytest.mark.parametrize(
    ("name", "message"),
    [("prealloc[fast]", "takes no options"), ("prealloc:naive", "does not wrap")],
)
def test_options_and_inner_variants_are_refused(name: str, message: str) -> None:
    with pytest.raises(VariantError, match=message):
        load_variant(name)
