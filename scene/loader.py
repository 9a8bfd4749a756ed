"""The top level of a scene file: a list of ``- add:`` and ``- define:`` items, read in order.

``- add: camera`` (one), ``- add: light`` and ``- add: area_light`` (any number: published
scenes use several), shapes added to the world as they come, and ``- define: NAME`` for
materials, transforms and shapes used further down (``extend: OTHER`` builds on an earlier
definition).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from raytracer.sampling import MAX_LIGHT_STEPS
from scene.context import Context, Definition, Kind, updated
from scene.errors import SceneError
from scene.limits import Limits, limits_from_environment
from scene.materials import read_color, read_material_properties
from scene.progress import LoadProgress
from scene.reader import Entry, Reader, compose, describe, line_of
from scene.shapes import SHAPES, ShapeSpec, build_shape, read_shape
from scene.transforms import read_transform, transform_problem
from variants.learner import is_stub

CAMERA_KEYS = ("add", "width", "height", "field-of-view", "from", "to", "up")
LIGHT_KEYS = ("add", "at", "intensity")
AREA_LIGHT_KEYS = ("add", "corner", "uvec", "usteps", "vvec", "vsteps", "intensity", "jitter")
AREA_LIGHT_REQUIRED = AREA_LIGHT_KEYS[1:-1]  # all but add and jitter
DEFINE_KEYS = ("define", "value", "extend")
MAX_SIDE = 16384  # as the canvas allows
# After loading, every top-level group, OBJ model and CSG shape is divided (the bonus chapter
# 'Bounding boxes and hierarchies'): a group of this many children or more is split into
# subgroups by where they lie. 8: a box test costs about what a triangle test costs in
# Python, so leaves of a few shapes keep the boxes a ray meets few while a missed box still
# skips several shapes. Timed on a 1,280-triangle icosphere at 40x30 (cached, prealloc):
# thresholds 2 to 16 within about 10% of each other, 32 slower; 8 was at or near the best
# for both, with half the groups of 2.
DIVIDE_THRESHOLD = 8


@dataclass
class Scene:
    """A loaded scene file.

    path: the scene file; camera and world: built with the variant's API; variant: its name;
    api: the variant's API (to resize the camera); camera_line, light_line: where the camera
    and the first light are; obj_files: the OBJ models the scene reads; warnings: what the
    file asks that is allowed but probably not meant (``rtc render`` prints them); notes:
    what the loader did to the scene beyond the file (the groups it divided).
    """

    path: Path
    camera: Any
    world: Any
    variant: str
    api: Mapping[str, Any] = field(repr=False, compare=False)
    camera_line: int = 0
    light_line: int = 0
    obj_files: tuple[Path, ...] = ()
    warnings: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    def resized(self, width: int, height: int) -> Scene:
        """The same scene seen by a camera of another size, with the same field of view."""
        c = self.camera
        camera = updated(self.api["camera"](width, height, c.field_of_view), transform=c.transform)
        return Scene(
            self.path, camera, self.world, self.variant, self.api,
            self.camera_line, self.light_line, self.obj_files, self.warnings, self.notes,
        )  # fmt: skip


@dataclass
class _Loading:
    """What the top level has seen so far."""

    ctx: Context
    world: Any
    camera: Any = None
    camera_line: int = 0
    light_line: int = 0
    obj_files: list[Path] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def load_scene(
    path: str | Path, api: Mapping[str, Any], *, variant: str = "this variant", divide: bool = True,
    limits: Limits | None = None, progress: bool | None = None,
) -> Scene:  # fmt: skip
    """Chapter 7's camera and world from a scene file in the book's YAML format.

    api: a variant's book API (every object is built with it); variant: its name, for errors;
    divide: False keeps groups as the file builds them (no ``divide_groups``); limits: how
    deep and how big the scene may be (default: ``limits_from_environment``); progress: a
    progress bar on stderr if the load takes more than a second (default: when stderr is a
    terminal). Any mistake in the file is a ``SceneError`` naming the file and line.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as error:
        raise SceneError(path, None, f"cannot read the scene file: {error.strerror}") from None
    except UnicodeDecodeError as error:
        line = bytes(error.object[: error.start]).count(b"\n") + 1
        raise SceneError(
            path, line, f"the scene file is not UTF-8 text: byte 0x{error.object[error.start]:02x} "
            f"({error.reason}); save it as UTF-8",
        ) from None  # fmt: skip
    return load_scene_text(
        text, api, path=path, variant=variant, divide=divide, limits=limits, progress=progress
    )


