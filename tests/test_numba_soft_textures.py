"""The numba variant with the other two bonus chapters (issue 15): area lights (soft
shadows, their cells jittered at random or placed by a sequence) and texture maps
(spherical, planar, cylindrical and cube mappings; checkers, align check and image uv
patterns) drawn as ``naive`` draws them; the light jitter bit for bit; the book's steps in
their new forms; specialization leaving both out of scenes that lack them; refusals.

Pictures are compared with ``naive`` as ``test_numba`` does (float64: no pixel more than
``FLOAT64_WORST`` away, none by 1/255). The scenes are the project's own
(``scenes/soft-shadows.yml``, ``textures.yml``), at a few pixels, and the soft
shadows one with its light rewritten (fewer cells, jitter off, a sequence), since naive
casts a shadow ray per cell of the light at every point it shades.
"""

from __future__ import annotations

import math
import random
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from reference_pixels import checkerboard, lattice, naive_at, picture_at

from harness.instruments.raycount import count_rays
from raytracer.camera import RenderSettings
from raytracer.colors import Color
from raytracer.materials import material
from raytracer.sampling import light_jitter, sample_key
from raytracer.textures.uv_patterns import UVCheckers
from raytracer.tuples import Tuple
from scene import load_scene
from variants.numba import layout as L
from variants.numba.errors import PackError
from variants.numba.features import analyse
from variants.numba.pack import pack_world
from variants.numba.render import Options
from variants.numba.specialize import load_kernels, module_source
from variants.registry import load_variant

SCENES = Path(__file__).resolve().parent.parent / "scenes"
FLOAT64_WORST = 1e-6
ONE_STEP = 1.0 / 255.0
SOFT = {"HAS_AREA_LIGHTS", "HAS_JITTER"}
TEXTURES = {"HAS_TEXTURE_MAP", "HAS_CUBE_MAP", "HAS_UV_IMAGE"}


def soft_shadows(
    api: Any,
    size: tuple[int, int],
    cells: int | None = None,
    jitter: bool = True,
    sequence: tuple[float, ...] | None = None,
    start: int = 0,
) -> tuple[Any, Any]:
    """``soft-shadows.yml`` at ``size``; its light (8x8 cells, jittered) rewritten to
    ``cells`` x ``cells`` over the same square when given, jittered or not, with
    ``sequence`` as its ``jitter_by`` when given, moved on by ``start`` values."""
    scene = load_scene(SCENES / "soft-shadows.yml", api).resized(*size)
    light = scene.world.lights[0]
    if cells is not None:
        light = api["area_light"](
            light.corner, light.uvec * light.usteps, cells, light.vvec * light.vsteps, cells,
            light.intensity,
        )  # fmt: skip
    light = replace(light, jitter=jitter)
    if sequence is not None:
        light = replace(light, jitter_by=api["sequence"](*sequence))
    for _ in range(start):
        api["next"](light.jitter_by)
    scene.world.lights[0] = light
    return scene.camera, scene.world


def textures(api: Any, size: tuple[int, int]) -> tuple[Any, Any]:
    scene = load_scene(SCENES / "textures.yml", api).resized(*size)
    return scene.camera, scene.world


def _pixels(name: str, build: Any, settings: RenderSettings) -> np.ndarray:
    variant = load_variant(name)
    camera, world = build(variant.api)
    image = variant.api["render"](camera, world, settings)
    at = variant.api["pixel_at"]
    return np.array(
        [[(q.red, q.green, q.blue) for q in (at(image, x, y) for x in range(image.width))]
         for y in range(image.height)]
    )  # fmt: skip


PICTURES = {
    # the scene as written: 8x8 cells, jittered at random per sample
    "soft-as-written": (lambda api: soft_shadows(api, (12, 9)), RenderSettings()),
    # 3x3 cells at their centres (the chapter's default sequence(0.5))
    "soft-3x3-centres": (
        lambda api: soft_shadows(api, (16, 12), cells=3, jitter=False),
        RenderSettings(),
    ),
    # 2x2 cells jittered, three samples per pixel (every sample its own points)
    "soft-2x2-jittered-3spp": (
        lambda api: soft_shadows(api, (14, 10), cells=2),
        RenderSettings(samples=3, seed=5),
    ),
    # 2x2 cells placed by a sequence of 4 values (dividing the 8 a point takes), which
    # stands at its third value when the render starts
    "soft-2x2-sequence": (
        lambda api: soft_shadows(
            api, (16, 12), cells=2, jitter=False, sequence=(0.2, 0.9, 0.65, 0.35), start=2
        ),
        RenderSettings(),
    ),
    "textures": (lambda api: textures(api, (48, 36)), RenderSettings()),
}


