"""The path integrator's pure parts (chapter 21 here, beyond the book), as properties over
many inputs: its random numbers (the documented formula, pinned values a port checks
itself against), the basis and the cosine-weighted directions, the lobe shares, Russian
roulette, the sky; energy is never created; the settings and the scene items that carry
them refuse what is not meant."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from raytracer import (
    World,
    color,
    cosine_direction,
    cross,
    dot,
    gradient_sky,
    magnitude,
    material,
    normalize,
    orthonormal_basis,
    path_color_at,
    path_random,
    point,
    ray,
    russian_roulette,
    scaling,
    sky,
    sky_color,
    sphere,
    translation,
    vector,
)
from raytracer.camera import RenderSettings
from raytracer.colors import Color
from raytracer.sampling import GAMMA, MASK64, PATH_TAG, mix64, sample_key
from raytracer.scatter import DIFFUSE, GLASS, MIRROR, choose_lobe
from raytracer.tuples import Tuple
from scene import SceneError, load_scene_text
from variants.registry import load_variant

SEEDS = st.integers(0, 2**64 - 1)
PIXELS = st.integers(0, 16383)
SAMPLES = st.integers(0, 2**20 - 1)
BOUNCES = st.integers(0, 100)
DIMENSIONS = st.integers(0, 2**32 - 1)
UNIT = st.floats(0, 1, exclude_max=True)
COMPONENT = st.floats(-1, 1)


@st.composite
def unit_vectors(draw: st.DrawFn) -> Tuple:
    x, y, z = draw(COMPONENT), draw(COMPONENT), draw(COMPONENT)
    length = math.sqrt(x * x + y * y + z * z)
    if length < 1e-3:
        return vector(0, 0, -1 if x < 0 else 1)
    return vector(x / length, y / length, z / length)


def test_path_random_is_the_documented_formula_and_its_pinned_values() -> None:
    # path_random(seed, x, y, i, b, d): mix64(((key ^ PATH_TAG) + (1 + (b << 32) + d) *
    # GAMMA) mod 2**64), top 53 bits; pinned so a port can check itself bit for bit
    key = sample_key(7, 3, 4, 5)
    counter = 1 + (1 << 32) + 2
    expected = (mix64(((key ^ PATH_TAG) + counter * GAMMA) & MASK64) >> 11) * 2.0**-53
    assert path_random(7, 3, 4, 5, 1, 2) == expected
    assert path_random(0, 0, 0, 0, 0, 0) == 0.7286465750620634
    assert path_random(7, 3, 4, 5, 1, 2) == 0.11284039809645863


@settings(max_examples=200)
@given(SEEDS, PIXELS, PIXELS, SAMPLES, BOUNCES, DIMENSIONS)
def test_path_random_is_a_number_in_0_1_and_the_same_every_time(
    seed: int, x: int, y: int, i: int, bounce: int, dimension: int
) -> None:
    u = path_random(seed, x, y, i, bounce, dimension)
    assert 0.0 <= u < 1.0
    assert u == path_random(seed, x, y, i, bounce, dimension)


@pytest.mark.parametrize(
    "arguments",
    [(0, 0, 0, 0, -1, 0), (0, 0, 0, 0, 2**31, 0), (0, 0, 0, 0, 0, 2**32), (0, 16384, 0, 0, 0, 0)],
)
def test_path_random_refuses_arguments_outside_its_streams(arguments: tuple[int, ...]) -> None:
    with pytest.raises(ValueError, match="outside"):
        path_random(*arguments)


def test_path_numbers_are_not_the_pixel_offsets_or_the_light_jitter() -> None:
    from raytracer.sampling import light_jitter, sample_offset

    others = set(sample_offset(3, 1, 2, 0)) | set(light_jitter(3, 1, 2, 0, 0, 0, 0))
    mine = {path_random(3, 1, 2, 0, b, d) for b in range(6) for d in range(8)}
    assert not mine & others and len(mine) == 48


@settings(max_examples=200)
@given(unit_vectors())
def test_the_basis_is_orthonormal_and_right_handed(n: Tuple) -> None:
    t, b = orthonormal_basis(n)
    for v in (t, b):
        assert magnitude(v) == pytest.approx(1, abs=1e-12)
        assert dot(v, n) == pytest.approx(0, abs=1e-12)
    assert dot(t, b) == pytest.approx(0, abs=1e-12)
    c = cross(t, b)
    assert (c.x, c.y, c.z) == pytest.approx((n.x, n.y, n.z), abs=1e-12)


@settings(max_examples=200)
@given(unit_vectors(), UNIT, UNIT)
def test_a_cosine_direction_is_a_unit_vector_at_its_height_above_the_surface(
    n: Tuple, u1: float, u2: float
) -> None:
    d = cosine_direction(n, u1, u2)
    assert magnitude(d) == pytest.approx(1, abs=1e-12)
    # the height above the surface is sqrt(1 - u1): never below it
    assert dot(d, n) == pytest.approx(math.sqrt(1 - u1), abs=1e-12)
    assert dot(d, n) > 0


def test_cosine_directions_of_a_seed_have_the_cosine_density() -> None:
    # pdf cos(theta)/pi: P(cos(theta) <= c) = c^2, so each quarter of c^2 holds a quarter
    n = normalize(vector(1, -2, 3))
    cosines = [
        dot(cosine_direction(n, path_random(7, 0, 0, i, 0, 3), path_random(7, 0, 0, i, 0, 4)), n)
        for i in range(4096)
    ]
    quarters = [sum(1 for c in cosines if k / 4 <= c * c < (k + 1) / 4) for k in range(4)]
    assert all(abs(count - 1024) < 100 for count in quarters), quarters  # about 3 sigma


@settings(max_examples=300)
@given(st.floats(0, 1), st.floats(0, 1), UNIT)
def test_the_lobes_take_their_shares(r: float, t: float, u: float) -> None:
    m = material(reflective=r, transparency=t)
    lobe = choose_lobe(m, u)
    s = r + t
    glass, mirror = (t / s, r / s) if s > 1 else (t, r)
    if u < glass:
        assert lobe == GLASS
    elif u < glass + mirror - 1e-12:
        assert lobe == MIRROR
    elif u >= glass + mirror + 1e-12:
        assert lobe == DIFFUSE
    assert s < 1 or lobe != DIFFUSE  # no diffuse share left when r + t >= 1


@settings(max_examples=200)
@given(st.floats(0, 3), st.floats(0, 3), st.floats(0, 3), UNIT)
def test_russian_roulette_keeps_the_throughput_on_average(
    red: float, green: float, blue: float, u: float
) -> None:
    throughput = Color(red, green, blue)
    p = min(1.0, max(red, green, blue))
    kept = russian_roulette(throughput, u)
    if u < p:  # kept with probability p, divided by p: on average the throughput itself
        assert (kept.red * p, kept.green * p, kept.blue * p) == pytest.approx(
            (red, green, blue), rel=1e-12
        )
        assert max(kept.red, kept.green, kept.blue) <= max(1.0, red, green, blue) * (1 + 1e-12)
    else:
        assert kept == Color(0.0, 0.0, 0.0)


@settings(max_examples=200)
@given(unit_vectors(), st.floats(0.1, 10))
def test_the_sky_lies_between_horizon_and_zenith_and_a_uniform_one_is_exact(
    d: Tuple, length: float
) -> None:
    horizon, zenith = color(1, 0.9, 0.8), color(0.2, 0.4, 1.0)
    seen = sky_color(gradient_sky(horizon, zenith), d * length)
    t = max(0.0, d.y)
    assert seen.red == pytest.approx(1 + (0.2 - 1) * t, abs=1e-12)
    assert seen.blue == pytest.approx(0.8 + (1.0 - 0.8) * t, abs=1e-12)
    assert sky_color(sky(horizon), d * length) == horizon
    assert sky_color(None, d) == Color(0.0, 0.0, 0.0)


@settings(max_examples=25)
@given(
    st.lists(
        st.tuples(
            st.floats(-2, 2),
            st.floats(-2, 2),
            st.floats(0.2, 1),  # x, y, radius
            st.floats(0, 1),
            st.floats(0, 1),
            st.floats(0, 1),  # albedo
            st.floats(0, 1),
            st.floats(0, 1),  # reflective, transparency
        ),
        min_size=1,
        max_size=4,
    ),
    unit_vectors(),
    st.integers(0, 2**20 - 1),
)
def test_energy_is_never_created(
    balls: list[tuple[float, ...]], direction: Tuple, sample: int
) -> None:
    # no light, no emission, albedo at most 1: a path returns at most the sky
    w = World()
    for x, y, radius, red, green, blue, reflective, transparency in balls:
        s = sphere()
        s.transform = translation(x, y, 0) * scaling(radius, radius, radius)
        s.material = material(
            color=color(red, green, blue), diffuse=1.0, reflective=reflective,
            transparency=transparency, refractive_index=1.5,
        )  # fmt: skip
        w.objects.append(s)
    w.sky = sky(color(0.5, 0.25, 1.0))
    tracer = load_variant("naive").tracer
    tracer._sample = (5, 1, 2, sample)
    try:
        seen = tracer.path_color_at(w, ray(point(0, 0, -6), direction), 5, 2)
    finally:
        tracer.forget()
    assert seen.red <= 0.5 * (1 + 1e-9) and seen.green <= 0.25 * (1 + 1e-9)
    assert seen.blue <= 1.0 * (1 + 1e-9)
    assert min(seen.red, seen.green, seen.blue) >= 0.0


def test_the_default_tracer_path_traces_outside_a_render_with_sample_zero() -> None:
    w = World([sphere()], [])
    w.sky = sky(color(1, 1, 1))
    first = path_color_at(w, ray(point(0, 0, -5), vector(0, 0, 1)))
    assert first == path_color_at(w, ray(point(0, 0, -5), vector(0, 0, 1)))


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"integrator": "photon"}, "integrator must be whitted or path, got 'photon'"),
        ({"roulette": -1}, "roulette must be a whole number 0 (off) to 100"),
        ({"roulette": 1.5}, "roulette must be a whole number"),
        ({"depth": 101}, "depth must be a whole number 0 to 100"),
    ],
)
def test_render_settings_refuse_what_is_not_meant(options: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        RenderSettings(**options)  # type: ignore[arg-type]


CAMERA = """
- add: camera
  width: 4
  height: 3
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
"""


def test_the_scene_items_of_path_tracing_reach_the_scene_and_its_world() -> None:
    api = load_variant("naive").api
    text = (
        CAMERA
        + """
