"""The path integrator with and without explicit light sampling (chapter 21 here, beyond the
book; ``raytracer.path``): with it off an area light is found by the paths that cross it,
each crossing weighted so the mean is what the shadow rays give. The crossing's arithmetic
exactly, its mean against the shadow rays' at one point, both settings converging to the
same picture of a scene with an area light, every path-tracing variant drawing the
reference's picture with it off, the scene file's key and the flag; and the rays a path-traced
render counts (``count_rays``): its camera rays are what MRay/s divides by.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import pytest
from test_path_tracing import SMALL_SCENE, SMALL_SETTINGS

from harness.engine.figures import samples_per_second
from harness.instruments.raycount import HOOK, INSTRUMENTED, count_rays
from raytracer import plane
from raytracer.camera import RenderSettings
from raytracer.colors import color
from raytracer.intersections import intersection, prepare_computations
from raytracer.lights import area_light
from raytracer.materials import material
from raytracer.path import crossed_lights, direct_light
from raytracer.rays import ray
from raytracer.sampling import path_random
from raytracer.scatter import cosine_direction
from raytracer.tracer import TRACER
from raytracer.tuples import point, vector
from raytracer.world import world
from rtc.cli import main
from scene import load_scene_text
from scene.errors import SceneError
from variants.registry import load_variant

# a square floor and two spheres under a square area light, no sky: only the light lights
# them, seen from below it. (Far from the light, or near its plane, the crossings are rare
# and bright: the book's light does not fall off with distance, so a crossing's weight grows
# as the distance cubed, and over an endless plane the crossings' variance has no bound.)
AREA_SCENE = """
- add: camera
  width: 12
  height: 9
  field-of-view: 1.2
  from: [0, 2.8, -0.4]
  to: [0, 0, 0]
  up: [0, 0, 1]
- add: area_light
  corner: [-1, 3, -1]
  uvec: [2, 0, 0]
  usteps: 4
  vvec: [0, 0, 2]
  vsteps: 4
  intensity: [1, 1, 1]
- add: cube
  transform: [[scale, 2.5, 0.1, 2.5], [translate, 0, -0.1, 0]]
  material: {color: [0.8, 0.8, 0.8], diffuse: 0.9}
- add: sphere
  transform: [[scale, 0.6, 0.6, 0.6], [translate, 0.3, 0.6, 0.2]]
  material: {color: [0.9, 0.3, 0.2], diffuse: 0.9}
- add: sphere
  transform: [[scale, 0.4, 0.4, 0.4], [translate, -1.2, 0.4, -0.6]]
  material: {color: [0.2, 0.4, 0.9], diffuse: 0.9}