def load_scene_text(
    text: str, api: Mapping[str, Any], *, path: str | Path = "<scene>",
    variant: str = "this variant", divide: bool = True, limits: Limits | None = None,
    progress: bool | None = None,
) -> Scene:  # fmt: skip
    """Like ``load_scene`` for text already read; ``path`` names it and locates OBJ files."""
    path = Path(path)
    limits = limits or limits_from_environment(path)
    limits.make_room()
    bar = LoadProgress(f"loading {path.name}", enabled=progress)
    try:
        return _load(text, api, path, variant, divide, limits, bar)
    finally:
        bar.close()


def _load(
    text: str, api: Mapping[str, Any], path: Path, variant: str, divide: bool, limits: Limits,
    bar: LoadProgress,
) -> Scene:  # fmt: skip
    reader = Reader(path)
    bar.phase("reading YAML", len(text), "char")
    root, shapes = compose(text, path, limits, bar)
    if root is None:
        reader.fail(None, "the scene file is empty; expected a list of '- add:' and '- define:'")
    items = reader.sequence(root, "a scene file (its top level)")
    ctx = Context(reader, api, variant, limits=limits, progress=bar)
    state = _Loading(ctx, ctx.need("world", root, "the scene")())
    bar.phase("building shapes", shapes, "shape")
    for item in items:
        _item(state, item)
    if state.camera is None:
        reader.fail(
            None, "the scene has no camera; expected '- add: camera' with width, height, "
            "field-of-view, from, to and up"
        )  # fmt: skip
    if state.light_line == 0:
        state.warnings.append(
            f"{path}: the scene has no light, so every surface renders black; add one with "
            "'- add: light' (at, intensity)"
        )
    notes = divide_groups(state.world.objects, api, variant, progress=bar) if divide else ()
    return Scene(
        path, state.camera, state.world, variant, api,
        state.camera_line, state.light_line, tuple(state.obj_files), tuple(state.warnings),
        (*ctx.notes, *notes),
    )  # fmt: skip


def _count_groups(shape: Any) -> int:
    """The groups in ``shape`` (itself included), through children and CSG operands."""
    children = getattr(shape, "children", None)
    count = 0 if children is None else 1 + sum(_count_groups(c) for c in children)
    for operand in ("left", "right"):
        inside = getattr(shape, operand, None)
        if inside is not None:
            count += _count_groups(inside)
    return count


def divides(variant: Any) -> bool:
    """Whether scenes loaded for ``variant`` (a registry ``Variant``) are divided: yes,
    unless its tracer builds a hierarchy of its own (``Tracer.builds_hierarchy``)."""
    return not getattr(getattr(variant, "tracer", None), "builds_hierarchy", False)


def divide_groups(
    objects: list[Any], api: Mapping[str, Any], variant: str, threshold: int = DIVIDE_THRESHOLD,
    progress: LoadProgress | None = None,
) -> tuple[str, ...]:  # fmt: skip
    """Divide every group, OBJ model and CSG shape among ``objects`` with the variant's
    ``divide`` (the bonus chapter); what was done, as notes (none without such a shape)."""
    composite = [s for s in objects if hasattr(s, "children") or hasattr(s, "left")]
    if not composite:
        return ()
    divide = api.get("divide")
    if divide is None or is_stub(divide):
        return (f"groups not divided: {variant!r} has no divide() (the bonus chapter)",)
    before = sum(_count_groups(s) for s in composite)
    if progress is not None:
        progress.phase("dividing groups", len(composite), "group")
    for shape in composite:
        divide(shape, threshold)
        if progress is not None:
            progress.advance()
    made = sum(_count_groups(s) for s in composite) - before
    what = f"divide (threshold {threshold}) on {len(composite)} top-level group"
    what += "s, OBJ models or CSG shapes" if len(composite) > 1 else ", OBJ model or CSG shape"
    if made == 0:
        return (f"{what}: no group had {threshold} children or more; nothing to divide",)
    return (f"{what}: {made} subgroups made (groups: {before} before, {before + made} after)",)