# naive draws these pictures at some of their pixels (tests/reference_pixels.py), numba's
# whole picture is compared there: the 8x8 cells' shadow rays cost naive about 0.2 CPU s
# a pixel (half the pixels, a checkerboard), the 48x36 textures' 1,728 pixels about 15 s (a
# quarter, every other one of every other row); the others whole (a sequence's light moves
# on from pixel to pixel: a pixel drawn alone is not the picture's)
NAIVE_AT = {"soft-as-written": checkerboard, "textures": lattice}


@pytest.mark.slow
@pytest.mark.parametrize("picture", list(PICTURES))
def test_numba_draws_what_naive_draws(picture: str) -> None:
    build, settings = PICTURES[picture]
    numba = _pixels("numba", build, settings)
    height, width = numba.shape[:2]
    choose = NAIVE_AT.get(picture)
    if choose is None:
        expected = _pixels("naive", build, settings).reshape(-1, 3)
        got = numba.reshape(-1, 3)
    else:
        pixels = choose(width, height)
        expected, got = naive_at(build, settings, pixels), picture_at(numba, pixels)
    expected, got = np.clip(expected, 0, 1), np.clip(got, 0, 1)
    difference = np.abs(got - expected)
    print(f"{picture}: max difference {difference.max():.3g} over {len(expected)} pixels")
    assert difference.max() <= FLOAT64_WORST
    assert int((difference.max(axis=1) > ONE_STEP).sum()) == 0
    assert len({tuple(np.round(q, 3)) for q in expected}) > 30, "a real picture"


@pytest.mark.usefixtures("specialized_kernels")
def test_the_generic_kernel_draws_what_the_specialized_one_draws() -> None:
    for picture in ("soft-2x2-jittered-3spp", "textures"):
        build, settings = PICTURES[picture]
        generic = _pixels("numba[specialize=off]", build, settings)
        assert np.array_equal(generic, _pixels("numba", build, settings)), picture


def test_the_light_jitter_is_the_reference_s_bit_for_bit() -> None:
    """The kernels' ``light_jitter`` (uint64 arithmetic) against
    ``raytracer.sampling.light_jitter`` (Python integers) for many samples, lights and
    cells, the extremes included."""
    rng = random.Random(15)
    rows = [
        (0, 0, 0, 0, 0, 0, 0),
        (2**64 - 1, 16383, 16383, 2**20 - 1, 2**31 - 1, 65535, 65535),
    ]
    for _ in range(5000):
        rows.append(
            (
                rng.choice([0, 1, 42, rng.getrandbits(64)]),
                rng.randrange(16384), rng.randrange(16384), rng.randrange(2**20),
                rng.choice([0, 1, 2, rng.randrange(2**31)]),
                rng.randrange(65536), rng.randrange(65536),
            )
        )  # fmt: skip
    kernels = load_kernels(Options().generic())
    keys = np.array([sample_key(*row[:4]) for row in rows], dtype=np.uint64)
    lights, us, vs = (np.array([row[j] for row in rows], dtype=np.int64) for j in (4, 5, 6))
    got = kernels.api_light_jitter(keys, lights, us, vs)
    expected = np.array([light_jitter(*row) for row in rows])
    assert got.shape == (len(rows), 2)
    assert np.array_equal(got.view(np.uint64), expected.view(np.uint64))
    assert got.min() >= 0.0 and got.max() < 1.0 and got.std() > 0.2


