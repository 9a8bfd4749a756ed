"""The path integrator in wavefront's passes (chapter 21 here, beyond the book; issue 34).

Its pieces against the reference, bit for bit (the random numbers, the cosine-weighted
directions, the sky); whole pictures against ``naive``'s path-traced ones: at float64 to
the float32 canvas's rounding (``FLOAT64_WORST``), every lobe, both kinds of light,
emission, a sky, roulette on and off, the hierarchy, CSG and the closed box of
radius-1e5 walls; at float32 within the variant's tolerance; the white furnace exact;
and ``threads`` and ``max_mb`` changing how the work is cut, never a bit of the picture.
"""

from __future__ import annotations

import math
import tracemalloc
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_path_tracing import SMALL_SCENE, SMALL_SETTINGS
from test_wavefront import lit_scene

from raytracer.camera import RenderSettings
from raytracer.colors import color
from raytracer.sampling import path_random, sample_key
from raytracer.scatter import cosine_direction
from raytracer.sky import gradient_sky, sky_color
from raytracer.tuples import normalize, vector
from scene import load_scene, load_scene_text
from variants.registry import load_variant
from variants.wavefront.camera import path_numbers, sample_keys
from variants.wavefront.paths import cosine_directions, sky_colors
from variants.wavefront.scene import Unsupported

SCENES = Path(__file__).resolve().parents[1] / "scenes"
FLOAT64_WORST = 1e-6  # the float32 canvas's rounding is about 6e-8 of a channel near 1


def _pixels(image: Any) -> np.ndarray:
    return np.array([(p.red, p.green, p.blue) for p in image.pixels])


def _small(name: str, settings: RenderSettings = SMALL_SETTINGS) -> np.ndarray:
    variant = load_variant(name)
    scene = load_scene_text(SMALL_SCENE, variant.api, path="small.yml")
    return _pixels(variant.api["render"](scene.camera, variant.world_for(scene), settings))


def _file(name: str, file: str, width: int, height: int) -> np.ndarray:
    variant = load_variant(name)
    scene = load_scene(SCENES / file, variant.api).resized(width, height)
    settings = RenderSettings(**scene.render)
    return _pixels(variant.api["render"](scene.camera, variant.world_for(scene), settings))


def _worst(a: np.ndarray, b: np.ndarray) -> float:
    assert a.shape == b.shape
    return float(np.abs(a - b).max())


ROULETTE_OFF = replace(SMALL_SETTINGS, roulette=0)


@pytest.fixture(scope="module", params=[SMALL_SETTINGS, ROULETTE_OFF], ids=["roulette", "none"])
def small(request: pytest.FixtureRequest) -> tuple[RenderSettings, np.ndarray]:
    """naive's path-traced picture of the small scene (every lobe, a point and an area
    light, emission, a gradient sky, a pattern), with roulette from bounce 2 and without."""
    settings = request.param
    pixels = _small("naive", settings)
    assert len({tuple(p) for p in pixels}) > len(pixels) // 2  # lit, varied
    return settings, pixels


# ------------------------------------------------------------------------------ pieces


def test_the_random_numbers_are_the_references_bit_for_bit() -> None:
    xs, ys, ii = [0, 3, 9, 16383, 7], [0, 5, 2, 16383, 11], [0, 1, 7, 1048575, 3]
    pixels = list(zip(xs, ys, ii, strict=True))
    seed = 2**64 - 5
    keys = sample_keys(seed, np.array(xs), np.array(ys), np.array(ii))
    assert keys.tolist() == [sample_key(seed, *p) for p in pixels]
    for bounce, dimension in ((0, 0), (0, 4), (3, 1), (5, 7), (2**31 - 1, 2**32 - 1)):
        got = path_numbers(keys, bounce, dimension).tolist()
        assert got == [path_random(seed, *p, bounce, dimension) for p in pixels]


def test_cosine_directions_and_the_sky_are_the_references_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    normals = [normalize(vector(*v)) for v in rng.normal(size=(40, 3))]
    normals += [vector(0, 0, 1), vector(0, 0, -1), vector(0, 1, 0), vector(-1, 0, 0)]
    u1, u2 = rng.random(len(normals)), rng.random(len(normals))
    n = tuple(np.array([getattr(v, c) for v in normals]) for c in "xyz")
    got = np.array(cosine_directions(n, u1, u2)).T  # type: ignore[arg-type]
    for k, v in enumerate(normals):
        d = cosine_direction(v, float(u1[k]), float(u2[k]))
        assert got[k].tolist() == [d.x, d.y, d.z]
    sky = gradient_sky(color(0.9, 0.8, 1), color(0.2, 0.4, 0.9))
    table = np.array([[0.9, 0.8, 1], [0.2, 0.4, 0.9]])
    seen = np.array(sky_colors(table, n)).T  # type: ignore[arg-type]
    for k, v in enumerate(normals):
        c = sky_color(sky, v)
        assert seen[k].tolist() == [c.red, c.green, c.blue]


# ---------------------------------------------------------------------------- pictures


def test_wavefront_draws_naives_path_traced_picture(
    small: tuple[RenderSettings, np.ndarray],
) -> None:
    settings, naive = small
    assert _worst(_small("wavefront", settings), naive) <= FLOAT64_WORST


def test_threads_and_pass_sizes_draw_the_same_picture_bit_for_bit() -> None:
    whole = _small("wavefront")
    for name in ("wavefront[threads=2]", "wavefront[max_mb=1,threads=3]"):
        # max_mb=1 on 3 threads: passes of the least size, 64 rays, over 160 samples
        assert np.array_equal(_small(name), whole), name


