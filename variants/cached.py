"""``cached``: the Go write-up's first big win, inverse transforms computed once.

The reference inverts a transform every time it reads ``inverse_transform`` (chapters 5, 6,
10 and 14) and every pixel's ``ray_for_pixel`` inverts the camera's (chapter 7). Here the
inverse, and for shapes the inverse transpose used for normals, is computed when the
transform is set, and read back from a slot. The reference also recomputes a group's and a
CSG shape's bounding box (the bonus chapter 'Bounding boxes and hierarchies') from its whole
subtree every time a ray meets it; here the box is kept once computed, and forgotten when
anything below it changes. Everything else is the reference's.

Module API (``prealloc`` builds on it):

- ``CachedShape``, ``CachedPattern``: mixins whose ``transform`` property recomputes the cache
  when the transform is set (by the constructor, ``set_transform``, ``s.transform ← m``,
  ``set_pattern_transform`` or unpickling) and whose ``inverse_transform`` (and
  ``inverse_transpose``) read it back. A singular transform is accepted as in the reference
  and raises the reference's ``NotInvertibleError`` when its inverse is used.
- ``CachedComposite``: the mixin of groups and CSG shapes: ``CachedShape`` plus
  ``local_bounds`` kept in a slot. It is computed on first use, not when set (a group being
  filled would recompute it for every ``add_child``), and forgotten when any public
  attribute of the shape or of a shape below it is set: a transform, a cylinder's
  ``minimum``, a child's ``parent`` (``add_child``), a group's ``children`` (``divide``
  assigns the list). Changing a list in place (``g.children.append``) or a shape that is in
  two groups at once (only its ``parent`` is told) goes unnoticed, as the book never does.
- ``CachedCamera``: the camera; frozen, so its cache is built in ``__post_init__`` (which
  ``dataclasses.replace`` runs too, for ``c.transform ← m``).
- ``CACHED_CLASSES``: every concrete reference shape and pattern class (and ``Camera``) ->
  its cached twin. The twins are made by ``derive_class`` and are attributes of this module
  (``variants.cached.CachedSphere``), so they pickle for the pool.
- ``reference_classes(base)``: the concrete subclasses of ``base`` defined in ``raytracer``.
- ``derive_class(mixin, base, name, module, slots)``: one twin (usable for further layers).
- ``to_twins(value, twins)``: a reference object (shape tree, pattern, camera, world,
  material) rebuilt with twin classes; parents are kept consistent.
- ``twin_api(reference_api, twins)``: the reference API with every constructor returning
  twins; returns the API and the names it overrides.
- ``variant()``: the registry's factory (no options, no inner variant).
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
import sys
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import raytracer
from raytracer.api import naive_api
from raytracer.bounds import BoundingBox
from raytracer.camera import Camera
from raytracer.materials import Material
from raytracer.matrices import Matrix, inverse, transpose
from raytracer.patterns import Pattern
from raytracer.shapes.csg import CSG
from raytracer.shapes.group import Group
from raytracer.shapes.shape import Shape
from raytracer.tracer import Tracer
from raytracer.world import World
from variants.registry import Variant, check_options, reject_inner, tracer_variant

NAME = "cached"

_SHAPE_TRANSFORM: Any = Shape.__dict__["transform"]  # the reference's slot (member descriptor)
_PATTERN_TRANSFORM: Any = Pattern.__dict__["transform"]
# the reference's properties: what a singular transform falls back to (a clear error)
_REFERENCE_SHAPE_INVERSE: Any = Shape.__dict__["inverse_transform"].fget
_REFERENCE_SHAPE_INVERSE_T: Any = Shape.__dict__["inverse_transpose"].fget
_REFERENCE_PATTERN_INVERSE: Any = Pattern.__dict__["inverse_transform"].fget
_REFERENCE_CAMERA_INVERSE: Any = Camera.__dict__["inverse_transform"].fget


def _inverse_or_none(m: Any) -> Matrix | None:
    """The inverse of ``m``, or None when it has none (the reference raises at use)."""
    try:
        return inverse(m)
    except Exception:  # singular, or not a matrix: let the reference report it at use
        return None


class CachedShape:
    """Mixin for a reference shape class: caches ``inverse_transform`` and
    ``inverse_transpose`` when ``transform`` is set. The twin supplies the two slots."""

    __slots__ = ()
    _inverse: Matrix | None
    _inverse_transpose: Matrix | None

    @property
    def transform(self) -> Matrix:
        return _SHAPE_TRANSFORM.__get__(self)

    @transform.setter
    def transform(self, m: Matrix) -> None:
        _SHAPE_TRANSFORM.__set__(self, m)
        inv = _inverse_or_none(m)
        # setattr: the slots are the twin's (the mixin itself has none)
        setattr(self, "_inverse", inv)  # noqa: B010
        setattr(self, "_inverse_transpose", transpose(inv) if inv is not None else None)  # noqa: B010

    @property
    def inverse_transform(self) -> Matrix:
        inv = self._inverse
        return inv if inv is not None else _REFERENCE_SHAPE_INVERSE(self)

    @property
    def inverse_transpose(self) -> Matrix:
        inv_t = self._inverse_transpose
        return inv_t if inv_t is not None else _REFERENCE_SHAPE_INVERSE_T(self)

    def __setattr__(self, name: str, value: Any) -> None:
        super().__setattr__(name, value)
        if not name.startswith("_"):  # a public field: boxes above it may have changed
            _forget_bounds(self)


class CachedComposite(CachedShape):
    """Mixin for a reference group or CSG class: ``CachedShape`` plus ``local_bounds`` (the
    bonus chapter) kept once computed. The twin supplies the ``_bounds`` slot."""

    __slots__ = ()
    _bounds: BoundingBox | None

    def local_bounds(self) -> BoundingBox:
        box: BoundingBox | None = getattr(self, "_bounds", None)
        if box is None:
            box = super().local_bounds()  # type: ignore[misc]  # the reference's, once
            object.__setattr__(self, "_bounds", box)
        return box


def _forget_bounds(shape: Any) -> None:
    """Forget the kept box of ``shape`` and of every group or CSG shape above it."""
    while shape is not None:
        if isinstance(shape, CachedComposite):
            object.__setattr__(shape, "_bounds", None)
        shape = getattr(shape, "parent", None)  # unset while a twin is being built


class CachedPattern:
    """Mixin for a reference pattern class: caches ``inverse_transform`` when ``transform``
    is set. The twin supplies the slot."""

    __slots__ = ()
    _inverse: Matrix | None

    @property
    def transform(self) -> Matrix:
        return _PATTERN_TRANSFORM.__get__(self)

    @transform.setter
    def transform(self, m: Matrix) -> None:
        _PATTERN_TRANSFORM.__set__(self, m)
        setattr(self, "_inverse", _inverse_or_none(m))  # noqa: B010  (the twin's slot)

    @property
    def inverse_transform(self) -> Matrix:
        inv = self._inverse
        return inv if inv is not None else _REFERENCE_PATTERN_INVERSE(self)


@dataclass(frozen=True, slots=True)
class CachedCamera(Camera):
    """Chapter 7's camera with the inverse of its view transform computed once."""

    _inverse: Matrix | None = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_inverse", _inverse_or_none(self.transform))

    @property
    def inverse_transform(self) -> Matrix:
        inv = self._inverse
        return inv if inv is not None else _REFERENCE_CAMERA_INVERSE(self)