def _item(state: _Loading, node: Node) -> None:
    reader = state.ctx.reader
    if not isinstance(node, MappingNode):
        reader.fail(node, f"expected an item '- add: ...' or '- define: ...', got {describe(node)}")
    entries = reader.mapping(node, "an item")
    if "add" in entries and "define" in entries:
        reader.fail(node, "an item has both 'add' and 'define'; expected one of them")
    if "define" in entries:
        _define(state.ctx, node, entries)
        return
    if "add" not in entries:
        first = next(iter(entries.values()), None)
        reader.fail(
            first.key_node if first else node,
            "expected an item '- add: ...' or '- define: ...'; "
            f"this one has {', '.join(entries) or 'no keys'}",
        )
    kind = entries["add"].value
    if isinstance(kind, ScalarNode) and kind.value == "camera":
        _camera(state, node, entries)
    elif isinstance(kind, ScalarNode) and kind.value == "light":
        _light(state, node, entries)
    elif isinstance(kind, ScalarNode) and kind.value == "area_light":
        _area_light(state, node, entries)
    else:
        spec = read_shape(state.ctx, node)
        state.ctx.count_shapes(spec.count, node, spec.label)
        for obj_file in _obj_files(spec):
            if obj_file not in state.obj_files:
                state.obj_files.append(obj_file)
        state.world.objects.append(build_shape(state.ctx, spec))


def _obj_files(spec: ShapeSpec) -> list[Path]:
    found = [spec.obj_file] if spec.obj_file is not None else []
    for child in (*spec.children, spec.left, spec.right):
        if child is not None:
            found.extend(_obj_files(child))
    return found


def _camera(state: _Loading, node: Node, entries: dict[str, Entry]) -> None:
    """``- add: camera``: chapter 7's camera and view transformation."""
    ctx, reader = state.ctx, state.ctx.reader
    if state.camera is not None:
        reader.fail(
            node, f"a second camera (the first is at line {state.camera_line}); "
            "a scene has one camera"
        )  # fmt: skip
    reader.check_keys(entries, CAMERA_KEYS, "the camera")
    value = {key: reader.require(entries, key, node, "the camera") for key in CAMERA_KEYS}
    width = reader.whole(value["width"], "the camera's width", 1, MAX_SIDE)
    height = reader.whole(value["height"], "the camera's height", 1, MAX_SIDE)
    fov = reader.number(value["field-of-view"], "the camera's field-of-view")
    if not 0 < fov < math.pi:
        reader.fail(
            value["field-of-view"],
            f"the camera's field-of-view must be between 0 and π radians (3.14159...), got {fov}",
        )
    eye, to, up = (reader.numbers(value[k], f"the camera's {k}", 3) for k in ("from", "to", "up"))
    forward = [b - a for a, b in zip(eye, to, strict=True)]
    if not any(forward):
        reader.fail(value["to"], "the camera's 'to' equals its 'from'; expected another point")
    _check_length(reader, value["to"], forward, "the camera's 'from' and 'to' are")
    if any(up):
        _check_length(reader, value["up"], up, "the camera's 'up' is")
    f, u = _unit(forward), _unit(up) if any(up) else (0.0, 0.0, 0.0)
    left = (f[1] * u[2] - f[2] * u[1], f[2] * u[0] - f[0] * u[2], f[0] * u[1] - f[1] * u[0])
    if not math.hypot(*left) > 1e-12:
        reader.fail(
            value["up"], "the camera's 'up' is zero or points along the line from 'from' to "
            "'to'; expected a direction across it, e.g. [0, 1, 0]"
        )  # fmt: skip
    point, vector = ctx.need("point", node, "the camera"), ctx.need("vector", node, "the camera")
    try:
        view = ctx.need("view_transform", node, "the camera")(point(*eye), point(*to), vector(*up))
    except (ArithmeticError, ValueError) as error:  # checked above; a variant may be stricter
        reader.fail(node, f"the camera's view transform cannot be made: {error}")
    problem = transform_problem(ctx, view)
    if problem is not None:
        reader.fail(node, f"the camera's view transform (from, to and up) {problem}")
    camera = ctx.need("camera", node, "the camera")(width, height, fov)
    state.camera = updated(camera, transform=view)
    state.camera_line = line_of(node)