"""


def _pixels(image: Any) -> np.ndarray:
    return np.array([(p.red, p.green, p.blue) for p in image.pixels])


def _render(name: str, text: str, settings: RenderSettings) -> np.ndarray:
    variant = load_variant(name)
    scene = load_scene_text(text, variant.api, path="area.yml")
    return _pixels(variant.api["render"](scene.camera, variant.world_for(scene), settings))


def _square_light() -> Any:
    # 2 x 2 at height 2 over the origin
    corner, intensity = point(-1, 2, -1), color(1, 0.5, 0.25)
    return area_light(corner, vector(2, 0, 0), 4, vector(0, 0, 2), 4, intensity)


def test_a_ray_that_crosses_the_light_brings_its_light_times_the_crossings_factor() -> None:
    w = world()
    w.lights = [_square_light()]
    weight = color(0.5, 0.5, 0.5)
    d = vector(0.3, 0.8, 0.1)  # from the origin: crosses y = 2 at t = 2.5, at (0.75, 2, 0.25)
    seen = crossed_lights(TRACER, w, ray(point(0, 0, 0), d), weight)
    # n = U x V = (2, 0, 0) x (0, 0, 2) = (0, -4, 0); d . n = -3.2; |d|^3
    factor = math.pi * 2.5 * 2.5 * (0.3**2 + 0.8**2 + 0.1**2) ** 1.5 / 3.2
    expected = color(0.5, 0.25, 0.125) * factor
    assert (seen.red, seen.green, seen.blue) == pytest.approx(
        (expected.red, expected.green, expected.blue), rel=1e-12
    )
    # outside the square, behind the origin, along the light's plane: nothing
    for miss in (vector(0.6, 0.8, 0), vector(0, -1, 0), vector(1, 0, 0)):
        assert crossed_lights(TRACER, w, ray(point(0, 0, 0), miss), weight) == color(0, 0, 0)
    # a floor between the origin and the light hides it
    w.objects = [plane()]
    assert crossed_lights(TRACER, w, ray(point(0, -1, 0), d), weight) == color(0, 0, 0)


def test_the_crossings_mean_is_the_shadow_rays_mean_at_a_point() -> None:
    # at a point of a floor under the light: the mean of crossed_lights over cosine-weighted
    # directions equals the mean of direct_light over the light's points (both estimate
    # intensity * mean cos over the light), within their noise
    w = world()
    w.lights = [_square_light()]
    floor = plane()
    floor.material = material()
    r = ray(point(0.7, 1, -0.4), vector(0, -1, 0))
    comps = prepare_computations(intersection(1, floor), r)
    white = color(1, 1, 1)
    n = 40_000
    crossings = np.empty(n)
    shadow_rays = np.empty(n)
    for i in range(n):
        u1, u2 = path_random(1, 0, 0, i, 0, 0), path_random(1, 0, 0, i, 0, 1)
        direction = cosine_direction(comps.normalv, u1, u2)
        crossings[i] = crossed_lights(TRACER, w, ray(comps.over_point, direction), white).red
        TRACER._sample = (2, 0, 0, i)
        shadow_rays[i] = direct_light(TRACER, w, comps, white, 0).red
    noise = 4 * math.hypot(crossings.std(), shadow_rays.std()) / math.sqrt(n)
    assert crossings.mean() == pytest.approx(shadow_rays.mean(), abs=noise)
    assert (crossings == 0).mean() > 0.5  # most directions miss the light: noisier
    assert crossings.std() > shadow_rays.std()
    TRACER._sample = (0, 0, 0, 0)


def test_without_light_sampling_the_picture_converges_to_the_same_one() -> None:
    # numba, against a picture with light sampling at 256 samples per pixel: without it
    # the RMSE falls as 1 / sqrt(samples) (about 4x per 16x samples), so it converges to
    # that picture, not to another; the means agree; and it is far the noisier
    on = RenderSettings(integrator="path", samples=256, depth=3, seed=1)
    off = dataclasses.replace(on, light_sampling=False, seed=2)
    reference = _render("numba", AREA_SCENE, on)
    assert reference.mean() > 0.1  # lit

    def rmse(settings: RenderSettings, samples: int) -> tuple[float, float]:
        picture = _render("numba", AREA_SCENE, dataclasses.replace(settings, samples=samples))
        return float(np.sqrt(((picture - reference) ** 2).mean())), float(picture.mean())

    few, _ = rmse(off, 8)
    many, mean = rmse(off, 128)
    assert many < few / 2.5
    assert abs(mean - reference.mean()) < 0.05 * reference.mean()
    sampled, _ = rmse(dataclasses.replace(on, seed=3), 8)
    assert sampled < few / 4


OFF = dataclasses.replace(SMALL_SETTINGS, light_sampling=False)


@pytest.fixture(scope="module")
def naive_off() -> np.ndarray:
    pixels = _render("naive", SMALL_SCENE, OFF)
    assert not np.array_equal(pixels, _render("naive", SMALL_SCENE, SMALL_SETTINGS))
    return pixels


@pytest.mark.parametrize("name", ["cached", "pooled[granularity=tile,tile=3,workers=2]:prealloc"])
def test_python_variants_draw_naives_picture_without_light_sampling(
    name: str, naive_off: np.ndarray
) -> None:
    assert np.array_equal(_render(name, SMALL_SCENE, OFF), naive_off)


@pytest.mark.parametrize("name", ["numba", "numba[threads=2]", "wavefront", "wavefront[threads=2]"])
def test_compiled_variants_draw_naives_picture_without_light_sampling(
    name: str, naive_off: np.ndarray
) -> None:
    tolerance = load_variant(name).tolerance if name.startswith("numba") else 1e-6
    assert float(np.abs(_render(name, SMALL_SCENE, OFF) - naive_off).max()) <= tolerance


def test_the_scene_files_render_item_and_the_flag_switch_it(tmp_path: Any, capsys: Any) -> None:
    naive = load_variant("naive")
    text = SMALL_SCENE + "- add: render\n  integrator: path\n  light-sampling: off\n"
    assert load_scene_text(text, naive.api, path="s.yml").render["light_sampling"] is False
    bad = SMALL_SCENE + "- add: render\n  light-sampling: sometimes\n"
    with pytest.raises(SceneError, match=r"s\.yml.*light-sampling must be on or off"):
        load_scene_text(bad, naive.api, path="s.yml")
    scene = tmp_path / "s.yml"
    scene.write_text(text)
    out = tmp_path / "s.png"
    args = ["render", str(scene), "-o", str(out), "--size", "4x3", "--variant", "numba"]
    assert main([*args, "--light-sampling", "on", "--samples", "1"]) == 0
    assert "light sampling off" not in capsys.readouterr().out
    assert main([*args, "--light-sampling", "off", "-o", str(tmp_path / "t.png")]) == 0
    assert "light sampling off" in capsys.readouterr().out
    with pytest.raises(SystemExit) as stop:
        main([*args, "--light-sampling", "maybe"])
    assert stop.value.code == 2
    assert "--light-sampling" in capsys.readouterr().err


# ---- count_rays under the path integrator

# the camera inside a closed diffuse sphere with a point light at its centre: every path
# bounces ``depth`` times (no roulette) and every diffuse hit sees the light, so a render
# of W x H pixels and S samples casts W H S camera rays, as many bounce rays per bounce,
# and as many shadow rays per bounce
INSIDE = """
- add: camera
  width: 5
  height: 3
  field-of-view: 1.0
  from: [0, 0, -1]
  to: [0, 0, 1]
  up: [0, 1, 0]