# ------------------------------------------------------------------- deriving the twins


def _import_reference_modules() -> None:
    """Import every module of ``raytracer`` so that every shape class is defined."""
    for info in pkgutil.walk_packages(raytracer.__path__, prefix="raytracer."):
        importlib.import_module(info.name)


def is_defined(cls: type) -> bool:
    """Whether ``cls`` is the class its module defines under its name. A class that
    ``@dataclass(slots=True)`` replaced is not (it makes a new class), yet some Python
    releases (3.11.2) keep the old one alive among its base's subclasses."""
    found: Any = sys.modules.get(cls.__module__)
    for part in cls.__qualname__.split("."):
        found = getattr(found, part, None)
    return found is cls


def reference_classes(base: type) -> list[type]:
    """Every concrete subclass of ``base`` defined in the reference (``raytracer.*``), in a
    stable order; subclasses defined elsewhere (twins, tests) are left out."""
    _import_reference_modules()
    found: dict[str, type] = {}
    stack: list[type] = [base]
    while stack:
        subclasses: list[type] = stack.pop().__subclasses__()
        for sub in subclasses:
            if sub.__module__.startswith("raytracer.") and is_defined(sub):
                stack.append(sub)
                if not inspect.isabstract(sub):
                    found[f"{sub.__module__}.{sub.__qualname__}"] = sub
    return [found[key] for key in sorted(found)]


