"""The top level of a scene file: a list of ``- add:`` and ``- define:`` items, read in order.

``- add: camera`` (one), ``- add: light`` and ``- add: area_light`` (any number: published
scenes use several), ``- add: sky`` and ``- add: render`` (one each: ``scene.path_items``),
shapes added to the world as they come, and ``- define: NAME`` for materials, transforms and
shapes used further down (``extend: OTHER`` builds on an earlier definition).

The result is a ``Scene``: a description (pbrt's ``BasicScene``), not a world. Its camera and
lights are the variant's values; its shapes are ``ShapeSpec`` entities, OBJ models read into
arrays (``Mesh``). Each tracer makes what it renders from it (``Tracer.world_for``): the
Python tracers the book's ``World`` (``Scene.book_world``), the compiled ones their packed
tables, with no object per triangle.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from groundwork.files import read_text
from groundwork.progress import LoadProgress
from raytracer.canvas import MAX_SIDE
from raytracer.sampling import MAX_LIGHT_STEPS
from scene.build import Builder, divide_groups
from scene.colors import read_color
from scene.context import Context, Definition, Kind, updated
from scene.errors import SceneError
from scene.limits import Limits, limits_from_environment
from scene.materials import read_material_properties
from scene.path_items import read_render, read_sky
from scene.reader import Entry, Reader, compose, describe, line_of
from scene.shapes import SCENE_ITEMS, SHAPES, ShapeSpec, read_shape, with_meshes
from scene.transforms import read_transform, transform_problem

CAMERA_KEYS = ("add", "width", "height", "field-of-view", "from", "to", "up")
LIGHT_KEYS = ("add", "at", "intensity")
AREA_LIGHT_KEYS = ("add", "corner", "uvec", "usteps", "vvec", "vsteps", "intensity", "jitter")
AREA_LIGHT_REQUIRED = AREA_LIGHT_KEYS[1:-1]  # all but add and jitter
DEFINE_KEYS = ("define", "value", "extend")


# the most of a scene file read: YAML of this size already takes minutes to read
MAX_SCENE_BYTES = 64 << 20


@dataclass
class Scene:
    """A loaded scene file: what it describes, nothing built.

    path: the scene file; camera: built with the variant's API; lights: the world's lights
    (the variant's values); objects: the shapes added to the world, in order (``ShapeSpec``,
    OBJ models read); variant: its name; api: the variant's API (to resize the camera, to
    build the book's world); camera_line, light_line: where the camera and the first light
    are; obj_files: the OBJ models the scene reads; warnings: what the file asks that is
    allowed but probably not meant (``rtc render`` prints them); notes: what the loader did
    beyond the file (triangles left out), and what building a world did (groups divided);
    sky: the variant's sky (``- add: sky``) or None; render: the settings ``- add: render``
    gives, by ``RenderSettings`` field name; inverses: the transforms' inverses the load
    computed with the API's ``inverse``, by the matrix's id (``Context.inverses``).
    """

    path: Path
    camera: Any
    lights: list[Any]
    objects: tuple[ShapeSpec, ...]
    variant: str
    api: Mapping[str, Any] = field(repr=False, compare=False)
    camera_line: int = 0
    light_line: int = 0
    obj_files: tuple[Path, ...] = ()
    warnings: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    sky: Any = None
    render: dict[str, Any] = field(default_factory=dict)
    inverses: Mapping[int, tuple[Any, Any]] = field(default_factory=dict, repr=False, compare=False)
    _world: Any = field(default=None, repr=False, compare=False)

    def resized(self, width: int, height: int) -> Scene:
        """The same scene seen by a camera of another size, with the same field of view."""
        c = self.camera
        camera = updated(self.api["camera"](width, height, c.field_of_view), transform=c.transform)
        return dataclasses.replace(self, camera=camera)

    @property
    def world(self) -> Any:
        """The book's world as the file builds it (groups not divided), made once."""
        if self._world is None:
            self._world = self.book_world()
        return self._world

    def book_world(
        self, divide: Callable[[Any, int], object] | bool | None = False,
        progress: bool | None = None,
    ) -> Any:  # fmt: skip
        """Chapter 7: a new world of the book's shapes, built through the scene's API
        (``scene.build``). ``divide``: the variant's ``divide`` (True: the API's), to divide
        every top-level group, OBJ model and CSG shape with (the bonus chapter 'Bounding
        boxes and hierarchies', ``divide_groups``), as a tracer that walks the book's groups
        wants; None: the variant has none (a note says so); False: keep the groups as the
        file builds them. What was divided joins ``notes``."""
        bar = LoadProgress(f"building {self.path.name}", enabled=progress)
        try:
            bar.phase("building shapes", sum(o.count for o in self.objects), "shape")
            world = _empty_world(self)
            builder = Builder(self.api, self.path, bar)
            world.objects.extend(builder.shape(spec) for spec in self.objects)
            if divide is not False:
                function = self.api.get("divide") if divide is True else divide
                done = divide_groups(world.objects, function, self.variant, progress=bar)
                self.notes.extend(note for note in done if note not in self.notes)
            return world
        finally:
            bar.close()


