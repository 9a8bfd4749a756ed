"""Shapes (chapters 5, 9, 12-16) as the scene format writes them.

Reading a ``- add: ...`` mapping gives a ``ShapeSpec``: a checked, fully resolved description
(names looked up, transforms multiplied, OBJ path found) of a shape, with nothing built: the
scene description's entity (pbrt's ``ShapeSceneEntity``). ``scene.build`` makes the book's
shapes of it through a variant's API, as often as it is added; a compiled or vectorized
tracer packs it directly. ``- add: NAME`` starts from a defined shape: its keys override the
definition's, and its transform is applied after the definition's.

The leaf kinds and their keys come from the kind table (``scene.kinds``); ``STRUCTURES`` are
the shapes that hold others. A material or ``shadow: false`` on a group, an OBJ model or a
CSG applies to every shape inside it that does not set its own (the book's groups have no
material of their own to show).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from yaml.nodes import MappingNode, Node

from groundwork.files import describe, read_bytes, resolved
from scene.context import Context
from scene.kinds import ADDABLE, BY_NAME
from scene.materials import read_material
from scene.reader import Entry, line_of
from scene.transforms import read_transform, transform_problem

if TYPE_CHECKING:  # an OBJ's reader only for a scene that reads one (``_mesh``)
    from scene.obj_mesh import Mesh

SCENE_ITEMS = ("camera", "light", "area_light", "sky", "render")
"""What a scene file adds besides shapes (``scene.loader`` reads each)."""
COMMON_KEYS = ("add", "transform", "material", "shadow")
STRUCTURES: dict[str, tuple[str, ...]] = {
    "group": ("children",),
    "obj": ("file",),
    "csg": ("operation", "left", "right"),
    "fir_branch": ("seed",),
}
"""The shapes that hold others (chapters 14, 15, 16; the christmas scene's fir branch,
``scene.fir_branch``) and their own keys."""
GROUPS = ("group", "fir_branch")
"""The structures a tracer builds as a group of their ``children``."""
KEYS: dict[str, tuple[str, ...]] = {
    **{k.name: (*COMMON_KEYS, *k.keys) for k in ADDABLE},
    **{name: (*COMMON_KEYS, *own) for name, own in STRUCTURES.items()},
}
SHAPES = tuple(KEYS)
# the book functions each kind of shape is built with (``scene.build``)
FACTORIES: dict[str, tuple[str, ...]] = {
    **{k.name: (k.name,) for k in ADDABLE},
    "group": ("group", "add_child"),
    "obj": ("group", "add_child", "triangle"),
    "csg": ("csg",),
    "fir_branch": ("group", "add_child", "cylinder", "triangle"),
}
OPERATIONS = ("union", "intersection", "difference")
# the most of an OBJ file read: a model within the default limit of shapes (5,000,000
# triangles) is some 300 MB of text
MAX_OBJ_BYTES = 1 << 30


@dataclass(frozen=True)
class ShapeSpec:
    """A resolved ``add:``. ``None`` means "not given" (the factory's default, or inherited).

    kind: one of ``SHAPES`` (a fir branch is a group of the children it is given: its stem
    and its needles); line: where it was added; label: how errors name it;
    transform: a matrix; material: book material properties; shadow: casts a shadow;
    params: a leaf kind's parameters given (by the shape's attribute, ``scene.kinds``), a
    fir branch's seed;
    children: a group's; obj_file: the OBJ model's resolved path; mesh: its triangles
    (``scene.obj_mesh``), read when the shape is added to the world; operation, left, right:
    a CSG's; height: levels of shapes, itself included (a sphere 1, a group of spheres 2);
    count: the shapes it builds, itself included (an OBJ model counts 1 here, its triangles
    once it is read).
    """

    kind: str
    line: int
    label: str
    transform: Any = None
    material: dict[str, Any] | None = None
    shadow: bool | None = None
    params: Mapping[str, Any] = field(default_factory=dict)
    children: tuple[ShapeSpec, ...] = ()
    obj_file: Path | None = None
    mesh: Mesh | None = field(default=None, repr=False)
    operation: str | None = None
    left: ShapeSpec | None = None
    right: ShapeSpec | None = None
    height: int = 1
    count: int = 1

    def parts(self) -> tuple[ShapeSpec, ...]:
        """The shapes directly inside it: a group's children, a CSG's operands."""
        return (*self.children, *(s for s in (self.left, self.right) if s is not None))


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
    if name in SCENE_ITEMS:
        reader.fail(add_node, f"a {name} cannot be part of a shape; add it at the top level")
    defined = sorted(n for n, d in ctx.scope.items() if d.kind == "shape")
    also = f", or a defined shape: {', '.join(defined)}" if defined else ""
    reader.fail(
        add_node,
        f"unknown thing to add: {name!r}; known: {', '.join((*SCENE_ITEMS, *SHAPES))}{also}",
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
    try:
        path = resolved(ctx.reader.path.parent / name)
    except OSError as error:
        ctx.reader.fail(entry.value, f"cannot read OBJ file {error.filename}: {error.strerror}")
    odd = describe(path)  # a named pipe would block the reader, a device never end
    if odd is not None:
        ctx.reader.fail(entry.value, f"cannot read OBJ file {path}: {odd}")
    provide = ctx.provide_mesh  # a generated mesh is written when first needed
    if not path.is_file() and not (provide is not None and provide(path)):
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
        elif spec.kind in BY_NAME and key in BY_NAME[spec.kind].keys:
            changes.setdefault("params", dict(spec.params))
            changes["params"].update(_parameter(ctx, spec.kind, key, value, what))
        elif key == "children":
            items = reader.sequence(value, what)
            changes["children"] = tuple(_child(ctx, item, f"{what} item") for item in items)
        elif key == "file":
            changes["obj_file"] = _obj_path(ctx, entry)
        elif key == "seed":
            changes["params"] = {"seed": reader.whole(value, what, 0, 2**63 - 1)}
        elif key == "operation":
            operation = reader.string(value, what)
            if operation not in OPERATIONS:
                known = ", ".join(OPERATIONS)
                reader.fail(value, f"{what}: unknown operation {operation!r}; known: {known}")
            changes["operation"] = operation
        elif key in ("left", "right"):
            changes[key] = _child(ctx, value, what)
    spec = dataclasses.replace(spec, **changes)
    if spec.kind == "fir_branch":  # drawn again for every add: its seed or line may change
        spec = dataclasses.replace(spec, children=_fir_branch(ctx, spec, node))
    _check_bounds(ctx, spec, node, entries)
    _check_complete(ctx, spec, node, entries)
    return _measured(ctx, spec, node)


def _parameter(ctx: Context, kind: str, key: str, value: Node, what: str) -> dict[str, Any]:
    """One parameter of a leaf kind (``scene.kinds``), by the shape's attribute."""
    parameter = next(p for p in BY_NAME[kind].parameters if p.key == key)
    if parameter.boolean:
        return {parameter.attribute: ctx.reader.boolean(value, what)}
    number = ctx.reader.number(value, what, allow_infinity=parameter.infinite)
    if parameter.above is not None and not number > parameter.above:
        ctx.reader.fail(
            value,
            f"{what} must be greater than {parameter.above:g} ({parameter.meaning}), "
            f"got {number:g}",
        )
    largest = parameter.largest
    if largest is not None and math.isfinite(number) and abs(number) > largest:
        ctx.reader.fail(
            value,
            f"{what} is too large for floating point ({number:g}): {parameter.overflow}; "
            f"expected a size up to {largest:g}" + (", or infinity" if parameter.infinite else ""),
        )
    return {parameter.attribute: number}


