"""The ``wavefront`` variant (issue 16): NumPy passes that draw the reference's pictures.

Its pieces against the reference, bit for bit where they follow its arithmetic (samples,
camera rays, every kind's intersections, n1/n2); whole pictures against ``cached`` (the
reference's pixels exactly, faster) within ``FLOAT64_WORST`` (the canvas stores float32);
what the options change and what they must not (``max_mb`` and ``threads`` change how the
work is cut, never a bit of the picture); and refusals, one clear error naming what the
passes do not vectorize.
"""

from __future__ import annotations

import itertools
import math
import random
import sys
import tracemalloc
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from groundwork.sizes import Size
from harness.document.model import Table
from harness.scenery.presets import SceneRef
from harness.sections.pass_size import measure as pass_size
from harness.sections.pass_size import plot as pass_size_plot
from harness.sections.pass_size import report as pass_size_report
from raytracer.camera import RenderSettings, ray_for_pixel
from raytracer.intersections import intersection, prepare_computations
from raytracer.materials import material
from raytracer.rays import ray
from raytracer.sampling import sample_offset
from raytracer.shapes.shape import intersect
from raytracer.shapes.sphere import Sphere
from raytracer.tracer import TRACER
from scene import load_scene
from variants.registry import VariantError, load_variant
from variants.wavefront import handoff
from variants.wavefront import hits as H
from variants.wavefront import tracer as tracer_module
from variants.wavefront import wave as wave_module
from variants.wavefront.camera import camera_rays, lens, sample_offsets
from variants.wavefront.indices import refractive_indices
from variants.wavefront.pack import pack
from variants.wavefront.scene import SLOTS, Unsupported
from variants.wavefront.tracer import WavefrontTracer
from variants.wavefront.wave import blocks

SCENES = Path(__file__).resolve().parents[1] / "scenes"
FLOAT64_WORST = 1e-6  # float32 canvas rounding is about 6e-8
NAIVE = load_variant("naive").api


def _pixels(name: str, build: Any, settings: RenderSettings | None = None) -> np.ndarray:
    variant = load_variant(name)
    camera, world = build(variant)
    image = variant.api["render"](camera, world, settings or RenderSettings())
    at = variant.api["pixel_at"]
    return np.array(
        [[(q.red, q.green, q.blue) for q in (at(image, x, y) for x in range(image.width))]
         for y in range(image.height)]
    )  # fmt: skip


def scene_file(name: str, width: int, height: int) -> Any:
    def build(variant: Any) -> tuple[Any, Any]:
        scene = load_scene(SCENES / name, variant.api, variant=variant.name)
        scene = scene.resized(width, height)
        return scene.camera, variant.world_for(scene)

    return build