def test_a_pixel_through_the_book_steps_is_the_render_s() -> None:
    """``pixel_color`` (the reference's loop: it sets the sample being traced) through
    numba's ``color_at`` sees the same jittered points as numba's render and naive's; so
    do ``color_at`` and ``shade_hit`` outside a render (the sample (0, 0, 0, 0))."""
    settings = RenderSettings(samples=2, seed=9)
    spots = ((5, 7), (9, 8), (12, 10))
    colors = {}
    for name in ("naive", "numba"):
        variant = load_variant(name)
        camera, world = soft_shadows(variant.api, (16, 12), cells=2)
        pixels = [variant.tracer.pixel_color(camera, world, x, y, settings) for x, y in spots]
        if name == "numba":
            image = variant.api["render"](camera, world, settings)
            rendered = [variant.api["pixel_at"](image, x, y) for x, y in spots]
            assert np.allclose(
                [(c.red, c.green, c.blue) for c in rendered],
                [(c.red, c.green, c.blue) for c in pixels],
                atol=1e-12,
                rtol=0,
            )
        variant.tracer.forget()
        r = variant.api["ray_for_pixel"](camera, 4.3, 7.1)  # in a penumbra
        xs = variant.api["intersect_world"](world, r)
        comps = variant.api["prepare_computations"](variant.api["hit"](xs), r, xs)
        pixels += [variant.api["color_at"](world, r), variant.api["shade_hit"](world, comps)]
        world.lights[0] = replace(world.lights[0], jitter=False)
        pixels.append(variant.api["color_at"](world, r))  # the cells' centres
        colors[name] = [(c.red, c.green, c.blue) for c in pixels]
    assert np.allclose(colors["numba"], colors["naive"], atol=1e-9, rtol=0)
    assert len(set(colors["naive"][:3])) == 3
    assert colors["naive"][3] == colors["naive"][4], "a matte surface: color_at is shade_hit"
    assert abs(colors["naive"][3][0] - colors["naive"][5][0]) > 0.1, "the jitter shows"


def _world_and_light(api: Any, values: tuple[float, ...]) -> tuple[Any, Any]:
    """The chapter's test world: the default world, a 2x2 light before it, its points
    placed by ``values``."""
    w = api["default_world"]()
    light = api["area_light"](
        api["point"](-0.5, -0.5, -5), api["vector"](1, 0, 0), 2, api["vector"](0, 1, 0), 2,
        api["color"](1, 1, 1),
    )  # fmt: skip
    return w, replace(light, jitter_by=api["sequence"](*values))


def test_intensity_at_and_lighting_take_the_sequence_as_the_reference_does() -> None:
    """One call takes 2 values per cell from where the sequence stands, whatever its
    length (here 5 and 3 values for 8 a call), and leaves it standing where the
    reference's does; a jittered light's ``jitter`` does not matter outside shade_hit."""
    results: dict[str, list[Any]] = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        out: list[Any] = []
        for values, jitter in (((0.7, 0.3, 0.9, 0.1, 0.5), False), ((0.25, 0.5, 0.75), True)):
            w, light = _world_and_light(api, values)
            light = replace(light, jitter=jitter)
            for q in ((0, 0, 2), (1, -1, 2), (1.5, 0, 2), (1.25, 1.25, 3), (0, 0, -2)):
                out.append(api["intensity_at"](light, api["point"](*q), w))
                out.append(light.jitter_by.position)
            m = material(color=api["color"](0.9, 0.4, 0.3), shininess=30)
            for spot in ((0.0, 0.0, -1.0), (0.3, 0.2, -0.9), (-0.6, 0.1, -0.7)):
                p = api["point"](*spot)
                n = api["vector"](*spot)
                for intensity in (1.0, 0.25, 0.0, True, False):
                    c = api["lighting"](
                        m, api["sphere"](), light, p, api["vector"](0, 0, -1), n, intensity,
                        ambient=intensity != 0.25,
                    )  # fmt: skip
                    out.append((c.red, c.green, c.blue))
                    out.append(light.jitter_by.position)
        results[name] = out
    assert len(results["numba"]) == len(results["naive"])
    for got, want in zip(results["numba"], results["naive"], strict=True):
        if isinstance(want, tuple):  # a color (numba leaves out specular terms below 1e-9)
            assert np.allclose(got, want, atol=1e-9, rtol=0)
        else:  # an intensity (a count of cells over their number) or where the sequence is
            assert got == want
    assert {0.0, 0.25, 0.75, 1.0} <= {v for v in results["naive"] if isinstance(v, float)}


