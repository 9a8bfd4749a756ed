"""Bounding boxes and hierarchies (the bonus chapter, chapter 17 here) beyond the scenarios:
the error messages, properties checked on random shapes and rays (hypothesis), and what the
``cached`` and ``prealloc`` variants do with boxes."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import pytest
from budget import examples
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import raytracer as rt
from raytracer.bounds import EMPTY, BoundingBox, ray_meets_box, transform_box
from raytracer.matrices import Matrix
from raytracer.shapes.shape import Shape
from raytracer.tolerance import EPSILON
from raytracer.tuples import Tuple
from rtc.scaffold import stub_source
from scene.build import DIVIDE_THRESHOLD, divide_groups
from scene.loader import load_scene_text
from variants.cached import CACHED_CLASSES, CachedComposite
from variants.prealloc.context import TraceContext
from variants.prealloc.groups import GroupRecord, box_buffer, meets_box
from variants.registry import load_variant
from variants.robust.geometry import ROBUST_CLASSES

APIS: dict[str, Mapping[str, Any]] = {
    name: load_variant(name).api for name in ("naive", "cached", "prealloc")
}
INF = math.inf

# ----------------------------------------------------------------------------- bad input


def _ray() -> rt.Ray:
    return rt.ray(rt.point(0, 0, -5), rt.vector(0, 0, 1))


def _unit_box() -> BoundingBox:
    return rt.bounding_box(min=rt.point(-1, -1, -1), max=rt.point(1, 1, 1))


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: rt.bounds_of("sphere"), TypeError, "bounds_of: expected a shape, got str"),
        (
            lambda: rt.parent_space_bounds_of(None),
            TypeError,
            "parent_space_bounds_of: expected a shape, got NoneType",
        ),
        (
            lambda: rt.bounding_box(min=rt.point(0, 0, 0)),
            TypeError,
            "bounding_box: only min given; give both min and max",
        ),
        (
            lambda: rt.bounding_box(min=rt.vector(0, 0, 0), max=rt.point(1, 1, 1)),
            TypeError,
            "bounding_box: min must be a point, got a vector",
        ),
        (
            lambda: rt.add_point(_unit_box(), (1, 2, 3)),
            TypeError,
            "add_point: the point must be a point, got tuple",
        ),
        (
            lambda: rt.add_box(_unit_box(), rt.point(1, 2, 3)),
            TypeError,
            "add_box: box2 must be a bounding box, got Tuple",
        ),
        (
            lambda: rt.box_contains_box(rt.sphere(), _unit_box()),
            TypeError,
            "box_contains_box: the box must be a bounding box, got Sphere",
        ),
        (
            lambda: rt.intersects(_unit_box(), rt.point(0, 0, 0)),
            TypeError,
            "intersects: the ray must be a ray, got Tuple",
        ),
        (
            lambda: rt.transform(rt.sphere(), rt.scaling(2, 2, 2)),
            TypeError,
            "transform(Sphere): expected a ray or a bounding box to transform, got Sphere",
        ),
        (
            lambda: rt.split_bounds([rt.point(0, 0, 0)]),
            TypeError,
            "split_bounds: the box must be a bounding box, got list",
        ),
        (
            lambda: rt.partition_children(rt.sphere()),
            TypeError,
            "partition_children(Sphere): expected a group, got Sphere",
        ),
        (
            lambda: rt.make_subgroup(rt.group(), rt.sphere()),
            TypeError,
            "make_subgroup(Group, Sphere): expected a list of shapes, got Sphere",
        ),
        (
            lambda: rt.make_subgroup(rt.group(), [rt.sphere(), 3]),
            TypeError,
            "make_subgroup(Group, [...]): every item must be a shape, got int",
        ),
        (
            lambda: rt.divide(rt.group(), 0),
            ValueError,
            "divide(Group, 0): the threshold must be a whole number of at least 1",
        ),
        (
            lambda: rt.divide(rt.group(), 2.5),
            ValueError,
            "divide(Group, 2.5): the threshold must be a whole number of at least 1",
        ),
        (lambda: rt.divide([rt.sphere()], 4), TypeError, "divide(list): expected a shape"),
    ],
)
def test_bad_input_is_one_clear_error(
    call: Callable[[], object], error: type[Exception], message: str
) -> None:
    with pytest.raises(error) as raised:
        call()
    assert str(raised.value).startswith(message)


def test_a_twins_errors_use_the_books_class_name() -> None:
    with pytest.raises(TypeError, match=r"^partition_children\(Sphere\): expected a group"):
        APIS["cached"]["partition_children"](APIS["cached"]["sphere"]())


def test_transform_still_transforms_rays_and_now_boxes() -> None:
    r = rt.transform(_ray(), rt.translation(1, 2, 3))
    assert isinstance(r, rt.Ray) and r.origin == rt.point(1, 2, -2)
    box = rt.transform(_unit_box(), rt.scaling(2, 3, 4))
    assert box == rt.bounding_box(min=rt.point(-2, -3, -4), max=rt.point(2, 3, 4))
    with pytest.raises(TypeError, match=r"transform\(BoundingBox\): expected a 4x4 matrix"):
        rt.transform(_unit_box(), rt.identity_matrix.rows)


def test_the_empty_box_stays_empty_whatever_happens_to_it() -> None:
    assert rt.transform(EMPTY, rt.scaling(2, 2, 2)) == EMPTY
    assert rt.split_bounds(EMPTY) == (EMPTY, EMPTY)
    assert not rt.intersects(EMPTY, _ray())
    assert not rt.box_contains_point(EMPTY, rt.point(0, 0, 0))


def test_a_shape_kind_without_its_own_box_is_everywhere() -> None:
    class Blob(rt.Sphere):
        __slots__ = ()

        def local_bounds(self) -> BoundingBox:  # as a kind that never wrote one
            return Shape.local_bounds(self)

    g = rt.group()
    rt.add_child(g, Blob())
    box = rt.bounds_of(g)
    assert box.min == rt.point(-INF, -INF, -INF) and box.max == rt.point(INF, INF, INF)
    assert len(rt.intersect(g, _ray())) == 2  # so the group always asks it


# ----------------------------------------------------------------------------- dividing


def test_divide_stops_where_a_split_would_take_every_child() -> None:
    # five triangles at one point: every split puts them all on one side, for ever
    p = rt.point(1, 2, 3)
    g = rt.group()
    shapes = [rt.triangle(p, p, p) for _ in range(5)]
    for s in shapes:
        rt.add_child(g, s)
    rt.divide(g, 1)
    assert g.children == shapes and all(a is b for a, b in zip(g.children, shapes, strict=True))
    # two cylinders from y = 0 up for ever: the cut is at the finite end, and all go right
    g = rt.group()
    for _ in range(2):
        c = rt.cylinder()
        c.minimum = 0
        rt.add_child(g, c)
    rt.divide(g, 1)
    assert len(g.children) == 2 and all(isinstance(s, rt.Cylinder) for s in g.children)


def test_a_plane_stays_at_the_top_while_the_shapes_beside_it_are_divided() -> None:
    plane = rt.plane()
    g = rt.group()
    rt.add_child(g, plane)
    spheres = []
    for x in (-6, -3, 3, 6):
        s = rt.sphere()
        rt.set_transform(s, rt.translation(x, 1, 0))
        rt.add_child(g, s)
        spheres.append(s)
    rt.divide(g, 2)
    left, right = g.children[1], g.children[2]
    assert g.children[0] is plane and len(g.children) == 3  # cut at x = 0 (infinite x side)
    assert [leaf.children[0] for leaf in left.children] == spheres[:2]
    assert [leaf.children[0] for leaf in right.children] == spheres[2:]


def test_subgroups_are_made_of_the_groups_own_class() -> None:
    for name, api in APIS.items():
        g = api["group"]()
        for x in (-2, 2):
            s = api["sphere"]()
            api["set_transform"](s, api["translation"](x, 0, 0))
            api["add_child"](g, s)
        api["divide"](g, 1)
        assert [type(child) for child in g.children] == [type(g), type(g)], name


# ----------------------------------------------------------------------------- properties
# (derandomized and without an example database: the same examples on every run, no files)

coordinate = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
unit = st.floats(0, 1, allow_nan=False, allow_infinity=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False, allow_infinity=False)
factor = st.floats(0.2, 4, allow_nan=False, allow_infinity=False)
sign = st.sampled_from([-1.0, 1.0])


@st.composite
def transforms(draw: st.DrawFn) -> Matrix:
    """A random invertible transform: scale (any sign), three rotations, a shear, a move."""
    m = rt.scaling(*(draw(factor) * draw(sign) for _ in range(3)))
    m = rt.rotation_x(draw(angle)) * m
    m = rt.rotation_y(draw(angle)) * m
    m = rt.rotation_z(draw(angle)) * m
    if draw(st.booleans()):
        m = rt.shearing(draw(unit), 0, 0, draw(unit), 0, 0) * m
    return rt.translation(draw(coordinate), draw(coordinate), draw(coordinate)) * m


@st.composite
def shapes_with_a_surface_point(draw: st.DrawFn) -> tuple[Any, Tuple]:
    """A shape of a random kind and a random point on its surface, in object space."""
    kind = draw(st.sampled_from(["sphere", "cube", "cylinder", "cone", "triangle"]))
    u, v = draw(unit), draw(unit)
    if kind == "sphere":
        theta, phi = math.pi * u, 2 * math.pi * v
        return rt.sphere(), rt.point(
            math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)
        )
    if kind == "cube":
        axis, side = draw(st.integers(0, 2)), draw(sign)
        xyz = [2 * u - 1, 2 * v - 1]
        xyz.insert(axis, side)
        return rt.cube(), rt.point(*xyz)
    if kind in ("cylinder", "cone"):
        shape = rt.cylinder() if kind == "cylinder" else rt.cone()
        low, high = sorted((draw(coordinate), draw(coordinate)))
        shape.minimum, shape.maximum = low, high
        y = low + (high - low) * u
        radius = 1.0 if kind == "cylinder" else abs(y)
        return shape, rt.point(
            radius * math.cos(2 * math.pi * v), y, radius * math.sin(2 * math.pi * v)
        )
    corners = [rt.point(draw(coordinate), draw(coordinate), draw(coordinate)) for _ in range(3)]
    if u + v > 1:
        u, v = 1 - u, 1 - v
    p1, p2, p3 = corners
    return rt.triangle(p1, p2, p3), p1 + (p2 - p1) * u + (p3 - p1) * v


def _contains(box: BoundingBox, p: Tuple) -> bool:
    """``box_contains_point`` with room for the rounding of the two transforms."""
    tolerance = 1e-9 * (1 + max(abs(p.x), abs(p.y), abs(p.z)))
    lo, hi = box.min, box.max
    return all(
        a - tolerance <= c <= b + tolerance
        for a, c, b in ((lo.x, p.x, hi.x), (lo.y, p.y, hi.y), (lo.z, p.z, hi.z))
    )


@settings(max_examples=examples(150), deadline=None)
@given(shapes_with_a_surface_point(), transforms(), transforms())
def test_a_transformed_shapes_box_contains_its_surface(
    shape_and_point: tuple[Any, Tuple], inner: Matrix, outer: Matrix
) -> None:
    shape, local = shape_and_point
    rt.set_transform(shape, inner)
    assert _contains(rt.parent_space_bounds_of(shape), inner * local)
    g = rt.group()
    rt.set_transform(g, outer)
    rt.add_child(g, shape)
    assert _contains(rt.parent_space_bounds_of(g), outer * (inner * local))


@settings(max_examples=examples(100), deadline=None)
@given(
    st.tuples(coordinate, coordinate, coordinate),
    st.tuples(coordinate, coordinate, coordinate),
    transforms(),
)
def test_transforming_a_box_is_boxing_its_transformed_corners(
    a: tuple[float, float, float], b: tuple[float, float, float], m: Matrix
) -> None:
    lo = rt.point(*(min(x, y) for x, y in zip(a, b, strict=True)))
    hi = rt.point(*(max(x, y) for x, y in zip(a, b, strict=True)))
    corners = [
        m * rt.point(x, y, z) for x in (lo.x, hi.x) for y in (lo.y, hi.y) for z in (lo.z, hi.z)
    ]
    box = transform_box(BoundingBox(lo, hi), m)
    for name in ("x", "y", "z"):
        values = [getattr(c, name) for c in corners]
        assert getattr(box.min, name) == pytest.approx(min(values), abs=1e-9)
        assert getattr(box.max, name) == pytest.approx(max(values), abs=1e-9)


@st.composite
def scenes(draw: st.DrawFn) -> list[tuple[str, Matrix, tuple[Tuple, ...]]]:
    """1 to 24 shapes (spheres, cubes, closed cylinders, triangles), each as (kind,
    transform, triangle corners)."""
    found = []
    for _ in range(draw(st.integers(1, 24))):
        kind = draw(st.sampled_from(["sphere", "cube", "cylinder", "triangle"]))
        corners = tuple(
            rt.point(draw(coordinate), draw(coordinate), draw(coordinate)) for _ in range(3)
        )
        found.append((kind, draw(transforms()), corners))
    return found


def _build(api: Mapping[str, Any], scene: list[tuple[str, Matrix, tuple[Tuple, ...]]]) -> Any:
    g = api["group"]()
    for kind, m, corners in scene:
        s = api["triangle"](*corners) if kind == "triangle" else api[kind]()
        if kind == "cylinder":
            s.minimum, s.maximum, s.closed = -1, 1, True
        api["set_transform"](s, m)
        api["add_child"](g, s)
    return g


def _ts_and_shapes(xs: list[Any]) -> list[tuple[float, int]]:
    return sorted((i.t, id(i.object)) for i in xs)


@pytest.mark.parametrize("variant", list(APIS))
@settings(max_examples=examples(40), deadline=None)
@given(
    scene=scenes(),
    origin=st.tuples(coordinate, coordinate, coordinate),
    direction=st.tuples(unit, unit, unit, sign, sign, sign),
    threshold=st.integers(1, 8),
)
def test_dividing_a_group_never_changes_what_a_ray_hits(
    variant: str,
    scene: list[tuple[str, Matrix, tuple[Tuple, ...]]],
    origin: tuple[float, float, float],
    direction: tuple[float, ...],
    threshold: int,
) -> None:
    # A direction of some length: with all three components within EPSILON of zero the
    # cube (chapter 12) reports a miss as two intersections at t = -∞, which a box drops.
    api = APIS[variant]
    dx, dy, dz, sx, sy, sz = direction
    assume(max(dx, dy, dz) >= 0.1)
    v = api["normalize"](api["vector"](dx * sx, dy * sy, dz * sz))
    r = api["ray"](api["point"](*origin), v)
    g = _build(api, scene)
    before = api["intersect"](g, r)
    api["divide"](g, threshold)
    after = api["intersect"](g, r)
    assert _ts_and_shapes(after) == _ts_and_shapes(before)
    first, second = api["hit"](before), api["hit"](after)
    if first is None or second is None:
        assert first is None and second is None
    else:  # the same hit, or one at the same t (two shapes can touch there)
        assert second.t == first.t
        assert any(i.object is second.object and i.t == first.t for i in before)


special = st.sampled_from([0.0, -0.0, 1.0, -1.0, 2.0, EPSILON / 2, -EPSILON / 2, 5e-324])
axis_value = st.one_of(special, coordinate)
box_end = st.one_of(st.sampled_from([-INF, INF, 0.0, 1.0, -1.0]), coordinate)


@settings(max_examples=examples(300), deadline=None)
@given(
    st.tuples(box_end, box_end, box_end, box_end, box_end, box_end),
    st.tuples(axis_value, axis_value, axis_value),
    st.tuples(axis_value, axis_value, axis_value),
)
def test_prealloc_tests_a_box_as_the_reference_does(
    ends: tuple[float, ...], origin: tuple[float, ...], direction: tuple[float, ...]
) -> None:
    box = BoundingBox(rt.point(*ends[:3]), rt.point(*ends[3:]))
    r = rt.ray(rt.point(*origin), rt.vector(*direction))
    ray_buffer = [*origin, 1.0, *direction, 0.0]
    assert meets_box(box_buffer(box), ray_buffer, EPSILON) == ray_meets_box(box, r)


# ----------------------------------------------------------------------------- variants


def test_the_reference_recomputes_a_groups_box_and_cached_keeps_it() -> None:
    naive = rt.group()
    rt.add_child(naive, rt.sphere())
    assert naive.local_bounds() is not naive.local_bounds()  # computed afresh, every time

    api = APIS["cached"]
    g, inner, s = api["group"](), api["group"](), api["sphere"]()
    api["add_child"](inner, s)
    api["add_child"](g, inner)
    box = g.local_bounds()
    assert g.local_bounds() is box and isinstance(g, CachedComposite)
    assert box.max == rt.point(1, 1, 1)


@pytest.mark.parametrize(
    ("change", "expected_max"),
    [
        (lambda api, g, inner, s: api["set_transform"](s, api["translation"](5, 0, 0)), 6),
        (lambda api, g, inner, s: api["set_transform"](inner, api["scaling"](3, 3, 3)), 3),
        (lambda api, g, inner, s: setattr(s, "transform", api["scaling"](2, 2, 2)), 2),
        (lambda api, g, inner, s: api["add_child"](inner, _far_cube(api)), 11),
        (lambda api, g, inner, s: setattr(inner, "children", []), -INF),
        (lambda api, g, inner, s: api["make_subgroup"](g, [_far_cube(api)]), 11),
    ],
)
def test_cached_forgets_a_kept_box_when_anything_below_it_changes(
    change: Callable[..., None], expected_max: float
) -> None:
    api = APIS["cached"]
    g, inner, s = api["group"](), api["group"](), api["sphere"]()
    api["add_child"](inner, s)
    api["add_child"](g, inner)
    assert g.local_bounds().max.x == 1 and inner.local_bounds().max.x == 1
    change(api, g, inner, s)
    assert g.local_bounds().max.x == expected_max
    assert g.local_bounds() == rt.Group.local_bounds(g)  # the reference's, from scratch


def _far_cube(api: Mapping[str, Any]) -> Any:
    c = api["cube"]()
    api["set_transform"](c, api["translation"](10, 0, 0))
    return c


def test_cached_keeps_a_csg_shapes_box_and_robust_inherits_it() -> None:
    api = APIS["cached"]
    left, right = api["sphere"](), api["cube"]()
    shape = api["csg"]("union", left, right)
    assert shape.local_bounds() is shape.local_bounds()
    right.transform = api["translation"](0, 4, 0)
    assert shape.local_bounds().max.y == 5
    for reference in (rt.Group, rt.CSG):
        assert issubclass(CACHED_CLASSES[reference], CachedComposite)
        assert issubclass(ROBUST_CLASSES[reference], CachedComposite)
    assert not issubclass(CACHED_CLASSES[rt.Sphere], CachedComposite)


def test_prealloc_builds_a_groups_box_once_with_its_records() -> None:
    api = APIS["cached"]
    g = api["group"]()
    s = api["sphere"]()
    api["set_transform"](s, api["translation"](0, 2, 0))
    api["add_child"](g, s)
    rec = TraceContext(EPSILON).record(g)
    assert isinstance(rec, GroupRecord)
    assert rec.box == [-1.0, 1.0, -1.0, 1.0, 3.0, 1.0]
    assert TraceContext(EPSILON).record(api["group"]()).box is None  # empty: never met


def test_the_learners_stubs_take_the_books_arguments() -> None:
    assert stub_source("bounding_box").startswith("def bounding_box(min=None, max=None):")
    assert stub_source("divide").startswith("def divide(shape, threshold):")
    assert stub_source("transform").startswith("def transform(value, m):")


# ----------------------------------------------------------------------------- scene loader


def _row_of_spheres(count: int) -> str:
    """A scene: a plane and a group of ``count`` spheres along x, 3 apart."""
    children = "".join(
        f"    - add: sphere\n      transform:\n        - [translate, {3 * i}, 1, 0]\n"
        for i in range(count)
    )
    return (
        "- add: camera\n  width: 12\n  height: 8\n  field-of-view: 1.2\n"
        "  from: [13.5, 6, -20]\n  to: [13.5, 1, 0]\n  up: [0, 1, 0]\n"
        "- add: light\n  at: [-10, 10, -10]\n  intensity: [1, 1, 1]\n"
        "- add: plane\n"
        f"- add: group\n  children:\n{children}"
    )


def test_the_python_tracers_divide_top_level_groups_and_note_it() -> None:
    # ten spheres from x = -1 to 28: cut at 13.5 into two subgroups of five (< 8 each)
    scene = load_scene_text(_row_of_spheres(10), APIS["cached"], variant="cached")
    assert DIVIDE_THRESHOLD == 8
    world = load_variant("cached").world_for(scene)
    assert scene.notes == [
        "divide (threshold 8) on 1 top-level group, OBJ model or CSG shape: 2 subgroups made "
        "(groups: 1 before, 3 after)",
    ]
    group = world.objects[1]
    assert [len(sub.children) for sub in group.children] == [5, 5]
    assert scene.resized(4, 3).notes == scene.notes
    assert len(scene.world.objects[1].children) == 10  # the book's world as the file has it


def test_the_python_tracers_note_when_there_is_nothing_to_divide() -> None:
    small = load_scene_text(_row_of_spheres(7), APIS["naive"], variant="naive")
    world = load_variant("naive").world_for(small)
    assert small.notes == [
        "divide (threshold 8) on 1 top-level group, OBJ model or CSG shape: no group had 8 "
        "children or more; nothing to divide",
    ]
    assert len(world.objects[1].children) == 7
    assert divide_groups([rt.sphere()], APIS["naive"]["divide"], "naive") == ()  # no group
    assert divide_groups([rt.group()], None, "mine") == (
        "groups not divided: 'mine' has no divide() (the bonus chapter)",
    )


@pytest.mark.parametrize("variant", list(APIS))
def test_dividing_never_changes_the_picture(variant: str) -> None:
    api = APIS[variant]
    scene = load_scene_text(_row_of_spheres(12), api, variant=variant)
    whole = scene.book_world()
    assert len(whole.objects[1].children) == 12 and scene.notes == []
    divided = scene.book_world(divide=True)
    assert len(divided.objects[1].children) < 12
    images = [rt.canvas_to_rgb8(api["render"](scene.camera, w)) for w in (whole, divided)]
    assert images[0] == images[1]
    assert len(set(images[0])) > 2  # not a blank picture
