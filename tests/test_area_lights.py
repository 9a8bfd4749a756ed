"""Area lights and soft shadows (the bonus chapter "Rendering soft shadows", 18 here): the
reference's properties, the jitter contract the variants follow, the variants' renders
against naive's, and the scene loader's ``- add: area_light``."""

from __future__ import annotations

import math
import pickle
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from textwrap import dedent
from typing import Any

import pytest
from budget import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from raytracer import (
    AreaLight,
    RenderSettings,
    Tracer,
    area_light,
    color,
    default_world,
    intensity_at,
    intersection,
    lighting,
    material,
    next_,
    point,
    point_light,
    point_on_light,
    prepare_computations,
    ray,
    sequence,
    shade_hit,
    sphere,
    vector,
    view_transform,
)
from raytracer.camera import camera
from raytracer.sampling import GAMMA, MASK64, light_jitter, light_jitters, mix64, sample_key
from raytracer.tracer import NO_SAMPLE
from scene import Scene, SceneError, load_scene
from variants.registry import load_variant

coordinate = st.floats(-5, 5, allow_nan=False)
unit = st.floats(0.05, 3, allow_nan=False)


def _direction(x: float, y: float, z: float) -> Any:
    length = math.sqrt(x * x + y * y + z * z)
    return vector(x / length, y / length, z / length)


# ----------------------------------------------------------------- the reference's light


@settings(max_examples=examples(60), deadline=None)
@given(
    corner=st.tuples(coordinate, st.floats(2, 8), coordinate),
    width=unit,
    depth=unit,
    at=st.tuples(coordinate, coordinate, coordinate),
    normal=st.tuples(coordinate, coordinate, coordinate),
    eye=st.tuples(coordinate, coordinate, coordinate),
    shadowed=st.booleans(),
)
def test_a_one_cell_area_light_shades_exactly_as_a_point_light_at_its_centre(
    corner: tuple[float, float, float],
    width: float,
    depth: float,
    at: tuple[float, float, float],
    normal: tuple[float, float, float],
    eye: tuple[float, float, float],
    shadowed: bool,
) -> None:
    if min(math.hypot(*normal), math.hypot(*eye)) < 1e-3:
        return
    area = area_light(point(*corner), vector(width, 0, 0), 1, vector(0, 0, depth), 1,
                      color(1, 0.9, 0.8))  # fmt: skip
    single = point_light(area.position, area.intensity)
    assert point_on_light(area, 0, 0) == area.position
    m = material(color=color(0.6, 0.7, 0.3), shininess=30)
    p, n, e = point(*at), _direction(*normal), _direction(*eye)
    for arriving in (shadowed, 1.0, 0.25):
        assert lighting(m, None, area, p, e, n, arriving) == lighting(m, None, single, p, e, n,
                                                                       arriving)  # fmt: skip
    w = default_world()
    assert intensity_at(area, p, w) == intensity_at(single, p, w)


def test_a_one_cell_area_light_world_renders_exactly_as_its_point_light() -> None:
    area = area_light(point(-10.5, 10, -10.5), vector(1, 0, 0), 1, vector(0, 0, 1), 1,
                      color(1, 1, 1))  # fmt: skip
    with_point = default_world()
    with_area = default_world()
    with_area.light = area
    assert area.position == with_point.light.position
    c = camera(12, 10, 0.8)
    c = replace(c, transform=view_transform(point(0, 0, -5), point(0, 0, 0), vector(0, 1, 0)))
    a = load_variant("naive").api["render"](c, with_area)
    b = load_variant("naive").api["render"](c, with_point)
    assert a.pixels == b.pixels


@settings(max_examples=examples(40), deadline=None)
@given(
    at=st.tuples(coordinate, st.floats(-1.5, 1.5), coordinate),
    usteps=st.integers(1, 4),
    vsteps=st.integers(1, 4),
    jitter=st.lists(st.floats(0, 1), min_size=1, max_size=5),
)
def test_intensity_at_is_a_whole_number_of_cells(
    at: tuple[float, float, float], usteps: int, vsteps: int, jitter: list[float]
) -> None:
    w = default_world()
    light = area_light(point(-1, 1.5, -4), vector(2, 0, 0), usteps, vector(0, 1, 1), vsteps,
                       color(1, 1, 1))  # fmt: skip
    light = replace(light, jitter_by=sequence(*jitter))
    fraction = intensity_at(light, point(*at), w)
    assert 0.0 <= fraction <= 1.0
    cells = fraction * light.samples
    assert cells == round(cells)
    assert fraction == round(cells) / light.samples


