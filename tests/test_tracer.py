"""The Tracer interface (raytracer/tracer.py): steps reach each other through ``self``, one
pixel loop, one preparation per frame, wrappers that forward."""

from __future__ import annotations

import math
from typing import Any

import pytest

import raytracer
from raytracer import (
    RenderSettings,
    color,
    default_world,
    point,
    point_light,
    vector,
    view_transform,
)
from raytracer.camera import Camera
from raytracer.colors import Color
from raytracer.tracer import STEPS, TRACER, Tracer, write_region
from raytracer.tuples import Tuple
from raytracer.world import World
from variants.registry import load_variant
from variants.wrapper import Wrapper, steps_overridden


def _scene(size: int = 11) -> tuple[Camera, World]:
    view = view_transform(point(0, 0, -5), point(0, 0, 0), vector(0, 1, 0))
    return Camera(size, size, math.pi / 2, view), default_world()


def _pixels(image: Any) -> list[Color]:
    return [
        raytracer.pixel_at(image, x, y) for y in range(image.height) for x in range(image.width)
    ]


def test_the_book_names_are_the_default_tracers_steps() -> None:
    for name in ("color_at", "shade_hit", "is_shadowed", "render", "intersect_world"):
        method = getattr(raytracer, name)
        assert method.__self__ is TRACER, name
        assert method.__func__ is getattr(Tracer, name), name
    # the leaf steps are their chapter's functions themselves
    for name in ("lighting", "prepare_computations", "schlick", "ray_for_pixel"):
        assert getattr(raytracer, name) is getattr(Tracer, name) is getattr(TRACER, name)


class NoShadows(Tracer):
    """Overrides one step, chapter 8's shadow test."""

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        return False


def _shadow_scene() -> tuple[Camera, World]:
    """Chapter 8's "shade_hit() is given an intersection in shadow", seen through a 1x1
    camera: the pixel is the second sphere's point in the first one's shadow."""
    s1 = raytracer.sphere()
    s2 = raytracer.sphere()
    raytracer.set_transform(s2, raytracer.translation(0, 0, 10))
    w = World([s1, s2], [point_light(point(0, 0, -10), color(1, 1, 1))])
    view = view_transform(point(0, 0, 5), point(0, 0, 10), vector(0, 1, 0))
    return Camera(1, 1, math.pi / 2, view), w


def test_an_override_of_one_step_is_called_by_every_step_above_it() -> None:
    c, w = _shadow_scene()
    shadowed = raytracer.pixel_at(TRACER.render(c, w), 0, 0)
    lit = raytracer.pixel_at(NoShadows().render(c, w), 0, 0)
    assert shadowed == color(0.1, 0.1, 0.1)  # ambient only, as the book expects
    assert lit.red > 0.5  # render -> pixel_color -> color_at -> shade_hit -> is_shadowed
    assert steps_overridden(NoShadows()) == ("is_shadowed",)


def test_render_region_gives_the_same_pixels_as_render() -> None:
    c, w = _scene(9)
    settings = RenderSettings(samples=2, seed=7)
    whole = TRACER.render(c, w, settings)
    image = raytracer.canvas(9, 9)
    for region in [(0, 0, 9, 4), (0, 4, 4, 9), (4, 4, 9, 9)]:
        write_region(image, region, TRACER.render_region(c, w, settings, region))
    assert _pixels(image) == _pixels(whole)


class CountingPrepare(Tracer):
    def __init__(self) -> None:
        super().__init__()
        self.prepares = 0

    def prepare(self, c: Camera, w: World, settings: RenderSettings) -> Any:
        self.prepares += 1
        return super().prepare(c, w, settings)


def test_a_frame_is_prepared_once_for_all_its_regions_and_afresh_for_each_render() -> None:
    c, w = _scene(4)
    settings = RenderSettings()
    tracer = CountingPrepare()
    for y in range(4):
        tracer.render_region(c, w, settings, (0, y, 4, y + 1))
    assert tracer.prepares == 1
    tracer.render_region(c, w, RenderSettings(), (0, 0, 1, 1))  # another frame
    assert tracer.prepares == 2
    tracer.render(c, w)
    tracer.render(c, w)
    assert tracer.prepares == 4


def test_a_changed_world_between_renders_is_seen() -> None:
    c, w = _scene(11)
    tracer = Tracer()
    before = _pixels(tracer.render(c, w))
    w.light = point_light(point(-10, 10, 10), color(1, 1, 1))  # behind the spheres
    assert _pixels(tracer.render(c, w)) != before


class Doubling(Wrapper):
    def render_region(
        self, c: Camera, w: World, settings: RenderSettings, region: Any
    ) -> list[float]:
        return [2 * v for v in self.inner.render_region(c, w, settings, region)]


def test_a_wrapper_forwards_every_step_but_its_own() -> None:
    c, w = _scene(3)
    inner = NoShadows()
    wrapped = Doubling(inner)
    r = raytracer.ray(point(0, 0, -5), vector(0, 0, 1))
    assert wrapped.color_at(w, r) == inner.color_at(w, r)
    settings = RenderSettings()
    region = (0, 1, 3, 2)
    assert wrapped.render_region(c, w, settings, region) == [
        2 * v for v in inner.render_region(c, w, settings, region)
    ]
    assert steps_overridden(wrapped) == ("is_shadowed", "render_region")


def test_steps_lists_the_book_names_first_and_every_step_is_a_tracer_method() -> None:
    for name in STEPS:
        assert callable(getattr(Tracer, name)), name


@pytest.mark.parametrize(
    ("name", "steps"),
    [
        ("naive", ()),
        ("cached", ()),
        (
            "robust",
            ("lighting", "prepare_computations", "is_shadowed", "refracted_color", "schlick"),
        ),
    ],
)
def test_variants_declare_the_steps_they_override(name: str, steps: tuple[str, ...]) -> None:
    v = load_variant(name)
    assert isinstance(v.tracer, Tracer)
    assert sorted(v.steps) == sorted(steps)
    assert set(steps) <= v.overrides
    # the API's pipeline names are the variant's tracer's
    assert v.api["color_at"].__self__ is v.tracer


def test_the_architecture_pages_own_variant_example_works() -> None:
    """docs/architecture.md's "Your own variant" example: a subclass overriding one step."""
    from pathlib import Path

    page = Path(__file__).resolve().parent.parent / "docs" / "architecture.md"
    text = page.read_text(encoding="utf-8")
    code = text.split("```python\n# noshadows.py\n", 1)[1].split("```", 1)[0]
    namespace: dict[str, Any] = {}
    exec(compile(code, "docs/architecture.md (noshadows.py)", "exec"), namespace)
    v = namespace["variant"]()
    assert v.name == "noshadows" and v.steps == ("is_shadowed",)
    c, w = _shadow_scene()
    assert v.api["render"](c, w) == NoShadows().render(c, w)
    assert v.api["render"](c, w) != TRACER.render(c, w)