def _unit(v: list[float]) -> tuple[float, float, float]:
    length = math.hypot(*v)
    return (v[0] / length, v[1] / length, v[2] / length)


def _check_length(reader: Reader, node: Node, v: list[float], what: str) -> None:
    """The book's ``normalize`` squares the components: their squares' sum must be a
    positive, finite float (a vector from about 1e-154 to 1e154 long)."""
    squares = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    if not 0 < squares < math.inf:
        close = "too close together" if "and" in what else "too short"
        far = "too far apart" if "and" in what else "too long"
        reader.fail(
            node,
            f"{what} {close if squares == 0 else far} for floating point (a length of "
            f"{math.hypot(*v):.3g}); expected a length from about 1e-150 to 1e150",
        )


def _light(state: _Loading, node: Node, entries: dict[str, Entry]) -> None:
    """``- add: light``: chapter 6's point light, added to the world's lights (a variant
    whose world has a single ``light`` takes one)."""
    ctx, reader = state.ctx, state.ctx.reader
    reader.check_keys(entries, LIGHT_KEYS, "the light")
    at = reader.numbers(reader.require(entries, "at", node, "the light"), "the light's at", 3)
    intensity = read_color(
        ctx, reader.require(entries, "intensity", node, "the light"), "the light's intensity"
    )
    position = ctx.need("point", node, "the light")(*at)
    light = ctx.need("point_light", node, "the light")(position, intensity)
    _add_light(state, node, light)


def _add_light(state: _Loading, node: Node, light: Any) -> None:
    """Add a light to the world's lights (or set a one-light variant's ``light``)."""
    lights = getattr(state.world, "lights", None)
    if lights is None:
        if state.light_line:
            state.ctx.reader.fail(
                node,
                f"a second light (the first is at line {state.light_line}): "
                f"{state.ctx.variant}'s world has one light (no 'lights' list); expected a "
                "single light",
            )
        state.world.light = light
    else:
        lights.append(light)
    state.light_line = state.light_line or line_of(node)