def lit_scene(variant: Any, lights: int = 3, balls: int = 0) -> tuple[Any, Any]:
    """A reflective checkered floor, a glass sphere inside another, a striped cube in a
    rotated group, a CSG shape, a smooth triangle, a closed cone; ``balls`` small spheres
    in a row (over ``hits.DIRECT_MAX`` of them: the hierarchy); 16x12."""
    api = variant.api
    c, p, v = api["color"], api["point"], api["vector"]
    floor = api["plane"]()
    floor.material = material(
        pattern=api["checkers_pattern"](c(1, 1, 1), c(0.1, 0.1, 0.1)), reflective=0.3
    )
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](-1, 1, 0) * api["scaling"](0.7, 0.7, 0.7))
    glass.material = replace(glass.material, reflective=0.8, diffuse=0.1, ambient=0.05)
    core = api["glass_sphere"]()
    api["set_transform"](core, api["translation"](-1, 1, 0) * api["scaling"](0.3, 0.3, 0.3))
    core.material = replace(core.material, refractive_index=1.1)
    g = api["group"]()
    api["set_transform"](g, api["translation"](1.2, 0, 1) * api["rotation_y"](0.5))
    cube = api["cube"]()
    api["set_transform"](cube, api["translation"](0, 0.5, 0) * api["scaling"](0.5, 0.5, 0.5))
    stripes = api["stripe_pattern"](c(1, 0.2, 0.2), c(1, 1, 1))
    api["set_pattern_transform"](stripes, api["scaling"](0.2, 0.2, 0.2))
    cube.material = material(pattern=stripes)
    api["add_child"](g, cube)
    left, right = api["cube"](), api["sphere"]()
    api["set_transform"](right, api["scaling"](1.3, 1.3, 1.3))
    carved = api["csg"]("difference", left, right)
    api["set_transform"](carved, api["translation"](0.2, 0.5, -1.8) * api["scaling"](0.4, 0.4, 0.4))
    smooth = api["smooth_triangle"](
        p(0.5, 1.6, -0.8), p(-0.3, 1.2, -0.4), p(0.4, 0.9, -0.2),
        v(0, 1, -1), v(-1, 0, -1), v(1, 0, -1),
    )  # fmt: skip
    cone = api["cone"]()
    cone.minimum, cone.maximum, cone.closed = -1.0, 0.0, True
    api["set_transform"](cone, api["translation"](2, 1, -1) * api["scaling"](0.3, 0.5, 0.3))
    cone.material = material(pattern=api["ring_pattern"](c(0.2, 0.8, 0.2), c(1, 1, 1)))
    w = api["world"]()
    w.objects.extend([floor, glass, core, g, carved, smooth, cone])
    for k in range(balls):
        ball = api["sphere"]()
        api["set_transform"](
            ball, api["translation"](-2.5 + 5 * k / balls, 0.2, 1.5) * api["scaling"](0.1, 0.1, 0.1)
        )
        ball.material = material(color=c(0.2, 0.3, k / balls), reflective=0.5)
        w.objects.append(ball)
    lamps = (((-4, 6, -6), (1, 1, 1)), ((5, 3, -4), (0.3, 0.3, 0.6)), ((0, 8, 2), (0.5, 0.4, 0.2)))
    for at, rgb in lamps[:lights]:
        w.lights.append(api["point_light"](p(*at), c(*rgb)))
    view = api["view_transform"](p(0, 1.6, -5), p(0, 0.7, 0), v(0, 1, 0))
    return replace(api["camera"](16, 12, math.pi / 3), transform=view), w


def _same_picture(name: str, build: Any, settings: RenderSettings | None = None) -> np.ndarray:
    expected = _pixels("cached", build, settings)
    got = _pixels(name, build, settings)
    assert got.shape == expected.shape
    worst = float(np.abs(got - expected).max())
    assert worst <= FLOAT64_WORST, f"{name} differs from the reference by up to {worst:.3g}"
    assert len({tuple(p) for p in expected.reshape(-1, 3).round(3)}) > 5  # not blank
    return got


# ------------------------------------------------------------------------ the pieces


def test_samples_are_the_references_bit_for_bit() -> None:
    rng = random.Random(5)
    cases = [(0, 0, 0, 0), (2**64 - 1, 16383, 16383, 2**20 - 1), (11, 3, 4, 2)]
    cases += [
        (rng.randrange(2**64), rng.randrange(4000), rng.randrange(3000), rng.randrange(64))
        for _ in range(200)
    ]
    for seed in {case[0] for case in cases}:
        chosen = [case for case in cases if case[0] == seed]
        x, y, i = (np.array([case[k] for case in chosen]) for k in (1, 2, 3))
        dx, dy = sample_offsets(seed, x, y, i)
        expected = [sample_offset(*case) for case in chosen]
        assert dx.tolist() == [e[0] for e in expected]
        assert dy.tolist() == [e[1] for e in expected]
    with pytest.raises(ValueError, match=r"within 0\.\.16383"):
        sample_offsets(0, np.array([16384]), np.array([0]), np.array([0]))


