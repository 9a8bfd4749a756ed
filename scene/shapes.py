"""Shapes (chapters 5, 9, 12-16) as the scene format writes them.

Reading a ``- add: ...`` mapping gives a ``ShapeSpec``: a checked, fully resolved description
(names looked up, transforms multiplied, OBJ path found) that builds fresh shapes through the
variant's API as often as it is added. ``- add: NAME`` starts from a defined shape: its keys
override the definition's, and its transform is applied after the definition's.

A material or ``shadow: false`` on a group, an OBJ model or a CSG applies to every shape
inside it that does not set its own (the book's groups have no material of their own to show).
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from yaml.nodes import MappingNode, Node

from scene.context import Context
from scene.materials import make_material, read_material
from scene.reader import Entry, line_of
from scene.transforms import read_transform, transform_problem

COMMON_KEYS = ("add", "transform", "material", "shadow")
KEYS: dict[str, tuple[str, ...]] = {
    "sphere": COMMON_KEYS,
    "plane": COMMON_KEYS,
    "cube": COMMON_KEYS,
    "cylinder": (*COMMON_KEYS, "min", "max", "closed"),
    "cone": (*COMMON_KEYS, "min", "max", "closed"),
    "group": (*COMMON_KEYS, "children"),
    "obj": (*COMMON_KEYS, "file"),
    "csg": (*COMMON_KEYS, "operation", "left", "right"),
}
SHAPES = tuple(KEYS)
# the book functions each kind of shape is built with
FACTORIES: dict[str, tuple[str, ...]] = {
    "sphere": ("sphere",),
    "plane": ("plane",),
    "cube": ("cube",),
    "cylinder": ("cylinder",),
    "cone": ("cone",),
    "group": ("group", "add_child"),
    "obj": ("parse_obj_file", "obj_to_group"),
    "csg": ("csg",),
}
OPERATIONS = ("union", "intersection", "difference")


@dataclass(frozen=True)
class ShapeSpec:
    """A resolved ``add:``. ``None`` means "not given" (the factory's default, or inherited).

    kind: one of ``SHAPES``; line: where it was added; label: how errors name it;
    transform: a matrix; material: book material properties; shadow: casts a shadow;
    minimum, maximum, closed: cylinders and cones; children: a group's; obj_file: the OBJ
    model's resolved path; operation, left, right: a CSG's; height: levels of shapes, itself
    included (a sphere 1, a group of spheres 2); count: the shapes it builds, itself included
    (an OBJ model counts 1 here, its triangles once it is parsed).
    """

    kind: str
    line: int
    label: str
    transform: Any = None
    material: dict[str, Any] | None = None
    shadow: bool | None = None
    minimum: float | None = None
    maximum: float | None = None
    closed: bool | None = None
    children: tuple[ShapeSpec, ...] = ()
    obj_file: Path | None = None
    operation: str | None = None
    left: ShapeSpec | None = None
    right: ShapeSpec | None = None
    height: int = 1
    count: int = 1


def _start(ctx: Context, node: Node, add_node: Node) -> ShapeSpec:
    """The spec an ``add:`` starts from: an empty one of a built-in kind, or a definition."""
    reader = ctx.reader
    name = reader.string(add_node, "add")
    line = line_of(node)
    if name in SHAPES:
        for function in FACTORIES[name]:
            ctx.need(function, add_node, f"the {name} at line {line}")
        return ShapeSpec(name, line, f"the {name} at line {line}")
    if name in ctx.scope and ctx.scope[name].kind == "shape":
        base: ShapeSpec = ctx.scope[name].value
        label = f"the {name!r} {base.kind} at line {line}"
        return dataclasses.replace(base, line=line, label=label)
    if name in ctx.scope:
        ctx.lookup(add_node, "shape", "add")  # names the definition and what it really is
    if name in ("camera", "light"):
        reader.fail(add_node, f"a {name} cannot be part of a shape; add it at the top level")
    defined = sorted(n for n, d in ctx.scope.items() if d.kind == "shape")
    also = f", or a defined shape: {', '.join(defined)}" if defined else ""
    reader.fail(
        add_node,
        f"unknown thing to add: {name!r}; known: camera, light, {', '.join(SHAPES)}{also}",
    )


def _child(ctx: Context, node: Node, what: str) -> ShapeSpec:
    if not isinstance(node, MappingNode):
        ctx.reader.fail(node, f"{what} must be a shape ('add: sphere' and its keys)")
    if ctx.depth >= ctx.limits.max_depth:  # the YAML reader's limit comes first; a guard
        ctx.reader.fail(
            node,
            f"groups and CSGs nested more than {ctx.limits.max_depth} deep; "
            f"{ctx.limits.depth_hint()}",
        )
    ctx.depth += 1
    try:
        return read_shape(ctx, node)
    finally:
        ctx.depth -= 1


def _obj_path(ctx: Context, entry: Entry) -> Path:
    name = ctx.reader.string(entry.value, "file")
    path = (ctx.reader.path.parent / name).resolve()
    from harness.make_meshes import provide  # a generated mesh is written when first needed

    if not path.is_file() and not provide(path):
        ctx.reader.fail(
            entry.value,
            f"OBJ file not found: {path} ('{name}' is read relative to the scene file's folder)",
        )
    return path


def read_shape(ctx: Context, node: Node) -> ShapeSpec:
    """Read one ``add:`` mapping (a shape, a defined shape, a child, a CSG operand)."""
    reader = ctx.reader
    entries = reader.mapping(node, "a shape")
    spec = _start(ctx, node, reader.require(entries, "add", node, "a shape"))
    reader.check_keys(entries, KEYS[spec.kind], f"a {spec.kind}")
    changes: dict[str, Any] = {}
    for key, entry in entries.items():
        value = entry.value
        what = f"{spec.label}: {key}"
        if key == "transform":
            m = read_transform(ctx, value, what)
            changes["transform"] = m if spec.transform is None else m * spec.transform
        elif key == "material":
            changes["material"] = read_material(ctx, value, what)
        elif key == "shadow":
            changes["shadow"] = reader.boolean(value, what)
        elif key in ("min", "max"):
            bound = reader.number(value, what, allow_infinity=True)
            changes["minimum" if key == "min" else "maximum"] = bound
        elif key == "closed":
            changes["closed"] = reader.boolean(value, what)
        elif key == "children":
            items = reader.sequence(value, what)
            changes["children"] = tuple(_child(ctx, item, f"{what} item") for item in items)
        elif key == "file":
            changes["obj_file"] = _obj_path(ctx, entry)
        elif key == "operation":
            operation = reader.string(value, what)
            if operation not in OPERATIONS:
                known = ", ".join(OPERATIONS)
                reader.fail(value, f"{what}: unknown operation {operation!r}; known: {known}")
            changes["operation"] = operation
        elif key in ("left", "right"):
            changes[key] = _child(ctx, value, what)
    spec = dataclasses.replace(spec, **changes)
    _check_bounds(ctx, spec, node, entries)
    _check_complete(ctx, spec, node, entries)
    return _measured(ctx, spec, node)


def _measured(ctx: Context, spec: ShapeSpec, node: Node) -> ShapeSpec:
    """``spec`` with its height and count; nesting or a count past the limits (through
    defined shapes added by name, which the YAML reader cannot see) is a ``SceneError``."""
    inside = [c for c in (*spec.children, spec.left, spec.right) if c is not None]
    height = 1 + max((c.height for c in inside), default=0)
    count = 1 + sum(c.count for c in inside)
    limits = ctx.limits
    if ctx.depth + height - 1 > limits.max_depth:
        ctx.reader.fail(
            node,
            f"{spec.label} nests groups and CSGs {ctx.depth + height - 1} deep (defined shapes "
            f"added by name included), more than the limit, {limits.max_depth}; "
            f"{limits.depth_hint()}",
        )
    if count > limits.max_shapes:
        ctx.reader.fail(
            node,
            f"{spec.label} holds {count:,} shapes (every copy of a defined shape counted), "
            f"more than the limit, {limits.max_shapes:,}; {limits.shapes_hint()}",
        )
    return dataclasses.replace(spec, height=height, count=count)


def _check_bounds(ctx: Context, spec: ShapeSpec, node: Node, entries: dict[str, Entry]) -> None:
    """A cylinder's or cone's ``min`` (default -infinity) must not be above its ``max``
    (default infinity): such a shape has no side (the book's functions allow it)."""
    low = -math.inf if spec.minimum is None else spec.minimum
    high = math.inf if spec.maximum is None else spec.maximum
    at = next((entries[k].value for k in ("min", "max") if k in entries), node)
    if low == math.inf or high == -math.inf:
        ctx.reader.fail(
            at,
            f"{spec.label}: min cannot be infinity, nor max -infinity; min and max are the "
            "heights (y) where it starts and ends",
        )
    if low > high:
        ctx.reader.fail(
            at,
            f"{spec.label}: min ({low:g}) is above max ({high:g}); min and max are the heights "
            "(y) where it starts and ends, min below max",
        )


def _check_complete(ctx: Context, spec: ShapeSpec, node: Node, entries: dict[str, Entry]) -> None:
    """What a kind needs (an OBJ file, a CSG's operands) and an invertible transform."""
    needed = {"obj": ("file",), "csg": ("operation", "left", "right")}.get(spec.kind, ())
    present = {"file": spec.obj_file, "operation": spec.operation, "left": spec.left,
               "right": spec.right}  # fmt: skip
    for key in needed:
        if present[key] is None:
            ctx.reader.fail(node, f"{spec.label} has no '{key}'; a {spec.kind} needs one")
    problem = None if spec.transform is None else transform_problem(ctx, spec.transform)
    if problem is not None:
        at = entries["transform"].key_node if "transform" in entries else node
        ctx.reader.fail(at, f"the transform of {spec.label} {problem}")


@dataclass(frozen=True)
class Inherited:
    """What a group, OBJ model or CSG passes down to the shapes inside it."""

    material: dict[str, Any] | None = None
    shadow: bool = True


def build_shape(ctx: Context, spec: ShapeSpec, inherited: Inherited = Inherited()) -> Any:
    """A new shape (with new children) from ``spec``, through the variant's API."""
    api = ctx.api
    if ctx.progress is not None:
        ctx.progress.advance()
    material = spec.material if spec.material is not None else inherited.material
    shadow = spec.shadow if spec.shadow is not None else inherited.shadow
    passed = Inherited(material, shadow)
    if spec.kind == "group":
        shape = api["group"]()
        for child in spec.children:
            api["add_child"](shape, build_shape(ctx, child, passed))
    elif spec.kind == "obj":
        shape = _build_obj(ctx, spec)
        _pass_down(ctx, shape, passed, spec)
    elif spec.kind == "csg":
        assert spec.left is not None and spec.right is not None
        left, right = build_shape(ctx, spec.left, passed), build_shape(ctx, spec.right, passed)
        shape = api["csg"](spec.operation, left, right)
    else:
        shape = api[spec.kind]()
        for name in ("minimum", "maximum", "closed"):
            if getattr(spec, name) is not None:
                setattr(shape, name, getattr(spec, name))
    _finish(ctx, shape, spec.transform, material, shadow, spec)
    return shape


def _finish(
    ctx: Context, shape: Any, transform: Any, material: dict[str, Any] | None, shadow: bool,
    spec: ShapeSpec,
) -> None:  # fmt: skip
    if transform is not None:
        try:
            ctx.api["set_transform"](shape, transform)
        except ValueError as error:  # already checked; a variant may be stricter
            ctx.reader.fail(spec.line, f"{spec.label}: {error}")
    if material is not None:
        shape.material = make_material(ctx, material)
    if not shadow:
        shape.casts_shadow = False


def _pass_down(ctx: Context, group: Any, inherited: Inherited, spec: ShapeSpec) -> None:
    """Give every shape inside an OBJ model's group the model's material (one material
    value, made once, shared by every triangle) and shadow."""
    made = None if inherited.material is None else make_material(ctx, inherited.material)
    stack = list(getattr(group, "children", ()))
    while stack:
        child = stack.pop()
        if made is not None:
            child.material = made
        if not inherited.shadow:
            child.casts_shadow = False
        stack.extend(getattr(child, "children", ()))


def _build_obj(ctx: Context, spec: ShapeSpec) -> Any:
    """Chapter 15: the OBJ model's triangles in a group (``parse_obj_file``, ``obj_to_group``)."""
    assert spec.obj_file is not None
    try:
        text = spec.obj_file.read_text(encoding="utf-8", errors="replace")
    except OSError as error:
        ctx.reader.fail(
            spec.line, f"{spec.label}: cannot read OBJ file {spec.obj_file}: {error.strerror}"
        )
    known = ctx.triangles.get(spec.obj_file)
    if known is not None:  # parsed before: count its triangles before parsing it again
        ctx.count_shapes(known, spec.line, f"the {known:,} triangles of {spec.label}")
    api = ctx.api
    parse, to_group = api["parse_obj_file"], api["obj_to_group"]
    factories = {
        "make_triangle": api.get("triangle"),
        "make_smooth_triangle": api.get("smooth_triangle"),
        "make_group": api.get("group"),
        "source": str(spec.obj_file),
        "require_faces": True,  # a model without a face would draw nothing
    }
    try:
        parser = parse(text, **_accepted(parse, factories))
    except ValueError as error:
        ctx.reader.fail(spec.line, f"the OBJ file of {spec.label} is broken: {error}")
    if known is None:
        triangles = int(getattr(parser, "triangles", 0))
        ctx.triangles[spec.obj_file] = triangles
        ctx.count_shapes(triangles, spec.line, f"the {triangles:,} triangles of {spec.label}")
    skipped = getattr(parser, "degenerate_triangles", 0)
    if skipped:
        first = getattr(parser, "first_degenerate_line", 0)
        ctx.notes.append(
            f"{spec.obj_file}: {skipped} degenerate triangle{'s' if skipped > 1 else ''} "
            f"(zero area) skipped, the first at line {first}"
        )
    return to_group(parser, **_accepted(to_group, {"make_group": api.get("group")}))


def _accepted(function: Callable[..., Any], keywords: dict[str, Any]) -> dict[str, Any]:
    """The keywords (a variant's own shape factories) that ``function`` takes."""
    try:
        parameters = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return {}
    takes_any = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())
    return {
        name: value
        for name, value in keywords.items()
        if value is not None and (takes_any or name in parameters)
    }