def test_a_point_light_with_part_of_its_light() -> None:
    """``lighting``'s seventh argument as a fraction, with a point light: the diffuse and
    specular terms scaled by it, the ambient term not."""
    seen = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        light = api["point_light"](api["point"](-3, 4, -5), api["color"](1, 0.9, 0.8))
        m = material(color=api["color"](0.2, 0.6, 0.9), shininess=20)
        n = api["vector"](0, 0.6, -0.8)
        seen[name] = [
            api["lighting"](
                m,
                api["sphere"](),
                light,
                api["point"](0, 0, 0),
                api["vector"](0, 0, -1),
                n,
                fraction,
            )
            for fraction in (0.0, 0.3, 0.5, 1.0)
        ]
    for got, want in zip(seen["numba"], seen["naive"], strict=True):
        assert (got.red, got.green, got.blue) == pytest.approx(
            (want.red, want.green, want.blue), abs=1e-12
        )
    assert seen["naive"][1].red < seen["naive"][2].red < seen["naive"][3].red


def test_texture_patterns_at_points_as_the_reference_colors_them() -> None:
    """``pattern_at`` and ``pattern_at_shape`` of every texture pattern of ``textures.yml``
    (planar, spherical, cylindrical and cube maps; checkers, align check, two images) at
    random points and at the seams, faces' edges and poles."""
    rng = random.Random(3)
    points = [(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)) for _ in range(300)]
    points += [
        (0, 1, 0), (0, -1, 0), (0, 0, -1), (0, 0, 1), (1, 1, 1), (-1, -1, -1), (1, 0.3, -1),
        (0.5, 0.999999, 0.2), (-0.0, 0.5, -1), (0.25, 0.5, 0.0), (1, 1, -0.5), (-0.25, 0, 0),
    ]  # fmt: skip
    colors: dict[str, list[Any]] = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        _, world = textures(api, (4, 3))
        out = []
        for shape in world.objects:
            pattern = shape.material.pattern
            for q in points:
                p = api["point"](*q)
                for c in (
                    api["pattern_at"](pattern, p),
                    api["pattern_at_shape"](pattern, shape, p),
                ):
                    out.append((c.red, c.green, c.blue))
        colors[name] = out
    assert colors["numba"] == colors["naive"]
    assert len(set(colors["naive"])) > 25


class WavyCheckers(UVCheckers):
    """Checkers with a twist the kernels do not know."""

    __slots__ = ()

    def uv_color_at(self, u: float, v: float) -> Color:
        return super().uv_color_at(u + 0.1 * math.sin(v * 7), v)


def test_what_the_kernels_do_not_know_is_refused_by_name() -> None:
    api = load_variant("numba").api
    camera, world = soft_shadows(api, (4, 3), cells=2, jitter=False, sequence=(0.1, 0.2, 0.3))
    with pytest.raises(PackError, match=r"light 0 of the world \(an area light\) jitters by a "
                       r"sequence of 3 values, which does not divide the 8 values"):  # fmt: skip
        api["render"](camera, world)
    c = api["color"]
    checks = api["uv_checkers"](2, 2, c(1, 1, 1), c(0, 0, 0))

    def twisted(p: Tuple) -> tuple[float, float]:
        return p.x % 1.0, p.y % 1.0

    ball = api["sphere"]()
    ball.material = material(pattern=api["texture_map"](checks, twisted))
    with pytest.raises(PackError, match="maps points with twisted; the kernels know"):
        api["pattern_at_shape"](ball.material.pattern, ball, api["point"](0, 1, 0))
    wavy = WavyCheckers(2, 2, c(1, 1, 1), c(0, 0, 0))
    ball.material = material(pattern=api["cube_map"](checks, checks, checks, wavy, checks, checks))
    w = api["world"]()
    w.objects.append(ball)
    w.light = api["point_light"](api["point"](0, 5, -5), c(1, 1, 1))
    with pytest.raises(PackError, match=r"\(its back face\) is a WavyCheckers; the kernels know"):
        api["render"](camera, w)