def derive_class(
    mixin: type, base: type, name: str, module: str, slots: tuple[str, ...] = ()
) -> type:
    """``class NAME(mixin, base)`` with ``slots`` added, defined as if in ``module``.

    base: a slotted class (the mixin must have ``__slots__ = ()``); the caller stores the
    class as ``module.NAME`` so that pickle finds it.
    """
    namespace = {
        "__slots__": slots,
        "__module__": module,
        "__qualname__": name,
        "__doc__": f"{base.__name__} ({base.__module__}) with {mixin.__name__}.",
    }
    return type(base)(name, (mixin, base), namespace)


def _derive_twins() -> dict[type, type]:
    twins: dict[type, type] = {Camera: CachedCamera}
    layers = [
        (Shape, CachedShape, ("_inverse", "_inverse_transpose")),
        (Pattern, CachedPattern, ("_inverse",)),
    ]
    for base, mixin, slots in layers:
        for reference in reference_classes(base):
            name = f"Cached{reference.__name__}"
            if name in globals():
                raise RuntimeError(f"variants.cached: two reference classes named {name}")
            if issubclass(reference, Group | CSG):  # shapes whose box is their subtree's
                twin = derive_class(CachedComposite, reference, name, __name__, (*slots, "_bounds"))
            else:
                twin = derive_class(mixin, reference, name, __name__, slots)
            globals()[name] = twin
            twins[reference] = twin
    return twins


CACHED_CLASSES: Mapping[type, type] = _derive_twins()


# ------------------------------------------------------------------ converting to twins


class _Converter:
    """Rebuilds reference objects with twin classes, once each (``memo`` keeps the graph:
    a child's ``parent`` points at the rebuilt parent)."""

    def __init__(self, twins: Mapping[type, type]) -> None:
        self.twins = twins
        self.memo: dict[int, tuple[Any, Any]] = {}  # id(old) -> (old, new)

    def __call__(self, value: Any) -> Any:
        done = self.memo.get(id(value))
        if done is not None:
            return done[1]
        twin = self.twins.get(type(value))
        if twin is not None:
            return self._rebuild(value, twin)
        if isinstance(value, Shape):  # already a twin: re-parent it if its parent was rebuilt
            parent = self.memo.get(id(value.parent))
            if parent is not None:
                value.parent = parent[1]
            return value
        if isinstance(value, list):
            return [self(item) for item in value]
        if isinstance(value, Material) and value.pattern is not None:
            pattern = self(value.pattern)
            return (
                value if pattern is value.pattern else dataclasses.replace(value, pattern=pattern)
            )
        if isinstance(value, World):
            return World(self(value.objects), list(value.lights))
        return value

    def _rebuild(self, value: Any, twin: type) -> Any:
        params = getattr(type(value), "__dataclass_params__", None)
        if params is not None and params.frozen:  # a value (the camera): rebuild by __init__
            init = {
                f.name: self(getattr(value, f.name)) for f in dataclasses.fields(value) if f.init
            }
            new = twin(**init)
            self.memo[id(value)] = (value, new)
            return new
        new = object.__new__(twin)
        self.memo[id(value)] = (value, new)  # before the fields: children point back here
        for name in _slot_names(type(value)):
            if hasattr(value, name):
                setattr(new, name, self(getattr(value, name)))
        return new


def _slot_names(cls: type) -> list[str]:
    """Every slot of ``cls`` and its bases, base classes first."""
    names: list[str] = []
    for klass in reversed(cls.__mro__):
        slots = klass.__dict__.get("__slots__", ())
        for name in (slots,) if isinstance(slots, str) else slots:
            if name not in ("__dict__", "__weakref__") and name not in names:
                names.append(name)
    return names