def test_the_sequence_cycles_compares_by_values_and_pickles_where_it_stands() -> None:
    gen = sequence(0.25, 0.5, 0.75)
    assert [next_(gen) for _ in range(4)] == [0.25, 0.5, 0.75, 0.25]
    copy = pickle.loads(pickle.dumps(gen))
    assert next_(copy) == 0.5 and next_(gen) == 0.5
    assert gen == sequence(0.25, 0.5, 0.75) and gen != sequence(0.25, 0.5)
    assert hash(gen) == hash(sequence(0.25, 0.5, 0.75))
    assert repr(gen) == "sequence(0.25, 0.5, 0.75)"
    with pytest.raises(ValueError, match="at least one value"):
        sequence()
    with pytest.raises(ValueError, match="not a finite number"):
        sequence(0.5, math.nan)


def test_lights_are_values_whose_jitter_sequence_is_their_one_mutable_part() -> None:
    light = area_light(point(0, 0, 0), vector(2, 0, 0), 4, vector(0, 0, 1), 2, color(1, 1, 1))
    assert light == area_light(point(0, 0, 0), vector(2, 0, 0), 4, vector(0, 0, 1), 2,
                               color(1, 1, 1))  # fmt: skip
    assert light.jitter_by == sequence(0.5) and light.jitter is False
    moved = replace(light, jitter_by=sequence(0.3, 0.7))
    assert moved != light and moved.corner is light.corner
    assert {light: 1}[light] == 1  # hashable, as point lights are
    assert pickle.loads(pickle.dumps(moved)) == moved


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((vector(2, 0, 0), 0, vector(0, 0, 1), 2), "usteps must be 1 to 65536, got 0"),
        ((vector(2, 0, 0), 4, vector(0, 0, 1), -2), "vsteps must be 1 to 65536, got -2"),
        ((vector(2, 0, 0), 2.5, vector(0, 0, 1), 2), "usteps must be a whole number, got 2.5"),
        ((vector(2, 0, 0), True, vector(0, 0, 1), 2), "usteps must be a whole number, got True"),
        (
            (vector(0, 0, 0), 4, vector(0, 0, 1), 2),
            "full_uvec must be a vector of finite, non-zero",
        ),
        ((point(2, 0, 0), 4, vector(0, 0, 1), 2), "full_uvec must be a vector \\(w = 0\\)"),
    ],
)
def test_area_light_refuses_what_is_not_a_light(arguments: tuple[Any, ...], message: str) -> None:
    u, usteps, v, vsteps = arguments
    with pytest.raises(ValueError, match=f"^area_light: {message}"):
        area_light(point(0, 0, 0), u, usteps, v, vsteps, color(1, 1, 1))


def test_a_whole_float_step_count_is_a_whole_number() -> None:
    light = area_light(point(0, 0, 0), vector(2, 0, 0), 4.0, vector(0, 0, 1), 2, color(1, 1, 1))
    assert light.usteps == 4 and type(light.usteps) is int


@pytest.mark.parametrize("bad", ["x", 1.5, -0.25, None])
def test_lighting_takes_a_boolean_or_a_fraction(bad: Any) -> None:
    light = point_light(point(0, 0, -10), color(1, 1, 1))
    with pytest.raises(ValueError, match=r"^lighting: in_shadow must be true or false"):
        lighting(material(), None, light, point(0, 0, 0), vector(0, 0, -1), vector(0, 0, -1), bad)


