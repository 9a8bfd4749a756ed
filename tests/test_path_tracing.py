"""The path integrator (chapter 21 here, beyond the book) through the variants: every Python
variant path-traces through the reference ``Tracer``'s steps over its own hit-finding code
and draws the same picture as ``naive`` for the same seed, whatever its worker count or tile
split (the random numbers are a pure function of the sample, not of who traces it); numba's
compiled path integrator draws the same picture to rounding, on one thread or two
(wavefront's passes: ``tests/test_wavefront_path.py``); the white furnace is the sky in every
pixel through each; and the book's pictures are unchanged by a sky.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import pytest

from raytracer.camera import RenderSettings
from scene import load_scene, load_scene_text
from variants.numba.api import NumbaTracer
from variants.numba.features import analyse
from variants.numba.render import prepare_frame
from variants.numba.specialize import library_path
from variants.registry import load_variant

SCENES = Path(__file__).resolve().parent.parent / "scenes"
FURNACE = SCENES / "furnace.yml"
CPP_SPHERES = SCENES / "cpp-spheres.yml"

# every lobe, both kinds of light, emission, a gradient sky, a pattern and roulette, at
# 10x8 pixels
SMALL_SCENE = """
- add: camera
  width: 10
  height: 8
  field-of-view: 1.1
  from: [0, 1.5, -5]
  to: [0, 0.6, 0]
  up: [0, 1, 0]
- add: light
  at: [-4, 6, -3]
  intensity: [0.7, 0.7, 0.7]
- add: area_light
  corner: [2, 4, -2]
  uvec: [1, 0, 0]
  usteps: 2
  vvec: [0, 0, 1]
  vsteps: 2
  intensity: [0.5, 0.45, 0.4]
- add: sky
  horizon: [0.9, 0.9, 1]
  zenith: [0.3, 0.5, 0.9]
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[0.9, 0.9, 0.9], [0.2, 0.3, 0.2]]
    reflective: 0.2
- add: sphere
  transform: [[translate, -1.2, 1, 0.5]]
  material: {reflective: 1}
- add: sphere
  transform: [[scale, 0.7, 0.7, 0.7], [translate, 0.6, 0.7, -0.8]]
  material: {transparency: 0.9, reflective: 0.1, refractive-index: 1.5, color: [0, 0, 0]}
- add: cube
  transform: [[scale, 0.4, 0.4, 0.4], [translate, 1.8, 0.4, 0.8]]
  material: {color: [0.8, 0.3, 0.2], diffuse: 0.9}
- add: sphere
  transform: [[scale, 0.2, 0.2, 0.2], [translate, -0.2, 0.2, -1.6]]
  material: {color: [0, 0, 0], emissive: [3, 2, 1]}