def to_twins(value: Any, twins: Mapping[type, type] = CACHED_CLASSES) -> Any:
    """``value`` with every reference shape, pattern and camera in it rebuilt as its twin:
    shape trees (groups, CSG, parents), worlds, materials' patterns, lists. Objects that
    are already twins are kept (and re-parented under a rebuilt parent)."""
    return _Converter(twins)(value)


# --------------------------------------------------------------------------- the API

WORLD_BUILDERS = ("default_world",)  # return worlds full of reference shapes


def _return_class(function: Callable[..., Any]) -> type | None:
    """The class a function's return annotation names, if it is one."""
    try:
        returned = typing.get_type_hints(function).get("return")
    except Exception:  # an annotation only importable for type checkers
        return None
    return returned if isinstance(returned, type) else None


def _makes_twins(function: Any, twins: Mapping[type, type]) -> bool:
    returned = _return_class(function) if callable(function) else None
    return returned is not None and any(issubclass(twin, returned) for twin in twins.values())


def _returning_twins(
    function: Callable[..., Any], twins: Mapping[type, type]
) -> Callable[..., Any]:
    def constructor(*args: Any, **kwargs: Any) -> Any:
        return to_twins(function(*args, **kwargs), twins)

    constructor.__name__ = function.__name__
    constructor.__qualname__ = function.__qualname__
    constructor.__doc__ = f"{function.__doc__}\n\n(Returns {NAME} twins.)"
    constructor.__wrapped__ = function  # type: ignore[attr-defined]
    return constructor


def _factory_hooks(function: Any) -> list[str]:
    """The ``make_NAME`` keyword parameters of a function (``parse_obj_file``'s hooks)."""
    try:
        parameters = inspect.signature(function).parameters.values()
    except (TypeError, ValueError):
        return []
    return [p.name for p in parameters if p.kind is p.KEYWORD_ONLY and p.name.startswith("make_")]


def _with_hooks(function: Callable[..., Any], hooks: dict[str, Any]) -> Callable[..., Any]:
    def hooked(*args: Any, **kwargs: Any) -> Any:
        return function(*args, **{**hooks, **kwargs})

    hooked.__name__ = function.__name__
    hooked.__qualname__ = function.__qualname__
    hooked.__doc__ = f"{function.__doc__}\n\n(Builds {NAME} twins through its factory hooks.)"
    hooked.__wrapped__ = function  # type: ignore[attr-defined]
    return hooked


def twin_api(
    reference_api: Mapping[str, Any], twins: Mapping[type, type] = CACHED_CLASSES
) -> tuple[dict[str, Any], frozenset[str]]:
    """``reference_api`` with its constructors returning twins, and the names overridden.

    A constructor is a function whose return annotation is a class with a twin (sphere,
    plane, cube, group, csg, triangle, obj_to_group, the patterns, camera ...) or one of
    ``WORLD_BUILDERS``; its result goes through ``to_twins``. A function with ``make_NAME``
    keyword hooks (``parse_obj_file``) gets the twin-making ``NAME`` constructors as hooks.
    """
    api = dict(reference_api)
    overridden: set[str] = set()
    for name, function in reference_api.items():
        if name in WORLD_BUILDERS or _makes_twins(function, twins):
            api[name] = _returning_twins(function, twins)
            overridden.add(name)
    for name, function in reference_api.items():
        hooks = {
            hook: api[hook.removeprefix("make_")]
            for hook in _factory_hooks(function)
            if hook.removeprefix("make_") in overridden
        }
        if hooks:
            api[name] = _with_hooks(function, hooks)
            overridden.add(name)
    return api, frozenset(overridden)


def cached_api() -> tuple[dict[str, Any], frozenset[str]]:
    """The cached variant's API and the book names it overrides."""
    return twin_api(naive_api(), CACHED_CLASSES)


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: no options, no inner variant."""
    reject_inner(NAME, inner)
    check_options(NAME, options)
    api, overrides = cached_api()
    return tracer_variant(
        NAME,
        "inverse transforms of shapes, patterns and the camera computed once, when set",
        Tracer(),  # the reference's pipeline: what changes is the shapes and the camera
        api=api,
        overrides=overrides,
        base="naive",
    )