@pytest.mark.usefixtures("specialized_kernels")
def test_a_scene_without_them_compiles_kernels_without_them() -> None:
    """Specialization: the reference scene's kernel has no area-light, jitter or texture
    code; the soft shadows and texture scenes' kernels have what they use, and
    ``explain`` lists it."""
    api = load_variant("naive").api
    reference = load_scene(SCENES / "reference.yml", api).world
    plain = analyse(pack_world(reference))
    assert not plain.flags & (SOFT | TEXTURES)
    source = module_source(Options().config(plain))
    assert "HAS_AREA_LIGHTS = False" in source and "HAS_TEXTURE_MAP = False" in source
    _, soft = soft_shadows(api, (4, 3))
    assert analyse(pack_world(soft)).flags & (SOFT | TEXTURES) == SOFT
    _, centres = soft_shadows(api, (4, 3), cells=3, jitter=False)
    assert analyse(pack_world(centres)).flags & (SOFT | TEXTURES) == {"HAS_AREA_LIGHTS"}
    _, textured = textures(api, (4, 3))
    assert analyse(pack_world(textured)).flags & (SOFT | TEXTURES) == TEXTURES
    numba = load_variant("numba").tracer
    assert "left out: " in numba.explain(reference)
    assert "area_lights, jitter" in numba.explain(reference)
    told = numba.explain(soft)
    assert "shading: shadows, area lights (a shadow ray per cell), jittered area lights" in told
    assert "light 0: an area light of 8x8 = 64 cells, jittered at random per sample" in told
    told = numba.explain(textured)
    assert "patterns: texture_map, cube_map, image textures" in told
    assert "uv patterns: uv_checkers, uv_align_check, uv_image; 2 images, 4,096 pixels" in told


def test_the_light_table_and_the_texture_records() -> None:
    api = load_variant("naive").api
    _, world = soft_shadows(api, (4, 3), cells=2, jitter=False, sequence=(0.2, 0.9))
    world.lights.append(api["point_light"](api["point"](1, 2, 3), api["color"](1, 1, 1)))
    packed = pack_world(world)
    area, point = packed.lights
    assert area[L.LIGHT_USTEPS] == area[L.LIGHT_VSTEPS] == 2 and area[L.LIGHT_JITTER] == 0
    assert area[L.LIGHT_UVEC : L.LIGHT_UVEC + 3].tolist() == [1.25, 0.0, 0.0]
    assert packed.light_values.tolist() == [0.2, 0.9] and area[L.LIGHT_SEQ_N] == 2
    assert point[L.LIGHT_USTEPS] == 0 and point[0:3].tolist() == [1, 2, 3]
    _, textured = textures(api, (4, 3))
    packed = pack_world(textured)
    ti, tf = packed.texture_table()
    kinds = packed.pi[:, L.PATTERN].tolist()
    assert sorted(kinds) == sorted([L.P_MAP] * 5 + [L.P_CUBE_MAP])
    images = 0
    for row, shape in enumerate(packed.shapes):
        uv = ti[packed.pi[row, L.PAT_TEX] + L.MAP_UV]
        if ti[uv + L.UV_KIND] != L.UV_IMAGE:
            continue
        images += 1
        pattern: Any = shape.material.pattern
        canvas = pattern.uv_pattern.canvas
        at, width, height = (int(ti[uv + j]) for j in (L.UV_AT, L.UV_WIDTH, L.UV_HEIGHT))
        assert (width, height) == (canvas.width, canvas.height)
        block = tf[at : at + width * height * 3]
        assert block.tolist() == [v for c in canvas.pixels for v in (c.red, c.green, c.blue)]
    assert images == 2


@pytest.mark.usefixtures("specialized_kernels")
def test_shadow_rays_are_counted_per_cell() -> None:
    """A shadow ray per cell of the light at every shaded point, as naive casts them (with a
    counting kernel of the scene's features: the area light's cells are counted in the same
    code in every kernel that has them, and no other test needs a generic counting one)."""
    settings = RenderSettings()
    counted = {}
    for name in ("naive", "numba"):
        variant = load_variant(name)
        camera, world = soft_shadows(variant.api, (10, 8), cells=2)
        found = count_rays(variant, camera, world, settings)
        assert found is not None
        counted[name] = found
    assert counted["numba"]["shadow"] == counted["naive"]["shadow"] > 4 * 10 * 8 // 2