def _fir_branch(ctx: Context, spec: ShapeSpec, node: Node) -> tuple[ShapeSpec, ...]:
    """A fir branch's stem and needles (``scene.fir_branch``), drawn with its ``seed``
    (default: the line it is added at, so each branch of a file differs and the same file
    draws the same branches); a material given to the branch is its needles'."""
    # deferred: the needles' drawing (with Python's random) only where a scene adds a branch
    from scene.fir_branch import BARK, LENGTH, NEEDLE, NEEDLES, RADIUS, needle_mesh

    color = ctx.need("color", node, spec.label)

    def material(properties: dict[str, Any]) -> dict[str, Any]:
        return {**properties, "color": color(*properties["color"])}

    seed = spec.params.get("seed", spec.line)
    stem = ShapeSpec(
        "cylinder", spec.line, f"the stem of {spec.label}",
        transform=ctx.need("scaling", node, spec.label)(RADIUS, 1, RADIUS),
        material=material(BARK),
        params={"minimum": 0.0, "maximum": LENGTH, "closed": True},
    )  # fmt: skip
    needles = ShapeSpec(
        "obj", spec.line, f"the needles of {spec.label}",
        material=spec.material if spec.material is not None else material(NEEDLE),
        mesh=needle_mesh(seed, f"the needles of {spec.label} (seed {seed})"),
        count=1 + NEEDLES,
    )  # fmt: skip
    return stem, needles