def _area_light(state: _Loading, node: Node, entries: dict[str, Entry]) -> None:
    """``- add: area_light``: the soft shadows chapter's light over a parallelogram:
    ``corner`` (a point), ``uvec`` and ``vvec`` (its full edges, as the book's
    ``area_light`` takes them), ``usteps`` and ``vsteps`` (cells along each), ``intensity``,
    and ``jitter`` (true: each cell's point placed at random per pixel sample, reproducibly;
    default false: cell centres)."""
    ctx, reader = state.ctx, state.ctx.reader
    what = "the area light"
    reader.check_keys(entries, AREA_LIGHT_KEYS, what)
    value = {key: reader.require(entries, key, node, what) for key in AREA_LIGHT_REQUIRED}
    corner = reader.numbers(value["corner"], f"{what}'s corner", 3)
    edges = {}
    for key in ("uvec", "vvec"):
        edge = reader.numbers(value[key], f"{what}'s {key}", 3)
        if not math.hypot(*edge) > 0:
            reader.fail(
                value[key],
                f"{what}'s {key} has zero length; expected the edge of the light along "
                f"which its {key[0]}steps cells lie, e.g. [2, 0, 0]",
            )
        edges[key] = edge
    steps = {
        key: reader.whole(value[key], f"{what}'s {key}", 1, MAX_LIGHT_STEPS)
        for key in ("usteps", "vsteps")
    }
    intensity = read_color(ctx, value["intensity"], f"{what}'s intensity")
    jitter = "jitter" in entries and reader.boolean(entries["jitter"].value, f"{what}'s jitter")
    point = ctx.need("point", node, what)
    vector = ctx.need("vector", node, what)
    make = ctx.need("area_light", node, what)
    try:
        light = make(
            point(*corner), vector(*edges["uvec"]), steps["usteps"], vector(*edges["vvec"]),
            steps["vsteps"], intensity,
        )  # fmt: skip
        if jitter:
            light = updated(light, jitter=True)
    except ValueError as error:  # checked above; a variant may be stricter
        reader.fail(node, f"{what}: {error}")
    _add_light(state, node, light)
    cells = steps["usteps"] * steps["vsteps"]
    ctx.notes.append(
        f"area light at line {line_of(node)}: {steps['usteps']}x{steps['vsteps']} = {cells} "
        f"cell{'' if cells == 1 else 's'}, {cells} shadow ray{'' if cells == 1 else 's'} per "
        "shaded point, "
        + ("jittered at random per pixel sample" if jitter else "each cell sampled at its centre")
    )


RESERVED = ("camera", "light", "area_light", *SHAPES)


def _define(ctx: Context, node: Node, entries: dict[str, Entry]) -> None:
    """``- define: NAME`` with ``value:`` (a material, a transform list or a shape) and an
    optional ``extend: OTHER`` (an earlier definition of the same kind to build on)."""
    reader = ctx.reader
    reader.check_keys(entries, DEFINE_KEYS, "a define")
    name_node = entries["define"].value
    name = reader.string(name_node, "define")
    if name in RESERVED:
        reader.fail(name_node, f"cannot define {name!r}: it is a built-in; choose another name")
    if "value" not in entries:
        if "extend" not in entries:
            reader.fail(node, f"define {name!r} has no 'value'; expected value: (or extend:)")
        alias_node = entries["extend"].value
        alias = reader.string(alias_node, "extend")
        if alias not in ctx.scope:
            reader.fail(alias_node, f"extend: {alias!r} is not defined above this line")
        ctx.scope[name] = Definition(name, ctx.scope[alias].kind, ctx.scope[alias].value,
                                     line_of(node))  # fmt: skip
        return
    value = entries["value"].value
    kind = _kind_of(ctx, value, name)
    base: Definition | None = None
    if "extend" in entries:
        base = ctx.lookup(entries["extend"].value, kind, f"define {name!r}: extend")
    what = f"define {name!r}"
    result: Any
    if kind == "material":
        result = {**(base.value if base else {}), **read_material_properties(ctx, value, what)}
    elif kind == "transform":
        m = read_transform(ctx, value, what)
        result = m * base.value if base else m
    else:
        if base is not None:
            reader.fail(
                entries["extend"].key_node,
                f"{what}: 'extend' works for materials and transforms; to build on the shape "
                f"{base.name!r}, write 'add: {base.name}' in the value instead",
            )
        result = read_shape(ctx, value)
    ctx.scope[name] = Definition(name, kind, result, line_of(node))


def _kind_of(ctx: Context, value: Node, name: str) -> Kind:
    if isinstance(value, SequenceNode):
        return "transform"
    if isinstance(value, MappingNode):
        keys = {k.value for k, _ in value.value if isinstance(k, ScalarNode)}
        return "shape" if "add" in keys else "material"
    ctx.reader.fail(
        value,
        f"define {name!r}: the value must be a material (a mapping), a transform list, "
        f"or a shape (a mapping with 'add'), got {describe(value)}",
    )