def _empty_world(scene: Scene) -> Any:
    """A world holding the scene's lights (a variant whose world has a single ``light``
    takes the one) and its sky."""
    world = scene.api["world"]()
    if scene.sky is not None:
        world.sky = scene.sky
    lights = getattr(world, "lights", None)
    if lights is None:
        if scene.lights:
            world.light = scene.lights[0]
    else:
        lights.extend(scene.lights)
    return world


@dataclass(eq=False)  # a load's state: compared by identity
class _Loading:
    """What the top level has seen so far."""

    ctx: Context
    world: Any  # a world of the variant's, holding the lights
    camera: Any = None
    objects: list[ShapeSpec] = field(default_factory=list)
    camera_line: int = 0
    light_line: int = 0
    obj_files: list[Path] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    sky: Any = None
    render: dict[str, Any] = field(default_factory=dict)
    sky_line: int = 0
    render_line: int = 0


def load_scene(
    path: str | Path, api: Mapping[str, Any], *, variant: str = "this variant",
    limits: Limits | None = None, progress: bool | None = None,
    provide_mesh: Callable[[Path], bool] | None = None,
) -> Scene:  # fmt: skip
    """Chapter 7's camera, lights and shapes from a scene file in the book's YAML format.

    api: a variant's book API (the camera, lights, colors, transforms and patterns are made
    with it, the shapes described for it); variant: its name, for errors; limits: how deep
    and how big the scene may be (default: ``limits_from_environment``); progress: a progress
    bar on stderr if the load takes more than a second (default: when stderr is a terminal);
    provide_mesh: writes a missing OBJ file the project generates (``Context``). Any mistake
    in the file is a ``SceneError`` naming the file and line.
    """
    path = Path(path)
    try:
        text = read_text(path, MAX_SCENE_BYTES)
    except OSError as error:
        raise SceneError(path, None, f"cannot read the scene file: {error.strerror}") from None
    except UnicodeDecodeError as error:
        line = bytes(error.object[: error.start]).count(b"\n") + 1
        raise SceneError(
            path, line, f"the scene file is not UTF-8 text: byte 0x{error.object[error.start]:02x} "
            f"({error.reason}); save it as UTF-8",
        ) from None  # fmt: skip
    return load_scene_text(
        text, api, path=path, variant=variant, limits=limits, progress=progress,
        provide_mesh=provide_mesh,
    )  # fmt: skip


def load_scene_text(
    text: str, api: Mapping[str, Any], *, path: str | Path = "<scene>",
    variant: str = "this variant", limits: Limits | None = None, progress: bool | None = None,
    provide_mesh: Callable[[Path], bool] | None = None,
) -> Scene:  # fmt: skip
    """Like ``load_scene`` for text already read; ``path`` names it and locates OBJ files."""
    path = Path(path)
    limits = limits or limits_from_environment(path)
    limits.make_room()
    bar = LoadProgress(f"loading {path.name}", enabled=progress)
    try:
        return _load(text, api, path, variant, limits, bar, provide_mesh)
    finally:
        bar.close()