def test_camera_rays_are_the_references_bit_for_bit() -> None:
    api = NAIVE
    view = api["view_transform"](
        api["point"](1, 2, -5), api["point"](0, 1, 0), api["vector"](0.2, 1, 0)
    )
    c = replace(api["camera"](21, 13, 1.2), transform=view)
    px = np.array([0, 20, 10, 3.25, 7.75, -0.5])
    py = np.array([0, 12, 6, 1.5, 11.99, 2.0])
    ox, oy, oz, dx, dy, dz = camera_rays(lens(c), px, py, np.float64)
    for k in range(len(px)):
        r = ray_for_pixel(c, float(px[k]), float(py[k]))
        assert (float(ox), float(oy), float(oz)) == (r.origin.x, r.origin.y, r.origin.z)
        assert (dx[k], dy[k], dz[k]) == (r.direction.x, r.direction.y, r.direction.z)


def _kinds(api: Any) -> list[Any]:
    """One shape of each kind, each with a transform that is not a similarity."""
    p, v = api["point"], api["vector"]
    shear = api["shearing"](0.3, 0, 0.1, 0, 0, 0.2)
    shapes = [api["sphere"](), api["plane"](), api["cube"](), api["cylinder"](), api["cone"]()]
    shapes[3].minimum, shapes[3].maximum, shapes[3].closed = -1.0, 2.0, True
    shapes[4].minimum, shapes[4].maximum, shapes[4].closed = -1.5, 1.0, True
    shapes.append(api["triangle"](p(0, 1, 0), p(-1, 0, 0), p(1, 0.2, 0.3)))
    shapes.append(
        api["smooth_triangle"](
            p(0, 1, 0), p(-1, 0, 0), p(1, 0, 0), v(0, 1, 0), v(-1, 0, 0), v(1, 0, 0)
        )
    )
    for k, s in enumerate(shapes):
        api["set_transform"](s, api["rotation_y"](0.3 * k) * shear * api["scaling"](1.2, 0.8, 1))
    return shapes


def test_every_kind_meets_rays_where_the_reference_does() -> None:
    api = NAIVE
    rng = random.Random(7)
    rays = []
    for _ in range(300):
        o = api["point"](*(rng.uniform(-4, 4) for _ in range(3)))
        target = api["point"](*(rng.uniform(-1.2, 1.2) for _ in range(3)))
        rays.append(ray(o, target - o))
    rays.append(ray(api["point"](0, 5, 0), api["vector"](0, -1, 0)))  # down the axis
    rays.append(ray(api["point"](3, 0.5, 0), api["vector"](-1, 0, 0)))  # parallel to y = 0
    batch = tuple(
        np.array([getattr(getattr(r, part), axis) for r in rays])
        for part in ("origin", "direction")
        for axis in "xyz"
    )
    for shape in _kinds(api):
        w = api["world"]()
        w.objects.append(shape)
        scene = pack(w)
        kind = int(scene.kind[0])
        ts, _, _ = H.prim_slots(scene, 0, kind, batch, 1e-4)  # type: ignore[arg-type]
        assert len(ts) == SLOTS[kind]
        met = 0
        for k, r in enumerate(rays):
            expected = sorted(i.t for i in intersect(shape, r))
            got = sorted(float(t[k]) for t in ts if t[k] < math.inf)
            assert got == expected, f"{type(shape).__name__}, ray {k}"
            met += bool(expected)
        assert met > 10, f"{type(shape).__name__}: too few rays meet it to prove anything"


