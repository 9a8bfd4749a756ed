"""The ``cached`` variant: a twin for every reference shape and pattern class, inverses
computed once when the transform is set, constructors that return twins, pickling."""

from __future__ import annotations

import dataclasses
import pickle
import sys
from typing import Any

import pytest

import raytracer
from raytracer.camera import Camera
from raytracer.matrices import NotInvertibleError, inverse, transpose
from raytracer.patterns import Pattern, StripePattern
from raytracer.shapes.group import Group
from raytracer.shapes.shape import Shape
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.triangle import Triangle
from variants import cached
from variants.cached import CACHED_CLASSES, CachedPattern, CachedShape, reference_classes
from variants.registry import load_variant

API = load_variant("cached").api


def twin(reference: type) -> Any:
    """The cached twin of a reference class."""
    return CACHED_CLASSES[reference]


def _reference_subclasses(base: type) -> set[type]:
    """Every concrete subclass of ``base`` in ``raytracer``, found independently of
    ``variants.cached`` (walking the class tree after importing the whole package). A class
    counts when its module names it: the class a ``@dataclass(slots=True)`` replaced stays
    among the subclasses in some Python releases (3.11.2), but nothing can make one."""
    found: set[type] = set()
    stack: list[type] = [base]
    while stack:
        subclasses: list[type] = stack.pop().__subclasses__()
        for sub in subclasses:
            if sub.__module__.startswith("raytracer."):
                stack.append(sub)
                named = getattr(sys.modules[sub.__module__], sub.__qualname__, None)
                if named is sub and not getattr(sub, "__abstractmethods__", None):
                    found.add(sub)
    return found


@pytest.mark.parametrize(("base", "mixin"), [(Shape, CachedShape), (Pattern, CachedPattern)])
def test_every_reference_class_has_a_cached_twin_that_pickles_by_name(
    base: type, mixin: type
) -> None:
    reference_classes(base)  # imports every raytracer module
    expected = _reference_subclasses(base)
    assert expected, f"no concrete {base.__name__} classes found"
    missing = sorted(cls.__name__ for cls in expected if cls not in CACHED_CLASSES)
    assert not missing, f"reference classes without a cached twin: {missing}"
    for reference in expected:
        twin = CACHED_CLASSES[reference]
        assert issubclass(twin, reference) and issubclass(twin, mixin)
        assert getattr(cached, twin.__name__) is twin and twin.__module__ == "variants.cached"


def test_the_camera_has_a_twin_too() -> None:
    assert issubclass(CACHED_CLASSES[Camera], Camera)


@pytest.mark.parametrize(
    "name",
    [
        "sphere", "glass_sphere", "plane", "cube", "cylinder", "cone", "group", "test_shape",
        "stripe_pattern", "gradient_pattern", "ring_pattern", "checkers_pattern", "test_pattern",
        "camera", "default_world", "triangle", "smooth_triangle", "csg", "parse_obj_file",
        "obj_to_group",
    ],
)  # fmt: skip
def test_every_constructor_is_overridden(name: str) -> None:
    if name not in raytracer.api.naive_api():
        pytest.fail(f"the reference has no {name}() yet")
    assert name in load_variant("cached").overrides
    assert API[name] is not raytracer.api.naive_api()[name]


def _point(x: float, y: float, z: float) -> Any:
    return API["point"](x, y, z)


def _vector(x: float, y: float, z: float) -> Any:
    return API["vector"](x, y, z)


NAIVE = load_variant("naive").api


def _arguments(api: Any) -> dict[str, tuple[Any, ...]]:
    """Arguments for each constructor, built through ``api`` itself."""
    white, black = api["color"](1, 1, 1), api["color"](0, 0, 0)
    p1, p2, p3 = api["point"](0, 1, 0), api["point"](-1, 0, 0), api["point"](1, 0, 0)
    n1, n2, n3 = api["vector"](0, 1, 0), api["vector"](-1, 0, 0), api["vector"](1, 0, 0)
    return {
        **{name: () for name in ("sphere", "glass_sphere", "plane", "cube", "cylinder")},
        **{name: () for name in ("cone", "group", "test_shape", "test_pattern")},
        **{f"{kind}_pattern": (white, black) for kind in ("stripe", "gradient", "ring")},
        "checkers_pattern": (white, black),
        "triangle": (p1, p2, p3),
        "smooth_triangle": (p1, p2, p3, n1, n2, n3),
        "csg": ("union", api["sphere"](), api["cube"]()),
        "camera": (20, 10, 1.0),
    }


def test_constructors_return_twins_equal_in_value_to_the_reference() -> None:
    mine_arguments, their_arguments = _arguments(API), _arguments(NAIVE)
    for name, arguments in mine_arguments.items():
        mine: Any = API[name](*arguments)
        theirs: Any = NAIVE[name](*their_arguments[name])
        assert type(mine) is twin(type(theirs)), name
        for f in dataclasses.fields(theirs):
            if f.name == "parent":
                continue
            a, b = getattr(mine, f.name), getattr(theirs, f.name)
            if isinstance(b, Shape):
                assert type(a) is twin(type(b)), f"{name}.{f.name}"
            else:
                assert a == b, f"{name}.{f.name}"
        assert mine.inverse_transform == inverse(mine.transform)