def test_lighting_walks_every_cell_whatever_the_intensity() -> None:
    """Each call takes 2 * samples values from the sequence (here 8 of 3): the contract a
    variant reproduces for a light with a sequence of several values."""
    light = area_light(point(-0.5, -0.5, -5), vector(1, 0, 0), 2, vector(0, 1, 0), 2,
                       color(1, 1, 1))  # fmt: skip
    light = replace(light, jitter_by=sequence(0.1, 0.5, 0.9))
    args = (material(), None, light, point(0, 0, -1), vector(0, 0, -1), vector(0, 0, -1))
    for arriving in (0.0, True, 1.0):
        before = light.jitter_by.position
        lighting(*args, arriving)
        assert light.jitter_by.position == (before + 8) % 3
    before = light.jitter_by.position
    intensity_at(light, point(0, 0, -1), default_world())
    assert light.jitter_by.position == (before + 8) % 3


# ---------------------------------------------------------------------- the jitter


@settings(max_examples=examples(200), deadline=None)
@given(
    seed=st.integers(0, MASK64),
    x=st.integers(0, 16383),
    y=st.integers(0, 16383),
    i=st.integers(0, (1 << 20) - 1),
    k=st.integers(0, (1 << 31) - 1),
    u=st.integers(0, 65535),
    v=st.integers(0, 65535),
)
def test_light_jitter_is_a_pure_function_into_the_unit_square(
    seed: int, x: int, y: int, i: int, k: int, u: int, v: int
) -> None:
    ju, jv = light_jitter(seed, x, y, i, k, u, v)
    assert 0.0 <= ju < 1.0 and 0.0 <= jv < 1.0
    assert (ju, jv) == light_jitter(seed, x, y, i, k, u, v)
    stream = 3 + 2 * ((k << 32) | (v << 16) | u)
    key = sample_key(seed, x, y, i)
    assert ju == (mix64((key + stream * GAMMA) & MASK64) >> 11) * 2.0**-53
    assert jv == (mix64((key + (stream + 1) * GAMMA) & MASK64) >> 11) * 2.0**-53


def test_light_jitter_known_values() -> None:
    # pinned, so a compiled variant can check it reproduces the function bit for bit
    assert light_jitter(0, 0, 0, 0, 0, 0, 0) == (
        (mix64((3 * GAMMA) & MASK64) >> 11) * 2.0**-53,
        (mix64((4 * GAMMA) & MASK64) >> 11) * 2.0**-53,
    )
    assert light_jitter(0, 0, 0, 0, 0, 0, 0) == (0.026433771592597743, 0.9708819781538285)
    assert light_jitter(7, 3, 4, 5, 1, 2, 3) == (0.7410667646221637, 0.36291762125330596)


def test_light_jitters_lists_the_cells_v_outer_u_inner() -> None:
    values = light_jitters(5, 1, 2, 3, 1, 3, 2)
    expected: list[float] = []
    for v in range(2):
        for u in range(3):
            expected += light_jitter(5, 1, 2, 3, 1, u, v)
    assert values == expected and len(set(values)) == 12


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((0, 0, 0, 0, -1, 0, 0), "light index -1"),
        ((0, 0, 0, 0, 0, 65536, 0), "cell \\(65536, 0\\)"),
    ],
)
def test_light_jitter_refuses_what_is_out_of_range(
    arguments: tuple[int, ...], message: str
) -> None:
    with pytest.raises(ValueError, match=message):
        light_jitter(*arguments)


def test_light_for_sample_jitters_only_jittered_area_lights() -> None:
    tracer = Tracer()
    assert tracer._sample == NO_SAMPLE
    lamp = point_light(point(0, 5, 0), color(1, 1, 1))
    still = area_light(point(0, 5, 0), vector(1, 0, 0), 2, vector(0, 0, 1), 3, color(1, 1, 1))
    jittered = replace(still, jitter=True)
    assert tracer.light_for_sample(lamp, 0) is lamp
    assert tracer.light_for_sample(still, 0) is still
    tracer._sample = (9, 4, 2, 1)
    sampled = tracer.light_for_sample(jittered, 2)
    assert isinstance(sampled, AreaLight) and sampled is not jittered
    assert sampled.jitter_by.values == tuple(light_jitters(9, 4, 2, 1, 2, 2, 3))
    assert replace(sampled, jitter_by=jittered.jitter_by) == jittered
    tracer.forget()
    assert tracer._sample == NO_SAMPLE