def _measured(ctx: Context, spec: ShapeSpec, node: Node) -> ShapeSpec:
    """``spec`` with its height and count; nesting or a count past the limits (through
    defined shapes added by name, which the YAML reader cannot see) is a ``SceneError``."""
    inside = spec.parts()
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
    low = spec.params.get("minimum", -math.inf)
    high = spec.params.get("maximum", math.inf)
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


def with_meshes(ctx: Context, spec: ShapeSpec) -> ShapeSpec:
    """``spec`` (a shape being added to the world) with every OBJ model inside it read
    (``scene.obj_mesh``, each file once) and its triangles counted against the limits: each
    copy counts."""
    if spec.kind == "obj" and spec.mesh is None:
        return dataclasses.replace(spec, mesh=_mesh(ctx, spec))
    parts = spec.parts()
    if not parts:
        return spec
    children = tuple(with_meshes(ctx, child) for child in spec.children)
    left = with_meshes(ctx, spec.left) if spec.left is not None else None
    right = with_meshes(ctx, spec.right) if spec.right is not None else None
    return dataclasses.replace(spec, children=children, left=left, right=right)


def _mesh(ctx: Context, spec: ShapeSpec) -> Mesh:
    """Chapter 15: the OBJ model's triangles, read once per file; a broken file is one
    error naming the model's line and the file's."""
    path = spec.obj_file
    assert path is not None
    known: Mesh | None = ctx.meshes.get(path)
    if known is not None:  # read before: count its triangles again for this copy
        ctx.count_shapes(known.count, spec.line, f"the {known.count:,} triangles of {spec.label}")
        return known
    try:
        data = read_bytes(path, MAX_OBJ_BYTES)
    except OSError as error:
        ctx.reader.fail(spec.line, f"{spec.label}: cannot read OBJ file {path}: {error.strerror}")
    from scene.obj_mesh import read_mesh  # deferred: most scenes read no OBJ file

    try:
        mesh = read_mesh(data, str(path))
    except ValueError as error:
        ctx.reader.fail(spec.line, f"the OBJ file of {spec.label} is broken: {error}")
    ctx.meshes[path] = mesh
    ctx.count_shapes(mesh.count, spec.line, f"the {mesh.count:,} triangles of {spec.label}")
    if mesh.degenerate:
        plural = "s" if mesh.degenerate > 1 else ""
        ctx.notes.append(
            f"{path}: {mesh.degenerate} degenerate triangle{plural} (zero area) skipped, the "
            f"first at line {mesh.first_degenerate_line}"
        )
    return mesh