- add: light
  at: [0, 0, 0]
  intensity: [1, 1, 1]
- add: sphere
  transform: [[scale, 10, 10, 10]]
  material: {color: [0.5, 0.5, 0.5], diffuse: 1}
"""


# numba counts with a kernel of the scene's features (the path's counters are the same code in
# every kernel that path-traces; no other test needs a generic counting kernel)
@pytest.mark.usefixtures("specialized_kernels")
@pytest.mark.parametrize(("name", "method"), [("naive", INSTRUMENTED), ("numba", HOOK)])
def test_count_rays_of_a_path_traced_render_counts_camera_rays_as_mray_s_does(
    name: str, method: str
) -> None:
    variant = load_variant(name)
    scene = load_scene_text(INSIDE, variant.api, path="inside.yml")
    settings = RenderSettings(integrator="path", samples=2, depth=3)
    counted = count_rays(variant, scene.camera, variant.world_for(scene), settings)
    assert counted is not None and counted["method"] == method
    camera = 5 * 3 * 2
    assert counted["camera"] == camera
    assert counted["secondary"] == camera * 3  # every path's bounces
    assert counted["shadow"] == camera * 3  # one shadow ray per diffuse hit
    assert counted["total"] == camera * 7
    # MRay/s divides the same count by the time: a row of that render taking 1 s
    row = {"size": [5, 3], "samples": 2, "wall": [1.0], "status": "ok"}
    assert samples_per_second(row) == counted["camera"]