def test_pixel_color_sets_the_sample_the_jitter_follows() -> None:
    seen: list[tuple[int, int, int, int]] = []

    class Recording(Tracer):
        __slots__ = ()

        def light_for_sample(self, light: Any, k: int) -> Any:
            seen.append(self._sample)
            return super().light_for_sample(light, k)

    w = default_world()
    view = view_transform(point(0, 0, -5), point(0, 0, 0), vector(0, 1, 0))
    c = replace(camera(4, 4, 0.3), transform=view)  # every ray meets the outer sphere
    tracer = Recording()
    tracer.pixel_color(c, w, 2, 1, RenderSettings(samples=3, seed=4))
    assert seen == [(4, 2, 1, 0), (4, 2, 1, 1), (4, 2, 1, 2)]
    seen.clear()
    tracer.pixel_color(c, w, 1, 2, RenderSettings(seed=6))
    assert seen == [(6, 1, 2, 0)]


def test_a_jittered_light_shades_the_same_points_in_intensity_at_and_lighting() -> None:
    """shade_hit's lighting is the lighting of the points intensity_at tested."""
    w = default_world()
    w.light = replace(area_light(point(-12, 10, -12), vector(4, 0, 0), 3, vector(0, 0, 4), 3,
                                 color(1, 1, 1)), jitter=True)  # fmt: skip
    shape = w.objects[0]
    r = ray(point(0, 0, -5), vector(0, 0, 1))
    comps = prepare_computations(intersection(4, shape), r)
    tracer = Tracer()
    tracer._sample = (1, 2, 3, 0)
    sampled = tracer.light_for_sample(w.light, 0)
    points = [point_on_light(sampled, u, v) for v in range(3) for u in range(3)]
    again = [point_on_light(sampled, u, v) for v in range(3) for u in range(3)]
    assert points == again  # 18 values, taken twice from a sequence of 18
    arriving = tracer.intensity_at(sampled, comps.over_point, w)
    expected = lighting(shape.material, shape, sampled, comps.over_point, comps.eyev,
                        comps.normalv, arriving)  # fmt: skip
    tracer._sample = (1, 2, 3, 0)
    assert tracer.shade_hit(w, comps) == expected
    tracer._sample = (1, 2, 3, 1)
    assert tracer.shade_hit(w, comps) != expected  # another sample, other points


# ------------------------------------------------------- the variants against naive


def soft_world(api: Mapping[str, Any]) -> tuple[Any, Any]:
    """A sphere on a plane under a jittered 3x3 area light and a point light, at 10x8."""
    w = api["world"]()
    floor = api["plane"]()
    ball = api["sphere"]()
    api["set_transform"](ball, api["translation"](0, 1, 0))
    ball.material = replace(ball.material, color=api["color"](0.9, 0.3, 0.2), reflective=0.2)
    w.objects.extend([floor, ball])
    light = api["area_light"](api["point"](-3, 4, -2), api["vector"](2, 0, 0), 3,
                              api["vector"](0, 0, 2), 3, api["color"](1, 1, 1))  # fmt: skip
    w.lights.append(replace(light, jitter=True))
    w.lights.append(api["point_light"](api["point"](4, 6, -4), api["color"](0.3, 0.3, 0.3)))
    view = api["view_transform"](api["point"](0, 2.5, -5), api["point"](0, 0.5, 0),
                                 api["vector"](0, 1, 0))  # fmt: skip
    return replace(api["camera"](10, 8, 1.0), transform=view), w


def render(name: str, samples: int = 1) -> list[tuple[float, float, float]]:
    variant = load_variant(name)
    c, w = soft_world(variant.api)
    image = variant.api["render"](c, w, RenderSettings(samples=samples, seed=3))
    pixel_at = variant.api["pixel_at"]
    colors = [pixel_at(image, x, y) for y in range(image.height) for x in range(image.width)]
    return [(float(p.red), float(p.green), float(p.blue)) for p in colors]


@pytest.fixture(scope="module")
def naive_pixels() -> dict[int, list[tuple[float, float, float]]]:
    return {samples: render("naive", samples) for samples in (1, 2)}


@pytest.mark.parametrize("name", ["cached", "prealloc", "pooled[workers=2]:prealloc"])
@pytest.mark.parametrize("samples", [1, 2])
def test_exact_variants_render_the_soft_world_as_naive(
    name: str, samples: int, naive_pixels: dict[int, list[tuple[float, float, float]]]
) -> None:
    expected = naive_pixels[samples]
    assert len({tuple(round(c, 3) for c in p) for p in expected}) > 20  # not a blank picture
    assert render(name, samples) == expected