def test_glass_sphere_keeps_its_material() -> None:
    glass = API["glass_sphere"]()
    assert (glass.material.transparency, glass.material.refractive_index) == (1.0, 1.5)


def test_the_inverse_is_computed_when_the_transform_is_set_and_read_back_after() -> None:
    s = API["sphere"]()
    m = API["translation"](1, 2, 3) * API["scaling"](2, 2, 2)
    API["set_transform"](s, m)
    first = s.inverse_transform
    assert first == inverse(m) and s.inverse_transpose == transpose(inverse(m))
    assert s.inverse_transform is first  # the same object: not recomputed
    s.transform = API["rotation_y"](0.5)  # the book's s.transform ← ...
    assert s.inverse_transform == inverse(API["rotation_y"](0.5))
    assert s.transform == API["rotation_y"](0.5)

    p = API["stripe_pattern"](API["color"](1, 1, 1), API["color"](0, 0, 0))
    API["set_pattern_transform"](p, m)
    assert p.inverse_transform == inverse(m) and p.inverse_transform is p.inverse_transform


def test_the_camera_cache_follows_a_functional_update_of_its_transform() -> None:
    c = API["camera"](11, 11, 1.5)
    view = API["view_transform"](_point(0, 0, -5), _point(0, 0, 0), _vector(0, 1, 0))
    moved = dataclasses.replace(c, transform=view)  # what ``c.transform ← ...`` does
    assert type(moved) is type(c) and moved.inverse_transform == inverse(view)
    assert moved.inverse_transform is moved.inverse_transform
    assert API["ray_for_pixel"](moved, 5, 5) == raytracer.ray_for_pixel(
        raytracer.Camera(11, 11, 1.5, view), 5, 5
    )


def test_a_singular_transform_fails_as_in_the_reference_when_it_is_used() -> None:
    s = API["sphere"]()
    with pytest.raises(NotInvertibleError, match=r"set_transform\(CachedSphere\)"):
        API["set_transform"](s, API["scaling"](0, 1, 1))
    s.transform = API["scaling"](0, 1, 1)  # allowed, as in the reference
    with pytest.raises(NotInvertibleError, match="determinant 0"):
        API["intersect"](s, API["ray"](_point(0, 0, -5), _vector(0, 0, 1)))
    s.transform = API["scaling"](2, 2, 2)
    assert len(API["intersect"](s, API["ray"](_point(0, 0, -5), _vector(0, 0, 1)))) == 2


def test_twins_pickle_with_their_caches_and_parents() -> None:
    g = API["group"]()
    API["set_transform"](g, API["rotation_y"](0.7))
    s = API["sphere"]()
    API["set_transform"](s, API["translation"](5, 0, 0))
    API["add_child"](g, s)
    copy = pickle.loads(pickle.dumps(g))
    child = copy.children[0]
    assert type(copy) is type(g) and child.parent is copy
    assert child.inverse_transform == s.inverse_transform
    assert copy.inverse_transform == g.inverse_transform
    c = API["camera"](10, 10, 1.0)
    assert pickle.loads(pickle.dumps(c)).inverse_transform == c.inverse_transform


def test_csg_and_obj_groups_point_their_children_at_the_twin_parent() -> None:
    left, right = API["sphere"](), API["cube"]()
    shape = API["csg"]("difference", left, right)
    assert left.parent is shape and right.parent is shape
    assert shape.left is left and shape.right is right

    parser = API["parse_obj_file"](
        "v -1 1 0\nv -1 0 0\nv 1 0 0\nv 1 1 0\ng First\nf 1 2 3\ng Second\nf 1 3 4\n"
    )
    first = parser.groups["First"]
    assert type(first) is twin(Group)
    assert type(first.children[0]) is twin(Triangle)
    assert first.children[0].parent is first
    whole = API["obj_to_group"](parser)
    assert type(whole) is twin(Group) and first.parent is whole


def test_to_twins_rebuilds_a_reference_tree_keeping_parents() -> None:
    g = raytracer.group()
    inner = raytracer.group()
    s = raytracer.sphere()
    raytracer.add_child(inner, s)
    raytracer.add_child(g, inner)
    m = raytracer.material(
        pattern=raytracer.stripe_pattern(raytracer.color(1, 1, 1), raytracer.color(0, 0, 0))
    )
    s.material = m
    rebuilt = cached.to_twins(g)
    twin_inner = rebuilt.children[0]
    twin_sphere = twin_inner.children[0]
    assert type(twin_sphere) is twin(Sphere) and twin_sphere.parent is twin_inner
    assert twin_inner.parent is rebuilt
    assert type(twin_sphere.material.pattern) is twin(StripePattern)
    assert s.parent is inner  # the reference tree is left alone


def test_the_default_world_holds_twins_with_the_books_values() -> None:
    w = API["default_world"]()
    reference = raytracer.default_world()
    assert all(type(obj) is twin(Sphere) for obj in w.objects)
    for mine, theirs in zip(w.objects, reference.objects, strict=True):
        assert mine.transform == theirs.transform and mine.material == theirs.material
    assert w.light == reference.light