@pytest.mark.parametrize("far", [0, 20], ids=["direct", "hierarchy"])
def test_n1_and_n2_are_the_references_along_every_hit(far: int) -> None:
    """Chapter 11's three overlapping glass spheres, and rays from many directions through
    them: every hit's n1 and n2 as ``prepare_computations`` finds them; with ``far`` small
    spheres far away, the spheres are reached through the hierarchy."""
    api = NAIVE
    a, b, c = (api["glass_sphere"]() for _ in range(3))
    api["set_transform"](a, api["scaling"](2, 2, 2))
    api["set_transform"](b, api["translation"](0, 0, -0.25))
    api["set_transform"](c, api["translation"](0, 0, 0.25))
    for s, index in ((a, 1.5), (b, 2.0), (c, 2.5)):
        s.material = replace(s.material, refractive_index=index)
    w = api["world"]()
    w.objects.extend([a, b, c])
    for k in range(far):
        speck = api["sphere"]()
        api["set_transform"](speck, api["translation"](50 + k, 50, 50))
        w.objects.append(speck)
    idx = H.index(pack(w))
    assert (idx.hierarchy is not None) == bool(far)
    rng = random.Random(3)
    rays = [ray(api["point"](0, 0, -4), api["vector"](0, 0, 1))]
    for _ in range(60):
        o = api["point"](*(rng.uniform(-3, 3) for _ in range(3)))
        rays.append(ray(o, api["point"](*(rng.uniform(-0.5, 0.5) for _ in range(3))) - o))
    checked = 0
    for r in rays:
        xs = TRACER.intersect_world(w, r)
        batch = tuple(
            np.array([getattr(getattr(r, part), axis)] * len(xs), dtype=np.float64)
            for part in ("origin", "direction")
            for axis in "xyz"
        )
        with np.errstate(all="ignore"):
            rec = H.records(idx, batch, 1e-4, 64)  # type: ignore[arg-type]
        prims = {id(s): k for k, s in enumerate(idx.scene.shapes)}
        hit = H.Nearest(
            np.array([i.t for i in xs]),
            np.array([prims[id(i.object)] for i in xs]),
            np.array([_slot(rec, prims[id(i.object)], i.t) for i in xs]),
            np.zeros(len(xs)),
            np.zeros(len(xs)),
        )
        with np.errstate(all="ignore"):  # as in a render: IEEE infinities are expected
            n1, n2 = refractive_indices(idx, batch, hit, 1e-4, 64)  # type: ignore[arg-type]
        for k, i in enumerate(xs):
            comps = prepare_computations(intersection(i.t, i.object), r, xs)
            assert (n1[k], n2[k]) == (comps.n1, comps.n2)
            checked += 1
    assert checked > 100


def _slot(rec: H.Records, prim: int, t: float) -> int:
    found = np.flatnonzero((rec.ray == 0) & (rec.prim == prim) & (rec.t == t))
    return int(rec.slot[found[0]])


def test_intersect_world_lists_what_the_reference_lists() -> None:
    tracer = WavefrontTracer()
    rng = random.Random(11)
    _, w = lit_scene(load_variant("naive"), 1)
    checked = 0
    for _ in range(80):
        o = NAIVE["point"](*(rng.uniform(-3, 3) for _ in range(2)), -4)
        r = ray(o, NAIVE["point"](rng.uniform(-2, 2), rng.uniform(0, 2), 0) - o)
        expected = TRACER.intersect_world(w, r)
        got = tracer.intersect_world(w, r)
        # the same objects in the same order; t the same but for the last bits of shapes
        # inside transformed groups (their transforms are composed once)
        assert [id(i.object) for i in got] == [id(i.object) for i in expected]
        assert [i.t for i in got] == pytest.approx([i.t for i in expected], rel=1e-12)
        checked += len(expected)
    assert checked > 50


# ------------------------------------------------------------------------ whole pictures


@pytest.mark.parametrize("name", ["csg.yml", "shapes.yml", "cpp-spheres.yml"])
def test_the_scene_files_render_as_the_reference(name: str) -> None:
    _same_picture("wavefront", scene_file(name, 12, 9))


def test_a_world_with_everything_renders_as_the_reference() -> None:
    """Three lights, nested glass, patterns, groups, CSG, a smooth triangle, a cone and
    enough spheres for the hierarchy; two samples per pixel."""
    assert H.index(pack(lit_scene(load_variant("naive"), 3, 24)[1])).hierarchy is not None
    _same_picture("wavefront", lambda v: lit_scene(v, 3, 24), RenderSettings(samples=2, seed=9))