- add: sky
  horizon: [1, 1, 1]
  zenith: [0.5, 0.7, 1]
- add: render
  integrator: path
  samples: 3
  depth: 4
  seed: 18446744073709551615
  roulette: 2
- add: sphere
  material:
    emissive: [2, 1, 0.5]
"""
    )
    scene = load_scene_text(text, api, path="scene.yml")
    assert scene.render == {
        "integrator": "path", "samples": 3, "depth": 4, "seed": 2**64 - 1, "roulette": 2,
    }  # fmt: skip
    assert scene.sky == gradient_sky(color(1, 1, 1), color(0.5, 0.7, 1))
    world = scene.book_world()
    assert world.sky == scene.sky
    assert world.objects[0].material.emissive == color(2, 1, 0.5)
    assert scene.warnings == ()  # no light, but a sky: no "renders black" warning
    RenderSettings(**scene.render)


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("- add: sky\n  zenith: [1, 1, 1]", "the sky takes 'color' (a uniform sky) or both"),
        ("- add: sky\n  colour: [1, 1, 1]", "unknown key 'colour' in the sky"),
        ("- add: sky\n  color: [1, 1, nan]", "the sky's color[2] must be a number"),
        ("- add: render\n  integrator: 3", "the render settings' integrator must be a name"),
        ("- add: render\n  samples: 0", "samples must be a whole number from 1 to 1048576"),
        ("- add: render\n  roulette: 1.5", "roulette must be a whole number from 0 to 100"),
        ("- add: render\n  seed: -1", "seed must be a whole number from 0 to"),
        ("- add: render\n  spp: 4", "unknown key 'spp' in the render settings"),
        ("- add: render\n- add: render", "a second '- add: render' (the first is at line 9)"),
        ("- define: sky\n  value: {color: [1, 1, 1]}", "cannot define 'sky': it is a built-in"),
        ("- add: group\n  children:\n    - add: sky", "a sky cannot be part of a shape"),
    ],
)
def test_a_bad_sky_or_render_item_is_one_error_naming_the_line(item: str, message: str) -> None:
    api = load_variant("naive").api
    with pytest.raises(SceneError, match=r"scene\.yml:") as raised:
        load_scene_text(CAMERA + item + "\n", api, path="scene.yml")
    assert message in str(raised.value), str(raised.value)
