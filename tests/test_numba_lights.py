"""The numba variant with several lights: each light adds its own diffuse and specular with
its own shadow test, the ambient term comes once (from the first light), no light shades
black; the book-API steps agree with the reference.

Pictures are compared with ``naive`` as ``test_numba`` does (float64: no pixel more than
``FLOAT64_WORST`` away, none by 1/255).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from differential_strategies import build_world, one_feature_set_worlds
from hypothesis import given, settings

from harness.instruments.raycount import count_rays
from raytracer.camera import RenderSettings
from raytracer.materials import material
from variants.numba import layout as L
from variants.numba.features import analyse
from variants.numba.pack import pack_world
from variants.registry import load_variant

FLOAT64_WORST = 1e-6
ONE_STEP = 1.0 / 255.0
LIGHTS = (
    ((-4.0, 6.0, -6.0), (1.0, 1.0, 1.0)),
    ((5.0, 3.0, -4.0), (0.3, 0.3, 0.6)),
    ((0.0, 8.0, 2.0), (0.5, 0.4, 0.2)),
)


def lit_scene(api: Any, lights: int) -> tuple[Any, Any]:
    """A checkered reflective floor, a glass sphere, a group of a striped cube, a capped
    cylinder (gradient) and a ringed cone, a CSG shape, a flat and a smooth triangle, lit by
    the first ``lights`` of ``LIGHTS``; 16x12. Every shape, pattern and shading stage of
    ``test_differential``'s specialized worlds (``one_feature_set_worlds``): one feature set,
    so the specialized kernel this module renders is the one that test compiles."""
    c, p, v = api["color"], api["point"], api["vector"]
    floor = api["plane"]()
    checks = api["checkers_pattern"](c(1, 1, 1), c(0.1, 0.1, 0.1))
    floor.material = material(pattern=checks, reflective=0.3, specular=0)
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](-1, 1, 0) * api["scaling"](0.7, 0.7, 0.7))
    glass.material = replace(glass.material, reflective=0.8, diffuse=0.1, ambient=0.05)
    g = api["group"]()
    api["set_transform"](g, api["translation"](1.2, 0, 1) * api["rotation_y"](0.5))
    cube = api["cube"]()
    api["set_transform"](cube, api["translation"](0, 0.5, 0) * api["scaling"](0.5, 0.5, 0.5))
    cube.material = material(pattern=api["stripe_pattern"](c(1, 0.2, 0.2), c(1, 1, 1)))
    api["add_child"](g, cube)
    cyl = api["cylinder"]()
    cyl.minimum, cyl.maximum, cyl.closed = 0.0, 1.2, True
    api["set_transform"](cyl, api["translation"](-0.8, 0, 0) * api["scaling"](0.3, 1, 0.3))
    cyl.material = material(pattern=api["gradient_pattern"](c(0.2, 0.9, 0.2), c(0.1, 0.1, 0.8)))
    cone = api["cone"]()
    cone.minimum, cone.maximum, cone.closed = -1.0, 0.0, True
    api["set_transform"](cone, api["translation"](0.9, 1, 0) * api["scaling"](0.3, 1, 0.3))
    rings = api["ring_pattern"](c(0.9, 0.5, 0.2), c(0.2, 0.3, 0.8))
    api["set_pattern_transform"](rings, api["scaling"](0.1, 0.1, 0.1))
    cone.material = material(pattern=rings)
    for shape in (cube, cyl, cone):
        api["add_child"](g, shape)
    left, right = api["cube"](), api["sphere"]()
    api["set_transform"](right, api["scaling"](1.3, 1.3, 1.3))
    carved = api["csg"]("difference", left, right)
    api["set_transform"](carved, api["translation"](0.2, 0.5, -1.8) * api["scaling"](0.4, 0.4, 0.4))
    smooth = api["smooth_triangle"](
        p(0.5, 1.6, -0.8), p(-0.3, 1.2, -0.4), p(0.4, 0.9, -0.2),
        v(0, 1, -1), v(-1, 0, -1), v(1, 0, -1),
    )  # fmt: skip
    flat = api["triangle"](p(-3.4, 0, 1), p(-2.9, 1.3, 1.5), p(-2.2, 0, 1.8))
    w = api["world"]()
    w.objects.extend([floor, glass, g, carved, flat, smooth])
    for at, rgb in LIGHTS[:lights]:
        w.lights.append(api["point_light"](p(*at), c(*rgb)))
    view = api["view_transform"](p(0, 1.6, -5), p(0, 0.7, 0), v(0, 1, 0))
    return replace(api["camera"](16, 12, math.pi / 3), transform=view), w


def _pixels(name: str, lights: int) -> np.ndarray:
    variant = load_variant(name)
    camera, world = lit_scene(variant.api, lights)
    image = variant.api["render"](camera, world, RenderSettings())
    at = variant.api["pixel_at"]
    return np.array(
        [[(q.red, q.green, q.blue) for q in (at(image, x, y) for x in range(image.width))]
         for y in range(image.height)]
    )  # fmt: skip


@pytest.mark.parametrize("lights", [0, 1, 2, 3])
def test_numba_draws_what_naive_draws_with_any_number_of_lights(lights: int) -> None:
    expected = np.clip(_pixels("naive", lights), 0, 1)
    got = np.clip(_pixels("numba", lights), 0, 1)
    difference = np.abs(got - expected)
    print(f"{lights} lights: max difference {difference.max():.3g}")
    assert difference.max() <= FLOAT64_WORST
    assert int((difference.max(axis=2) > ONE_STEP).sum()) == 0
    if lights == 0:
        assert not expected.any(), "no light: black"
    else:
        assert len({tuple(np.round(q, 3)) for q in expected.reshape(-1, 3)}) > 20


@settings(max_examples=3)
@given(spec=one_feature_set_worlds())
def test_the_lit_scene_has_the_feature_set_of_the_differential_worlds(spec: Any) -> None:
    """So the every-light test's specialized kernel is the one ``test_differential``'s
    specialized render compiles, not a compile of its own (a cold gate's 35 CPU s)."""
    api = load_variant("naive").api
    world, _ = build_world(api, spec)
    assert analyse(pack_world(lit_scene(api, 1)[1])) == analyse(pack_world(world))


@pytest.mark.usefixtures("specialized_kernels")
def test_every_light_adds_its_own_light() -> None:
    """More lights, a brighter picture; the generic kernel (every feature compiled in)
    draws a one-light world as the specialized one does."""
    totals = [float(_pixels("numba", k).sum()) for k in range(4)]
    assert totals[0] == 0.0
    assert totals[1] < totals[2] < totals[3]
    assert np.array_equal(_pixels("numba[specialize=off]", 1), _pixels("numba", 1))


def two_lights_one_blocked(api: Any) -> tuple[Any, Any, Any]:
    """Chapter 8's point in shadow (a sphere between it and the first light), lit by a
    second light that nothing blocks: the world, the hit's computations, the material."""
    w = api["world"]()
    w.light = api["point_light"](api["point"](0, 0, -10), api["color"](1, 1, 1))
    s1 = api["sphere"]()
    s2 = api["sphere"]()
    api["set_transform"](s2, api["translation"](0, 0, 10))
    s2.material = material(color=api["color"](0.2, 0.6, 0.9), specular=0.5, shininess=50)
    w.objects.extend([s1, s2])
    w.lights.append(api["point_light"](api["point"](1, 2, 4), api["color"](0.5, 0.7, 0.9)))
    r = api["ray"](api["point"](0, 0, 5), api["vector"](0, 0.05, 1))
    xs = api["intersect_world"](w, r)
    hit = next(i for i in xs if i.t > 0)
    assert hit.object is s2
    return w, api["prepare_computations"](hit, r, xs), s2.material


def test_two_lights_one_of_them_blocked() -> None:
    """The first light is blocked, the second is not: the color is the first light's
    ambient term plus the second light's diffuse and specular (and no second ambient)."""
    seen = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        w, comps, m = two_lights_one_blocked(api)
        first, second = w.lights
        assert api["is_shadowed"](w, comps.over_point) is True
        assert api["is_shadowed"](w, first.position, comps.over_point) is True
        assert api["is_shadowed"](w, second.position, comps.over_point) is False
        shaded = api["shade_hit"](w, comps)
        parts = (
            api["lighting"](m, comps.object, first, comps.over_point, comps.eyev,
                            comps.normalv, True),
            api["lighting"](m, comps.object, second, comps.over_point, comps.eyev,
                            comps.normalv, False, ambient=False),
        )  # fmt: skip
        expected = parts[0] + parts[1]
        for got, want in zip(
            (shaded.red, shaded.green, shaded.blue),
            (expected.red, expected.green, expected.blue),
            strict=True,
        ):
            assert got == pytest.approx(want, abs=1e-12)
        only_ambient = api["lighting"](
            m, comps.object, first, comps.over_point, comps.eyev, comps.normalv, True
        )
        assert shaded.red > only_ambient.red + 0.05  # the second light does add
        seen[name] = (shaded.red, shaded.green, shaded.blue)
    assert seen["numba"] == pytest.approx(seen["naive"], abs=1e-12)


def test_the_book_steps_agree_with_the_reference() -> None:
    """``lighting`` with and without its ambient term, ``is_shadowed`` in both forms,
    ``shade_hit`` and ``color_at`` in a world of three lights."""
    results: dict[str, list[Any]] = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        camera, w = lit_scene(api, 3)
        out: list[Any] = []
        m = material(color=api["color"](0.3, 0.6, 0.9), shininess=20)
        eyev, normalv = api["vector"](0, 0, -1), api["vector"](0, 0.6, -0.8)
        for light in w.lights:
            for in_shadow in (False, True):
                for ambient in (True, False):
                    c = api["lighting"](
                        m, api["sphere"](), light, api["point"](0, 0, 0), eyev, normalv,
                        in_shadow, ambient=ambient,
                    )  # fmt: skip
                    out.append(round(c.red, 12))
        for q in ((0, 0.01, 0), (-1, 0.2, 0.9), (1.2, 0.1, 1.5), (3, 0.001, 3)):
            p = api["point"](*q)
            out.append(api["is_shadowed"](w, p))
            out.extend(api["is_shadowed"](w, light.position, p) for light in w.lights)
        for x, y in ((4, 6), (8, 5), (11, 8), (2, 10)):
            r = api["ray_for_pixel"](camera, x, y)
            c = api["color_at"](w, r)
            out.append(tuple(round(v, 9) for v in (c.red, c.green, c.blue)))
            xs = api["intersect_world"](w, r)
            hit = api["hit"](xs)
            if hit is not None:
                s = api["shade_hit"](w, api["prepare_computations"](hit, r, xs))
                out.append(tuple(round(v, 9) for v in (s.red, s.green, s.blue)))
        results[name] = out
    assert results["numba"] == results["naive"]
    assert True in results["naive"] and False in results["naive"]


def test_every_light_is_packed_and_explained() -> None:
    """One kernel serves any number of lights (no feature of their own: a kernel kept to
    one light measured no faster); ``explain`` counts them."""
    api = load_variant("naive").api
    flags = set()
    for lights in (0, 1, 2, 3):
        _, w = lit_scene(api, lights)
        packed = pack_world(w)
        assert packed.lights.shape == (lights, L.NLIGHT)
        assert packed.lights[:, 3:6].tolist() == [list(rgb) for _, rgb in LIGHTS[:lights]]
        assert not packed.lights[:, L.LIGHT_USTEPS].any(), "point lights: no cells"
        flags.add(analyse(packed).flags)
    assert len(flags) == 1
    _, w = lit_scene(api, 2)
    printed = load_variant("numba").tracer.explain(w)
    assert "lights: 2 (each with its own shadow rays; the ambient term once)" in printed
    w.lights.clear()
    assert "lights: 0 (every surface black)" in load_variant("numba").tracer.explain(w)


def test_a_light_that_is_not_a_point_light_is_refused_naming_it() -> None:
    api = load_variant("numba").api
    _, w = lit_scene(api, 1)
    w.lights.append("a lamp")
    with pytest.raises(ValueError, match="numba: light 1 of the world is a str; the kernels"):
        api["render"](api["camera"](4, 4, 1.0), w)


@pytest.mark.usefixtures("specialized_kernels")
def test_a_world_without_light_counts_the_rays_the_reference_casts() -> None:
    """Without a light every hit is black: the render skips its normal, shading and the
    rays it spawns (``kernels_trace.drain``); the counting kernel still casts them all,
    as the reference does (its reflective floor and glass sphere spawn rays). The counting
    kernel is the one specialized to ``lit_scene`` (about a third of the generic one's
    compile); the skip is a switch of every kernel, specialized or not."""
    counts = {}
    for name in ("naive", "numba"):
        variant = load_variant(name)
        camera, world = lit_scene(variant.api, 0)
        counted = count_rays(variant, camera, world, RenderSettings())
        assert counted is not None
        counts[name] = {kind: counted[kind] for kind in ("camera", "shadow", "secondary")}
    assert counts["numba"] == counts["naive"]
    assert counts["naive"]["secondary"] > 0 and counts["naive"]["camera"] == 16 * 12