def _load(
    text: str, api: Mapping[str, Any], path: Path, variant: str, limits: Limits,
    bar: LoadProgress, provide_mesh: Callable[[Path], bool] | None,
) -> Scene:  # fmt: skip
    reader = Reader(path)
    bar.phase("reading YAML", len(text), "char")
    root, shapes = compose(text, path, limits, bar)
    if root is None:
        reader.fail(None, "the scene file is empty; expected a list of '- add:' and '- define:'")
    items = reader.sequence(root, "a scene file (its top level)")
    ctx = Context(reader, api, variant, limits=limits, progress=bar, provide_mesh=provide_mesh)
    state = _Loading(ctx, ctx.need("world", root, "the scene")())
    bar.phase("reading shapes", shapes, "shape")
    for item in items:
        _item(state, item)
    if state.camera is None:
        reader.fail(
            None, "the scene has no camera; expected '- add: camera' with width, height, "
            "field-of-view, from, to and up"
        )  # fmt: skip
    if state.light_line == 0 and state.sky is None and state.render.get("integrator") != "path":
        state.warnings.append(
            f"{path}: the scene has no light, so every surface renders black; add one with "
            "'- add: light' (at, intensity)"
        )
    world = state.world
    lights = list(world.lights) if hasattr(world, "lights") else [world.light]
    return Scene(
        path, state.camera, [light for light in lights if light is not None],
        tuple(state.objects), variant, api, state.camera_line, state.light_line,
        tuple(state.obj_files), tuple(state.warnings), list(ctx.notes), state.sky,
        state.render, ctx.inverses,
    )  # fmt: skip


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
    reading = ITEM_READERS.get(kind.value) if isinstance(kind, ScalarNode) else None
    if reading is not None:
        reading(state, node, entries)
    else:
        spec = read_shape(state.ctx, node)
        state.ctx.count_shapes(spec.count, node, spec.label)
        for obj_file in _obj_files(spec):
            if obj_file not in state.obj_files:
                state.obj_files.append(obj_file)
        state.objects.append(with_meshes(state.ctx, spec))


ITEM_READERS: dict[str, Callable[[_Loading, Node, dict[str, Entry]], None]] = {}
"""How each of ``scene.shapes.SCENE_ITEMS`` is read (filled below, once its readers exist)."""


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
    _check_pixels_apart(reader, value["from"], eye, width, height, fov)
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


def _check_pixels_apart(
    reader: Reader, node: Node, eye: list[float], width: int, height: int, fov: float
) -> None:
    """Chapter 7's camera aims a pixel's ray at a point one unit in front of ``from``: that
    point minus ``from`` is the ray's direction. Far enough from the origin, floats there
    step by more than a pixel's width, neighbouring pixels get the same ray and every ray a
    direction of 0 (a black picture): said here, instead of drawn."""
    half_view = math.tan(fov / 2)
    aspect = width / height
    half_width = half_view if aspect >= 1 else half_view * aspect
    pixel = half_width * 2 / width
    step = math.ulp(max(abs(c) for c in eye))
    if step > pixel:
        reader.fail(
            node,
            f"the camera's 'from' is too far from the origin ({max(abs(c) for c in eye):.3g}) "
            f"for its pixels: floats there step by {step:.3g}, more than a pixel's width "
            f"({pixel:.3g}) one unit in front of the camera, so its rays cannot aim; move the "
            f"scene nearer the origin (keep 'from' within about {pixel / 2**-52:.3g} of it)",
        )


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
    if not math.isfinite(at[0] * at[0] + at[1] * at[1] + at[2] * at[2]):  # shadow rays square it
        reader.fail(
            entries["at"].value,
            f"the light's at is too far for floating point ({math.hypot(*at):.3g} from the "
            "origin: the shadow rays' lengths overflow); expected up to about 1e150",
        )
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


def _sky(state: _Loading, node: Node, entries: dict[str, Entry]) -> None:
    """``- add: sky`` (``scene.path_items``): one per scene."""
    _only_one(state, node, "sky", state.sky_line)
    state.sky = read_sky(state.ctx, node, entries)
    state.sky_line = line_of(node)


def _render(state: _Loading, node: Node, entries: dict[str, Entry]) -> None:
    """``- add: render`` (``scene.path_items``): one per scene."""
    _only_one(state, node, "render", state.render_line)
    state.render = read_render(state.ctx, node, entries)
    state.render_line = line_of(node)


def _only_one(state: _Loading, node: Node, item: str, first: int) -> None:
    if first:
        state.ctx.reader.fail(
            node, f"a second '- add: {item}' (the first is at line {first}); a scene has one"
        )


RESERVED = (*SCENE_ITEMS, *SHAPES)


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


ITEM_READERS.update(zip(SCENE_ITEMS, (_camera, _light, _area_light, _sky, _render), strict=True))