def test_max_mb_and_threads_cut_the_work_but_change_no_bit() -> None:
    build = lambda v: lit_scene(v, 2, 20)  # noqa: E731
    settings = RenderSettings(samples=3, seed=4)
    first = _pixels("wavefront", build, settings)
    for name in ("wavefront[max_mb=1]", "wavefront[max_mb=1,threads=2]", "wavefront[threads=2]"):
        assert np.array_equal(_pixels(name, build, settings), first), name


def test_threaded_passes_hand_the_gil_over_quickly_and_give_the_interval_back(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """While passes run on two threads the switch interval is at most ``INTERVAL``; after,
    the program's own value is back, also when two renders overlap (the last one out puts it
    back) and when the program's value is already shorter (never raised)."""
    seen: list[float] = []
    real = wave_module.render_block

    def watched(*args: Any) -> Any:
        seen.append(sys.getswitchinterval())
        return real(*args)

    monkeypatch.setattr(tracer_module, "render_block", watched)
    before = sys.getswitchinterval()
    try:
        sys.setswitchinterval(0.003)
        _pixels("wavefront[max_mb=1,threads=2]", lambda v: lit_scene(v, 1, 8), RenderSettings())
        assert len(seen) >= 2 and max(seen) <= handoff.INTERVAL
        assert sys.getswitchinterval() == pytest.approx(0.003, abs=1e-5)
        with handoff.quick_handoffs():
            with handoff.quick_handoffs():
                assert sys.getswitchinterval() == pytest.approx(handoff.INTERVAL, abs=1e-5)
            assert sys.getswitchinterval() == pytest.approx(handoff.INTERVAL, abs=1e-5)
        assert sys.getswitchinterval() == pytest.approx(0.003, abs=1e-5)
        sys.setswitchinterval(handoff.INTERVAL / 2)
        with handoff.quick_handoffs():
            assert sys.getswitchinterval() == pytest.approx(handoff.INTERVAL / 2, abs=1e-5)
    finally:
        sys.setswitchinterval(before)


@pytest.mark.parametrize(
    ("pixels", "samples", "cap", "threads", "passes"),
    [(307_200, 1, 131_072, 1, 3), (307_200, 1, 65_536, 2, 6), (307_200, 1, 65_536, 3, 6),
     (100, 4, 64, 2, 8), (5, 1, 64, 4, 4), (3, 1, 64, 4, 3), (2, 200, 64, 2, 2)],
)  # fmt: skip
def test_passes_are_equal_and_a_multiple_of_the_threads(
    pixels: int, samples: int, cap: int, threads: int, passes: int
) -> None:
    """Threads taking the passes in turn end together: as many passes as the cap needs,
    rounded up to a multiple of the threads (never more passes than pixels), each within a
    pixel of the others, every pixel in exactly one, none over the cap (a pixel alone may
    hold more samples: its pass traces them a cap at a time)."""
    got = list(blocks(pixels, samples, cap, threads))
    assert len(got) == passes
    assert got[0][0] == 0 and got[-1][1] == pixels
    assert all(a[1] == b[0] for a, b in itertools.pairwise(got))
    sizes = [end - first for first, end in got]
    assert max(sizes) - min(sizes) <= 1
    assert all(size * samples <= cap or size == 1 for size in sizes)


def test_float32_stays_within_its_tolerance() -> None:
    build = lambda v: lit_scene(v, 2, 20)  # noqa: E731
    variant = load_variant("wavefront[float32]")
    got = _pixels(variant.name, build)
    expected = _pixels("cached", build)
    difference = np.abs(np.clip(got, 0, 1) - np.clip(expected, 0, 1))
    assert difference.max() <= variant.tolerance
    assert difference.mean() < 1e-3


def test_a_pass_stays_within_max_mb() -> None:
    """At max_mb=2 the arrays a render allocates besides its canvas stay under 2 MiB (a
    bigger budget lets them grow: the pass is what max_mb bounds). A first render warms up
    what NumPy loads on first use. At 64x48 and 4 samples a pass of the whole frame takes
    about 8.4 MiB (0.8 at max_mb=2): a budget ignored, or three times what it says, takes
    over 2 MiB (2.3 MiB; 2.5 at 96x72), at half 96x72's CPU seconds under tracemalloc."""
    peaks = {}
    for mb in (2, 64):
        variant = load_variant(f"wavefront[max_mb={mb}]")
        camera, world = lit_scene(variant, 2, 20)
        tracer = variant.tracer
        tracer.render(camera, world, RenderSettings(samples=2))
        camera = replace(camera, hsize=64, vsize=48)
        image = tracer.new_canvas(camera)
        tracemalloc.start()
        tracer.render_into(image, camera, world, RenderSettings(samples=4, seed=1))
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        tracer.forget()
        peaks[mb] = peak
    assert peaks[2] < 2 * 2**20
    assert peaks[64] > 2 * peaks[2]


@pytest.mark.parametrize("name", ["wavefront[max_mb=2]", "wavefront[float32,max_mb=2]"])
def test_a_pass_of_a_csg_scene_stays_within_max_mb(name: str) -> None:
    """CSG trees keep more per ray (every intersection of a tree's primitives until its rules
    pick): budgeted at the reference scene's bytes per ray, these passes took 2.27 and 2.79
    MiB of a 2 MiB budget (64x48, 4 samples)."""
    variant = load_variant(name)
    found = load_scene(SCENES / "csg.yml", variant.api, variant=variant.name)
    scene = found.resized(64, 48)
    camera, world = scene.camera, variant.world_for(scene)
    tracer = variant.tracer
    tracer.render(camera, world, RenderSettings(samples=1))  # NumPy's first-use loads
    image = tracer.new_canvas(camera)
    tracemalloc.start()
    tracer.render_into(image, camera, world, RenderSettings(samples=4, seed=1))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 2 * 2**20


def test_render_region_gives_the_pixels_of_render() -> None:
    variant = load_variant("wavefront")
    camera, world = lit_scene(variant, 1)
    settings = RenderSettings(samples=2, seed=3)
    whole = _pixels("wavefront", lambda v: (camera, world), settings)
    tracer = variant.tracer
    values = np.array(tracer.render_region(camera, world, settings, (3, 2, 11, 7)))
    tile = values.reshape(5, 8, 3).astype(np.float32)
    assert np.array_equal(tile, whole[2:7, 3:11].astype(np.float32))


# ------------------------------------------------------------------------ refusals, options


def test_what_the_passes_do_not_vectorize_is_refused_by_name() -> None:
    api = load_variant("wavefront").api
    camera, world = lit_scene(load_variant("wavefront"), 1)
    lamp = api["area_light"](
        api["point"](-1, 4, -1), api["vector"](2, 0, 0), 2, api["vector"](0, 0, 2), 2,
        api["color"](1, 1, 1),
    )  # fmt: skip
    soft = replace(world, lights=[lamp])
    with pytest.raises(Unsupported, match=r"light 0 of the world is an AreaLight"):
        api["render"](camera, soft, RenderSettings())
    mapped = replace(world, objects=list(world.objects))
    floor = mapped.objects[0]
    checkers = api["uv_checkers"](2, 2, api["color"](0, 0, 0), api["color"](1, 1, 1))
    floor.material = material(pattern=api["texture_map"](checkers, api["planar_map"]))
    with pytest.raises(Unsupported, match=r"world object 0 \(a Plane\) is a TextureMap"):
        api["render"](camera, mapped, RenderSettings())

    class Odd(Sphere):
        def local_intersect(self, local_ray: Any) -> list[Any]:
            return []

    odd = replace(world, objects=[Odd()])
    with pytest.raises(Unsupported, match=r"world object 0 \(an Odd\) is an Odd, which changes"):
        api["render"](camera, odd, RenderSettings())


def test_the_books_steps_answer_worlds_the_passes_refuse() -> None:
    """``color_at`` of a world with an area light is the reference's (which asks this
    tracer's ``is_shadowed``); ``is_shadowed`` needs no lights at all."""
    variant = load_variant("wavefront")
    api = variant.api
    _, world = lit_scene(variant, 1)
    lamp = api["area_light"](
        api["point"](-1, 4, -1), api["vector"](2, 0, 0), 2, api["vector"](0, 0, 2), 2,
        api["color"](1, 1, 1),
    )  # fmt: skip
    soft = replace(world, lights=[lamp])
    r = ray(api["point"](0, 1.5, -5), api["vector"](0, -0.2, 1))
    assert api["color_at"](soft, r) == NAIVE["color_at"](soft, r)
    p = api["point"](-1, 0.01, 0)
    answers = set()
    for light in ((-1, 5, 0), (-4, 0.5, -4), (1.2, 3, 1), (0, 0.5, -6)):
        shadowed = api["is_shadowed"](soft, api["point"](*light), p)
        assert shadowed is NAIVE["is_shadowed"](soft, api["point"](*light), p)
        answers.add(shadowed)
    assert answers == {True, False}


def test_options_and_names() -> None:
    assert load_variant("wavefront[threads=1,max_mb=256]").name == "wavefront"
    variant = load_variant("wavefront[threads=2, float32, max_mb=64]")
    assert variant.name == "wavefront[float32,max_mb=64,threads=2]"
    assert variant.tracer.options.cap() < load_variant("wavefront").tracer.options.cap()
    for bad, message in (
        ("wavefront[max_mb=0]", "max_mb"),
        ("wavefront[gpu]", "no option 'gpu'"),
        ("wavefront[threads=x]", "threads"),
        ("wavefront:naive", "does not wrap"),
    ):
        with pytest.raises(VariantError, match=message):
            load_variant(bad)


# ------------------------------------------------------------------------ the bench section


def test_with_max_mb_and_the_knee() -> None:
    assert pass_size.with_max_mb("wavefront", 64) == "wavefront[max_mb=64]"
    spelled = pass_size.with_max_mb("wavefront[float32,max_mb=8]", 16)
    assert load_variant(spelled).name == "wavefront[float32,max_mb=16]"
    points = [
        {"max_mb": mb, "render_median": seconds}
        for mb, seconds in ((16, 3.0), (64, 1.05), (256, 1.0), (1024, 1.02))
    ]
    bend = pass_size_report.knee(points)
    assert bend is not None and bend["max_mb"] == 64


def test_the_pass_size_section_measures_every_max_mb(tmp_path: Path) -> None:
    scene = SceneRef("reference", SCENES / "reference.yml")
    plan = pass_size.Plan(
        variant="wavefront", scene=scene, size=Size(48, 36), samples=2, repeat=1,
        max_mb=(1, 4), big=(Size(32, 24), 2),
    )  # fmt: skip
    saved: list[str] = []

    def save(_: Any, name: str) -> str:
        saved.append(name)
        return f"run/{name}"

    entries = pass_size.run(plan, tmp_path / "jobs", lambda _: None, save)
    assert len(entries) == 1 and entries[0]["status"] == "ok", entries
    small, large, big = entries[0]["points"]
    for point in (small, large, big):
        assert "error" not in point, point
        assert point["render_median"] > 0 and point["tracemalloc_peak"] > 0
    assert (small["batch"], large["batch"]) == (512, 2048)
    assert small["passes"] > large["passes"] >= 1
    assert large["difference"]["max_abs"] == 0  # max_mb never changes the picture
    assert big["big"] and big["size"] == [32, 24] and big["rss_growth"] >= 0
    assert saved == ["pass-size-reference.png"]
    run = {
        "series": entries,
        "settings": {"depth": 5, "repeat": 1, "threads": None},
        "machine": {"cpu_model": "cpu", "cores_available": 2, "python": "3.11"},
    }
    blocks = pass_size_report.blocks(run, None, "context")
    assert any(isinstance(b, Table) and len(b.rows) == 2 for b in blocks)
    assert any("knee" in getattr(b, "text", "") for b in blocks)
    assert len(pass_size_report.console_lines(run)) == 3
    path = pass_size_plot.plot(run, tmp_path / "plot.png")
    assert path is not None and path.stat().st_size > 1000