def test_float32_draws_it_within_its_tolerance(small: tuple[RenderSettings, np.ndarray]) -> None:
    settings, naive = small
    variant = load_variant("wavefront[float32]")
    worst = _worst(_small(variant.name, settings), naive)
    assert 0 < worst <= variant.tolerance


def test_the_white_furnace_is_the_sky_in_every_pixel() -> None:
    for name in ("wavefront", "wavefront[float32]"):
        pixels = _file(name, "furnace.yml", 12, 10)
        assert {tuple(p) for p in pixels.tolist()} == {(0.5, 0.5, 0.5)}, name


def test_the_closed_box_of_big_spheres_is_naives_at_float64() -> None:
    # lit only by emissive spheres found by bounces; walls of radius 1e5
    naive = _file("cached", "spheres-box.yml", 6, 6)
    assert naive.max() > 0.1
    assert _worst(_file("wavefront", "spheres-box.yml", 6, 6), naive) <= FLOAT64_WORST


def test_the_hierarchy_csg_and_every_kind_path_trace_as_naive() -> None:
    """lit_scene with 20 balls (over ``hits.DIRECT_MAX`` units: the hierarchy), CSG, a
    group, a cone, a smooth triangle, nested glass, three point lights, no sky, 8x6."""
    settings = RenderSettings(integrator="path", samples=1, depth=3, seed=3)
    images = []
    for name in ("cached", "wavefront"):
        variant = load_variant(name)
        camera, world = lit_scene(variant, balls=20)
        camera = replace(variant.api["camera"](8, 6, math.pi / 3), transform=camera.transform)
        images.append(_pixels(variant.api["render"](camera, world, settings)))
    assert images[0].max() > 0.1
    assert _worst(images[1], images[0]) <= FLOAT64_WORST


def test_a_path_traced_pass_stays_within_max_mb() -> None:
    """The batch of a pass only shrinks from bounce to bounce: max_mb bounds the path
    integrator's memory as it bounds the book's (96x72 pixels, 4 samples, 5 bounces)."""
    peaks = {}
    for mb in (2, 64):
        variant = load_variant(f"wavefront[max_mb={mb}]")
        scene = load_scene(SCENES / "cpp-spheres.yml", variant.api).resized(96, 72)
        world, tracer = variant.world_for(scene), variant.tracer
        settings = RenderSettings(integrator="path", samples=4, depth=5, seed=1)
        tracer.render(scene.camera, world, replace(settings, samples=1, depth=1))
        image = tracer.new_canvas(scene.camera)
        tracemalloc.start()
        tracer.render_into(image, scene.camera, world, settings)
        _, peaks[mb] = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        tracer.forget()
    assert peaks[2] < 2 * 2**20
    assert peaks[64] > 2 * peaks[2]


# ------------------------------------------------------------------------ the integrators


def test_an_area_light_is_path_traced_and_refused_by_the_books_integrator() -> None:
    variant = load_variant("wavefront")
    scene = load_scene(SCENES / "soft-shadows.yml", variant.api).resized(4, 3)
    world = variant.world_for(scene)  # packed: the area light is the path integrator's
    refusal = r"light 0 of the world is an AreaLight.*--integrator path"
    with pytest.raises(Unsupported, match=refusal):
        variant.api["render"](scene.camera, world, RenderSettings())
    image = variant.api["render"](scene.camera, world, RenderSettings(integrator="path"))
    assert _pixels(image).max() > 0


def test_rtc_render_explains_and_path_traces_an_area_lit_scene(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from rtc.cli import main

    output = tmp_path / "soft.png"
    scene = str(SCENES / "soft-shadows.yml")
    args = ["render", scene, "--variant", "wavefront", "--size", "8x6", "--explain"]
    status = main([*args, "--integrator", "path", "-o", str(output)])
    out, err = capsys.readouterr()
    assert status == 0, err
    assert "WavefrontTracer: passes of up to" in out + err and output.exists()
    assert main([*args, "-o", str(tmp_path / "book.png")]) == 2  # the book's: refused
    _, err = capsys.readouterr()
    assert err.count("\n") == 1 and "is an AreaLight" in err, err


def test_a_wavefront_frame_keeps_freed_pass_arrays_for_the_next_pass() -> None:
    # after a wavefront frame, a pass's arrays freed together and made again reuse mapped
    # memory (glibc): 20 passes of 8 arrays of 4 MiB take far fewer page faults than fresh
    # memory would (20 x 8 x 1024 pages; glibc's own adaptive thresholds give back the
    # 32 MiB freed at once and fault over half of them again). Where the C library is not
    # glibc nothing is changed, and it says so
    import platform
    import resource

    from variants.wavefront.allocator import keep_freed_arrays

    variant = load_variant("wavefront")
    scene = load_scene_text(SMALL_SCENE, variant.api, path="small.yml")
    variant.api["render"](scene.camera, variant.world_for(scene), SMALL_SETTINGS)

    def passes(n: int) -> int:
        before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        for _ in range(n):
            arrays = [np.ones(1 << 19) for _ in range(8)]
            del arrays
        return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before

    passes(2)  # the heap grown once
    faults = passes(20)  # before asking keep_freed_arrays: the frame has set it
    glibc = platform.libc_ver()[0] == "glibc"
    assert keep_freed_arrays() is glibc
    if glibc:
        assert faults < 20 * 8 * 1024 // 20, faults
