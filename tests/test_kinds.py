"""One table of shape kinds (``scene.kinds``) and one of pattern kinds
(``scene.pattern_kinds``): every list of kinds elsewhere is derived from them, and what they
say of a kind is what the reference's class does."""

from __future__ import annotations

import math

import pytest

import raytracer as rt
from raytracer.api import BOOK_API, naive_api
from raytracer.intersections import Intersection
from scene import materials as scene_materials
from scene import shapes as scene_shapes
from scene.kinds import ADDABLE, BY_NAME, KINDS, Kind, reference_kind
from scene.pattern_kinds import NO_PATTERN, PATTERN_KINDS, PLAIN, reference_pattern_kind
from variants.numba import features, kernel_flags
from variants.numba import layout as L
from variants.numba.features import KIND_NAMES
from variants.wavefront import scene as wavefront


def test_the_kinds_are_numbered_by_their_place_and_named_by_the_books_factories() -> None:
    assert [k.number for k in KINDS] == list(range(len(KINDS)))
    book = naive_api()
    corners = [rt.point(0, 0, 0), rt.point(1, 0, 0), rt.point(0, 1, 0)]
    for kind in KINDS:
        assert kind.name in BOOK_API and kind.chapter == BOOK_API[kind.name]
        arguments = corners[: kind.corners] + [rt.vector(0, 0, 1)] * (3 if kind.smooth else 0)
        made = book[kind.name](*arguments)
        assert type(made) is kind.reference
        assert reference_kind(made) == (kind, None)
        for parameter in kind.parameters:
            assert getattr(made, parameter.attribute) == parameter.default


@pytest.mark.parametrize("kind", [k for k in KINDS if not k.corners], ids=lambda k: k.name)
def test_a_kinds_box_is_the_reference_shapes(kind: Kind) -> None:
    values = {"minimum": -0.5, "maximum": 2.0, "closed": True, "major_radius": 2.0,
              "minor_radius": 0.5}  # fmt: skip
    shape = kind.reference()
    given = {p.attribute: values[p.attribute] for p in kind.parameters}
    for attribute, value in given.items():
        setattr(shape, attribute, value)
    box = shape.local_bounds()
    expected = ((box.min.x, box.min.y, box.min.z), (box.max.x, box.max.y, box.max.z))
    if all(math.isfinite(v) for corner in expected for v in corner):
        assert kind.local_box(given) == expected
    else:
        assert kind.local_box(given) is None
    if any(p.infinite for p in kind.parameters):  # at the defaults (unbounded ends): no box
        assert kind.local_box() is None


def test_every_list_of_kinds_is_the_tables() -> None:
    # the scene format: the keys of each addable kind, and what 'known:' lists
    for kind in ADDABLE:
        assert scene_shapes.KEYS[kind.name] == (*scene_shapes.COMMON_KEYS, *kind.keys)
    assert [s for s in scene_shapes.SHAPES if s in BY_NAME] == [k.name for k in ADDABLE]
    # numba: the numbers its kernels compare with, its switches and the names --explain uses
    numbers = [L.K_SPHERE, L.K_PLANE, L.K_CUBE, L.K_CYLINDER, L.K_CONE, L.K_TORUS,
               L.K_TRIANGLE, L.K_SMOOTH_TRIANGLE, L.K_TEST]  # fmt: skip
    assert numbers == [k.number for k in KINDS]
    assert set(features.KIND_FLAGS.values()) <= set(vars(kernel_flags))
    assert {k.number: k.name for k in KINDS} == KIND_NAMES
    # wavefront: every kind that renders
    assert tuple(k.name for k in KINDS if k.renders) == wavefront.KIND_NAMES
    assert tuple(k.max_hits for k in KINDS if k.renders) == wavefront.SLOTS


def test_a_subclass_that_changes_how_a_kind_intersects_is_no_kind() -> None:
    class OddSphere(rt.Sphere):
        def local_intersect(self, ray: object) -> list[Intersection]:
            return []

    class PlainSphere(rt.Sphere):
        pass

    assert reference_kind(OddSphere()) == (None, rt.Sphere)
    assert reference_kind(PlainSphere()) == (BY_NAME["sphere"], None)
    assert reference_kind(rt.group()) == (None, None)


def test_the_pattern_kinds_are_numbered_from_one_and_named_by_the_books_factories() -> None:
    assert NO_PATTERN == 0
    assert [k.number for k in PATTERN_KINDS] == list(range(1, len(PATTERN_KINDS) + 1))
    book = naive_api()
    white, black = rt.color(1, 1, 1), rt.color(0, 0, 0)
    uv = book["uv_checkers"](2, 2, white, black)
    arguments = {"test_pattern": (), "texture_map": (uv, book["spherical_map"]),
                 "cube_map": (uv,) * 6}  # fmt: skip
    for kind in PATTERN_KINDS:
        assert kind.name in BOOK_API and kind.chapter == BOOK_API[kind.name]
        made = book[kind.name](*arguments.get(kind.name, (white, black)))
        assert type(made) is kind.reference
        assert reference_pattern_kind(made) is kind
        assert kind.two_colors == hasattr(made, "a")
    assert tuple(k for k in PATTERN_KINDS if not k.texture) == PLAIN


def test_every_list_of_pattern_kinds_is_the_tables() -> None:
    # the scene format: its pattern types (the texture patterns are ``type: map``)
    assert {k.key: k.name for k in PLAIN if k.key} == scene_materials.PATTERNS
    # numba: the numbers its kernels compare with, its switches and the names --explain uses
    numbers = [L.P_STRIPE, L.P_GRADIENT, L.P_RING, L.P_CHECKERS, L.P_TEST, L.P_MAP,
               L.P_CUBE_MAP]  # fmt: skip
    assert numbers == [k.number for k in PATTERN_KINDS] and L.P_NONE == NO_PATTERN
    assert set(features.PATTERN_FLAGS.values()) <= set(vars(kernel_flags))
    assert {k.number: k.name for k in PATTERN_KINDS} == features.PATTERN_NAMES
    # wavefront: chapter 10's patterns
    assert wavefront.PATTERN_KINDS == PLAIN
    numbers = [wavefront.STRIPES, wavefront.GRADIENT, wavefront.RINGS, wavefront.CHECKERS,
               wavefront.TEST_PATTERN]  # fmt: skip
    assert numbers == [k.number for k in PLAIN]


def test_a_subclass_that_changes_how_a_pattern_colors_is_no_kind() -> None:
    class OddStripes(rt.StripePattern):
        def local_pattern_at(self, point: object) -> rt.Color:
            return rt.color(0, 0, 0)

    class PlainStripes(rt.StripePattern):
        pass

    white, black = rt.color(1, 1, 1), rt.color(0, 0, 0)
    assert reference_pattern_kind(OddStripes(white, black)) is None
    assert reference_pattern_kind(PlainStripes(white, black)).name == "stripe_pattern"
    assert reference_pattern_kind(rt.test_pattern(), PLAIN[:4]) is None