def test_robust_renders_the_soft_world_within_its_tolerance(
    naive_pixels: dict[int, list[tuple[float, float, float]]],
) -> None:
    robust = load_variant("robust")
    got = render("robust")
    worst = max(abs(a - b) for p, q in zip(got, naive_pixels[1], strict=True)
                for a, b in zip(p, q, strict=True))  # fmt: skip
    assert worst <= robust.tolerance


def test_prealloc_takes_a_lights_sequence_as_the_reference_does() -> None:
    """A light with a sequence of several values: each call moves the same sequence by
    the same number of values, so both tracers see the same points call after call."""
    prealloc = load_variant("prealloc").api
    light = area_light(point(-0.5, -0.5, -5), vector(1, 0, 0), 2, vector(0, 1, 0), 2,
                       color(1, 1, 1))  # fmt: skip
    mine = replace(light, jitter_by=sequence(0.7, 0.3, 0.9, 0.1, 0.5))
    theirs = replace(light, jitter_by=sequence(0.7, 0.3, 0.9, 0.1, 0.5))
    w = default_world()
    s = sphere()
    for p in (point(1, -1, 2), point(1.5, 0, 2), point(0, 0, -1.2), point(0.3, 0.6, -0.9)):
        assert prealloc["intensity_at"](mine, p, w) == intensity_at(theirs, p, w)
        n = vector(p.x, p.y, p.z)
        args = (s.material, s, p, vector(0, 0, -1), n, 0.75)
        assert prealloc["lighting"](args[0], args[1], mine, *args[2:]) == lighting(
            args[0], args[1], theirs, *args[2:]
        )
        assert mine.jitter_by.position == theirs.jitter_by.position


def test_prealloc_shades_a_hit_at_the_tracers_sample() -> None:
    """Outside its pixel loop, prealloc's shade_hit jitters by the tracer's sample, as the
    reference's does."""
    prealloc = load_variant("prealloc").tracer
    w = default_world()
    w.light = replace(area_light(point(-12, 10, -12), vector(4, 0, 0), 2, vector(0, 0, 4), 2,
                                 color(1, 1, 1)), jitter=True)  # fmt: skip
    comps = prepare_computations(intersection(4, w.objects[0]), ray(point(0, 0, -5),
                                                                     vector(0, 0, 1)))  # fmt: skip
    reference = Tracer()
    for sample in ((0, 0, 0, 0), (5, 3, 2, 1)):
        prealloc._sample = reference._sample = sample
        assert prealloc.shade_hit(w, comps) == reference.shade_hit(w, comps)
    prealloc.forget()


def test_the_explanation_counts_the_cells() -> None:
    _, w = soft_world(load_variant("naive").api)
    for name in ("naive", "prealloc"):
        text = load_variant(name).tracer.explain(w)
        assert "2 lights (1 area light: 3x3 = 9 cells jittered;" in text, text


# ----------------------------------------------------------------- the scene loader