"""
SMALL_SETTINGS = RenderSettings(integrator="path", samples=2, depth=4, seed=5, roulette=2)

SAME_AS_NAIVE = (
    "cached",
    "prealloc",
    "pooled[workers=2]:cached",
    "pooled[granularity=pixel,workers=2]:naive",
    "pooled[granularity=tile,tile=3,workers=2]:prealloc",
    "dask[workers=2,tile=4]:cached",
)
PYTHON_VARIANTS = ("naive", "robust", *SAME_AS_NAIVE)


def _pixels(image: Any) -> list[tuple[float, float, float]]:
    return [(p.red, p.green, p.blue) for p in image.pixels]


def _render_file(name: str, path: Path, width: int, height: int) -> list[tuple[float, ...]]:
    variant = load_variant(name)
    scene = load_scene(path, variant.api).resized(width, height)
    settings = RenderSettings(**scene.render)
    return _pixels(variant.api["render"](scene.camera, variant.world_for(scene), settings))


def _render_small(name: str, settings: RenderSettings = SMALL_SETTINGS) -> list[tuple[float, ...]]:
    variant = load_variant(name)
    scene = load_scene_text(SMALL_SCENE, variant.api, path="small.yml")
    return _pixels(variant.api["render"](scene.camera, variant.world_for(scene), settings))


def _worst(pixels: list[tuple[float, ...]], others: list[tuple[float, ...]]) -> float:
    pairs = zip(pixels, others, strict=True)
    return max(abs(a - b) for p, q in pairs for a, b in zip(p, q, strict=True))


@pytest.fixture(scope="module")
def naive_small() -> list[tuple[float, ...]]:
    pixels = _render_small("naive")
    # the picture is not trivial: lit, varied, nothing missing
    assert len(set(pixels)) > len(pixels) // 2
    assert all(0 <= channel < 100 for pixel in pixels for channel in pixel)
    return pixels


@pytest.mark.parametrize("name", [*PYTHON_VARIANTS, "numba", "numba[threads=2]"])
def test_the_white_furnace_is_the_sky_in_every_pixel(name: str) -> None:
    # a sphere of albedo 1 under a uniform sky of 0.5: every path returns 0.5 (4 samples
    # sum to 2.0 exactly, times 1/4)
    pixels = _render_file(name, FURNACE, 12, 10)
    assert set(pixels) == {(0.5, 0.5, 0.5)}


@pytest.mark.parametrize("name", SAME_AS_NAIVE)
def test_every_python_variant_and_split_draws_naives_path_traced_picture(
    name: str, naive_small: list[tuple[float, ...]]
) -> None:
    assert _render_small(name) == naive_small


def test_robust_path_traces_with_its_own_offsets(naive_small: list[tuple[float, ...]]) -> None:
    # robust moves points off surfaces by its own offsets: the same paths, to rounding
    pixels = _render_small("robust")
    pairs = zip(pixels, naive_small, strict=True)
    worst = max(abs(a - b) for p, q in pairs for a, b in zip(p, q, strict=True))
    assert worst <= load_variant("robust").tolerance


def test_another_seed_draws_another_picture(naive_small: list[tuple[float, ...]]) -> None:
    variant = load_variant("naive")
    scene = load_scene_text(SMALL_SCENE, variant.api, path="small.yml")
    other = RenderSettings(integrator="path", samples=2, depth=4, seed=6, roulette=2)
    pixels = _pixels(variant.api["render"](scene.camera, variant.world_for(scene), other))
    assert sum(p != q for p, q in zip(pixels, naive_small, strict=True)) > len(pixels) // 2


@pytest.mark.parametrize("roulette", [SMALL_SETTINGS.roulette, 0], ids=["roulette", "no-roulette"])
def test_numba_path_traces_cacheds_picture_to_rounding_on_one_thread_or_two(
    roulette: int, naive_small: list[tuple[float, ...]]
) -> None:
    # the small scene has every lobe, both kinds of light, emission and a gradient sky;
    # the kernels' sums run in another order and their hits round differently: the same
    # paths, to rounding
    settings = dataclasses.replace(SMALL_SETTINGS, roulette=roulette)
    reference = naive_small if roulette else _render_small("cached", settings)
    one = _render_small("numba[threads=1]", settings)
    assert _worst(one, reference) <= load_variant("numba").tolerance
    assert _render_small("numba[threads=2]", settings) == one  # who traces changes nothing
    assert _render_small("pooled[granularity=tile,tile=3,workers=2]:numba", settings) == one


def test_roulette_changes_numbas_picture(naive_small: list[tuple[float, ...]]) -> None:
    # the two settings above draw different pictures: roulette is not ignored
    off = _render_small("numba[threads=1]", dataclasses.replace(SMALL_SETTINGS, roulette=0))
    assert _worst(off, naive_small) > 1e-3


def test_a_whitted_render_through_numba_compiles_no_path_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("RTC_NUMBA_SPECIALIZE", "on")  # the gate's renders share the generic one
    variant = load_variant("numba")
    scene = load_scene(FURNACE, variant.api).resized(4, 4)
    world = variant.world_for(scene)
    assert isinstance(variant.tracer, NumbaTracer)
    options = variant.tracer.options
    whitted = prepare_frame(options, scene.camera, world, RenderSettings())
    path = prepare_frame(options, scene.camera, world, RenderSettings(integrator="path"))
    features = analyse(world)
    assert "HAS_PATH" not in features.flags
    assert str(library_path(options.config(features))) in whitted.renderer.origin
    assert str(library_path(options.config(features.with_path()))) in path.renderer.origin
    assert whitted.renderer.origin != path.renderer.origin


@pytest.mark.slow
def test_a_sky_leaves_the_books_picture_unchanged() -> None:
    """At 8x6 (a quarter of 16x12's CPU seconds): a Whitted render that let the sky into
    its misses differs at 44 of the 48 pixels, one that let it into reflected and refracted
    rays only at 28."""
    variant = load_variant("naive")
    scene = load_scene(CPP_SPHERES, variant.api).resized(8, 6)
    assert scene.sky is not None
    world = variant.world_for(scene)
    settings = RenderSettings(samples=2)
    with_sky = _pixels(variant.api["render"](scene.camera, world, settings))
    world.sky = None
    without = _pixels(variant.api["render"](scene.camera, world, settings))
    assert with_sky == without
    assert any(pixel != (0.0, 0.0, 0.0) for pixel in with_sky)
    assert (0.0, 0.0, 0.0) in with_sky  # the book's black background, where the sky is