CAMERA = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 0.8
  from: [0, 2, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
"""  # 7 lines: the area light starts at line 8

AREA = """\
- add: area_light
  corner: [-1, 4, -1]
  uvec: [2, 0, 0]
  usteps: 4
  vvec: [0, 0, 2]
  vsteps: 2
  intensity: [1, 0.9, 0.8]
"""


def load(tmp_path: Path, body: str, name: str = "naive") -> Scene:
    path = tmp_path / "scene.yml"
    path.write_text(CAMERA + dedent(body), encoding="utf-8")
    return load_scene(path, load_variant(name).api, variant=name)


def test_the_loader_reads_an_area_light(tmp_path: Path) -> None:
    scene = load(tmp_path, AREA + "  jitter: true\n- add: sphere\n")
    (light,) = scene.world.lights
    assert light == replace(
        area_light(point(-1, 4, -1), vector(2, 0, 0), 4, vector(0, 0, 2), 2, color(1, 0.9, 0.8)),
        jitter=True,
    )
    assert light.uvec == vector(0.5, 0, 0) and light.position == point(0, 4, 0)
    assert scene.light_line == 8 and scene.warnings == ()
    assert scene.notes == [
        "area light at line 8: 4x2 = 8 cells, 8 shadow rays per shaded point, jittered at "
        "random per pixel sample",
    ]
    plain = load(tmp_path, AREA).world.lights[0]
    assert plain.jitter is False and plain.jitter_by == sequence(0.5)


STEPS_RANGE = "must be a whole number from 1 to 65536, got"
ZERO_EDGE = "has zero length; expected the edge of the light along which its"
KNOWN = "known keys: add, corner, uvec, usteps, vvec, vsteps, intensity, jitter"


@pytest.mark.parametrize(
    ("old", "new", "line", "message"),
    [
        ("usteps: 4", "usteps: 0", 11, f"the area light's usteps {STEPS_RANGE} 0"),
        ("vsteps: 2", "vsteps: -3", 13, f"the area light's vsteps {STEPS_RANGE} -3"),
        ("usteps: 4", "usteps: 2.5", 11, f"the area light's usteps {STEPS_RANGE} 2.5"),
        ("uvec: [2, 0, 0]", "uvec: [0, 0, 0]", 10,
         f"the area light's uvec {ZERO_EDGE} usteps cells lie, e.g. [2, 0, 0]"),
        ("vvec: [0, 0, 2]", "vvec: [0, 0.0, 0]", 12,
         f"the area light's vvec {ZERO_EDGE} vsteps cells lie, e.g. [2, 0, 0]"),
        ("intensity: [1, 0.9, 0.8]", "intensty: [1, 0.9, 0.8]", 14,
         f"unknown key 'intensty' in the area light (did you mean 'intensity'?); {KNOWN}"),
        ("  corner: [-1, 4, -1]\n", "", 8, "the area light has no 'corner'; it needs one"),
        ("jitter: true", "jitter: sometimes", 15,
         "the area light's jitter must be true or false, got 'sometimes'"),
        ("usteps: 4", "usteps: [4]", 11,
         "the area light's usteps must be a single value, got a list"),
    ],
)  # fmt: skip
def test_the_loader_names_the_line_of_a_bad_area_light(
    tmp_path: Path, old: str, new: str, line: int, message: str
) -> None:
    body = AREA + "  jitter: true\n"
    assert old in body
    with pytest.raises(SceneError) as raised:
        load(tmp_path, body.replace(old, new))
    assert str(raised.value) == f"{tmp_path / 'scene.yml'}:{line}: {message}"


def test_an_area_light_cannot_be_a_defined_name(tmp_path: Path) -> None:
    with pytest.raises(SceneError, match="cannot define 'area_light': it is a built-in"):
        load(tmp_path, "- define: area_light\n  value:\n    color: [1, 1, 1]\n")


def test_an_area_light_scene_renders_the_same_through_the_loader(tmp_path: Path) -> None:
    body = AREA + "  jitter: true\n- add: plane\n- add: sphere\n"
    body += "  transform:\n    - [translate, 0, 1, 0]\n"
    pictures = []
    for name in ("naive", "prealloc"):
        scene = load(tmp_path, body, name)
        variant = load_variant(name)
        image = variant.api["render"](scene.camera, scene.world, RenderSettings(samples=2))
        pictures.append([variant.api["pixel_at"](image, x, y) for y in range(6) for x in range(8)])
    assert pictures[0] == pictures[1]
    assert len(set(pictures[0])) > 5


def test_the_soft_shadows_scene_loads_with_one_jittered_area_light() -> None:
    path = Path(__file__).resolve().parent.parent / "scenes" / "soft-shadows.yml"
    scene = load_scene(path, load_variant("naive").api)
    (light,) = scene.world.lights
    assert isinstance(light, AreaLight) and light.jitter and light.samples == 64
    assert scene.warnings == ()


def test_the_chapters_names_are_the_references_book_api() -> None:
    api = load_variant("naive").api
    assert api["next"] is next_ and api["sequence"] is sequence
    assert api["area_light"] is area_light and api["point_on_light"] is point_on_light
    assert api["intensity_at"] == intensity_at and intensity_at.__self__ is shade_hit.__self__
