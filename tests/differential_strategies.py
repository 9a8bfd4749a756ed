"""Hypothesis strategies for ``tests/test_differential.py`` (issue 19, item 1): random shapes,
transforms, matrices, materials, lights, cameras and small worlds, drawn as plain *recipes*
(frozen dataclasses and tuples of numbers) and built through any variant's API, so that
naive and the variant under test get equal scenes made by their own constructors.

A recipe's ``repr`` is Python that rebuilds it: a shrunk failing example can be pasted into
an ``@example(...)`` as it is printed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from hypothesis import strategies as st

from scene.kinds import BY_NAME, KINDS

Api = Mapping[str, Any]
Op = tuple[str, tuple[float, ...]]  # ("translation", (1.0, 2.0, 3.0)): a chapter-4 call
Triple = tuple[float, float, float]

LEAF_KINDS = tuple(kind.name for kind in KINDS if kind.renders)  # the kind table's
COMPOSITE_KINDS = ("group", "csg")
# every shape kind the reference defines but chapter 9's test shape (it only records a ray)
SHAPE_KINDS = LEAF_KINDS + COMPOSITE_KINDS
CSG_OPERATIONS = ("union", "intersection", "difference")
PATTERN_KINDS = ("stripe", "gradient", "ring", "checkers")


# ------------------------------------------------------------------------------- recipes


@dataclass(frozen=True)
class PatternSpec:
    kind: str
    a: Triple
    b: Triple
    ops: tuple[Op, ...] = ()


@dataclass(frozen=True)
class MaterialSpec:
    color: Triple = (1.0, 1.0, 1.0)
    ambient: float = 0.1
    diffuse: float = 0.9
    specular: float = 0.9
    shininess: float = 200.0
    reflective: float = 0.0
    transparency: float = 0.0
    refractive_index: float = 1.0
    pattern: PatternSpec | None = None


@dataclass(frozen=True)
class ShapeSpec:
    """One shape: ``params`` are a leaf kind's parameters in the kind table's order (a
    cylinder's or cone's minimum, maximum, closed; a torus's radii), a triangle's three
    corners (a smooth triangle's, then its three normals), a CSG shape's operation;
    ``children`` a group's or a CSG shape's (left, right)."""

    kind: str
    ops: tuple[Op, ...] = ()
    params: tuple[Any, ...] = ()
    children: tuple[ShapeSpec, ...] = ()
    material: MaterialSpec | None = None


@dataclass(frozen=True)
class LightSpec:
    position: Triple
    intensity: Triple


@dataclass(frozen=True)
class CameraSpec:
    hsize: int
    vsize: int
    field_of_view: float
    eye: Triple
    to: Triple


@dataclass(frozen=True)
class WorldSpec:
    objects: tuple[ShapeSpec, ...]
    lights: tuple[LightSpec, ...]


@dataclass(frozen=True)
class RaySpec:
    origin: Triple
    direction: Triple


# ------------------------------------------------------------------------------ building


def build_matrix(api: Api, ops: Sequence[Op]) -> Any:
    """The ops applied in order (the first op is applied to the shape first)."""
    m = api["identity_matrix"]
    for name, args in ops:
        m = api[name](*args) * m
    return m


def build_pattern(api: Api, spec: PatternSpec) -> Any:
    pattern = api[f"{spec.kind}_pattern"](api["color"](*spec.a), api["color"](*spec.b))
    if spec.ops:
        api["set_pattern_transform"](pattern, build_matrix(api, spec.ops))
    return pattern


def build_material(api: Api, spec: MaterialSpec) -> Any:
    return replace(
        api["material"](),
        color=api["color"](*spec.color),
        ambient=spec.ambient,
        diffuse=spec.diffuse,
        specular=spec.specular,
        shininess=spec.shininess,
        reflective=spec.reflective,
        transparency=spec.transparency,
        refractive_index=spec.refractive_index,
        pattern=build_pattern(api, spec.pattern) if spec.pattern is not None else None,
    )


def build_shape(api: Api, spec: ShapeSpec, leaves: list[Any] | None = None) -> Any:
    """The shape ``spec`` describes, made with ``api``'s constructors; its leaves (the shapes
    with a surface) are appended to ``leaves`` in a fixed order (children left to right)."""
    leaves = [] if leaves is None else leaves
    kind = spec.kind
    shape: Any
    leaf = BY_NAME.get(kind)
    if leaf is not None:  # a leaf kind of the kind table: its factory, then its parameters
        if leaf.corners:
            points = [api["point"](*p) for p in spec.params[: leaf.corners]]
            normals = [api["vector"](*n) for n in spec.params[leaf.corners :]]
            shape = api[kind](*points, *normals)
        else:
            shape = api[kind]()
            for parameter, value in zip(leaf.parameters, spec.params, strict=True):
                setattr(shape, parameter.attribute, value)
        leaves.append(shape)
    elif kind == "group":
        shape = api["group"]()
        for child in spec.children:
            api["add_child"](shape, build_shape(api, child, leaves))
    elif kind == "csg":
        left = build_shape(api, spec.children[0], leaves)
        right = build_shape(api, spec.children[1], leaves)
        shape = api["csg"](spec.params[0], left, right)
    else:
        raise ValueError(f"unknown shape kind {kind!r}")
    if spec.material is not None and kind not in COMPOSITE_KINDS:
        shape.material = build_material(api, spec.material)
    if spec.ops:  # after the children: a group's cached box must follow its transform
        api["set_transform"](shape, build_matrix(api, spec.ops))
    return shape


def build_world(api: Api, spec: WorldSpec) -> tuple[Any, list[Any]]:
    """The world and its leaves, in recipe order."""
    w = api["world"]()
    leaves: list[Any] = []
    for obj in spec.objects:
        w.objects.append(build_shape(api, obj, leaves))
    for light in spec.lights:
        w.lights.append(
            api["point_light"](api["point"](*light.position), api["color"](*light.intensity))
        )
    return w, leaves


def build_camera(api: Api, spec: CameraSpec) -> Any:
    c = api["camera"](spec.hsize, spec.vsize, spec.field_of_view)
    view = api["view_transform"](
        api["point"](*spec.eye), api["point"](*spec.to), api["vector"](0, 1, 0)
    )
    return replace(c, transform=view)


def build_ray(api: Api, spec: RaySpec) -> Any:
    return api["ray"](api["point"](*spec.origin), api["vector"](*spec.direction))


# ---------------------------------------------------------------------------- strategies


def floats(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


def triples(low: float, high: float) -> st.SearchStrategy[Triple]:
    return st.tuples(floats(low, high), floats(low, high), floats(low, high))


def signed(low: float, high: float) -> st.SearchStrategy[float]:
    """A magnitude from low to high, either sign (a negative scale mirrors)."""
    return st.tuples(st.booleans(), floats(low, high)).map(lambda s: -s[1] if s[0] else s[1])


ANGLES = floats(-math.pi, math.pi)
# |shear| <= 0.4 keeps the shearing matrix's determinant above 0.39 (at 0.5 it can reach 0)
OPS: st.SearchStrategy[Op] = st.one_of(
    st.tuples(st.just("translation"), triples(-2, 2)),
    st.tuples(st.just("scaling"), st.tuples(signed(0.3, 2.5), signed(0.3, 2.5), signed(0.3, 2.5))),
    st.tuples(st.sampled_from(("rotation_x", "rotation_y", "rotation_z")), st.tuples(ANGLES)),
    st.tuples(st.just("shearing"), st.tuples(*[floats(-0.4, 0.4)] * 6)),
)
TRANSFORMS = st.lists(OPS, max_size=3).map(tuple)
COLORS = triples(0, 1)


def patterns() -> st.SearchStrategy[PatternSpec]:
    return st.builds(
        PatternSpec,
        kind=st.sampled_from(PATTERN_KINDS),
        a=COLORS,
        b=COLORS,
        ops=st.lists(OPS, max_size=2).map(tuple),
    )


def materials() -> st.SearchStrategy[MaterialSpec]:
    """Matte, shiny, reflective and transparent surfaces, some patterned."""
    return st.builds(
        MaterialSpec,
        color=COLORS,
        ambient=floats(0, 0.3),
        diffuse=floats(0.2, 1),
        specular=floats(0, 1),
        shininess=floats(5, 300),
        reflective=st.one_of(st.just(0.0), floats(0.05, 1)),
        transparency=st.one_of(st.just(0.0), floats(0.05, 1)),
        refractive_index=floats(1, 2.5),
        pattern=st.one_of(st.none(), patterns()),
    )


@st.composite
def bounds(draw: st.DrawFn) -> tuple[float, float, bool]:
    """A cylinder's or cone's (minimum, maximum, closed): unbounded, or cut off."""
    if draw(st.booleans()):
        return (-math.inf, math.inf, False)
    low = draw(floats(-2, 1))
    return (low, low + draw(floats(0.1, 3)), draw(st.booleans()))


@st.composite
def radii(draw: st.DrawFn) -> tuple[float, float]:
    """A torus's (major_radius, minor_radius): a tube thinner than its ring (a hole)."""
    major = draw(floats(0.3, 2))
    return (major, major * draw(floats(0.05, 0.9)))


PARAMETERS: dict[tuple[str, ...], st.SearchStrategy[tuple[Any, ...]]] = {
    ("min", "max", "closed"): bounds(),
    ("major-radius", "minor-radius"): radii(),
}
"""How to draw each set of parameters a leaf kind of the kind table has (by its keys)."""


@st.composite
def leaves(
    draw: st.DrawFn, with_material: bool = False, kinds: Sequence[str] = LEAF_KINDS
) -> ShapeSpec:
    kind = draw(st.sampled_from(kinds))
    leaf = BY_NAME[kind]
    params: tuple[Any, ...] = ()
    if leaf.parameters:
        params = draw(PARAMETERS[leaf.keys])
    elif leaf.corners:
        corners = draw(st.lists(triples(-2, 2), min_size=leaf.corners, max_size=leaf.corners))
        params = tuple(corners)
        if leaf.smooth:
            normals = draw(st.lists(triples(-1, 1), min_size=leaf.corners, max_size=leaf.corners))
            params = (*corners, *normals)
    material = draw(materials()) if with_material else None
    return ShapeSpec(kind, draw(TRANSFORMS), params, material=material)


def shapes(with_material: bool = False, depth: int = 2) -> st.SearchStrategy[ShapeSpec]:
    """A leaf of any kind, or (``depth`` > 0) a group of 1-3 shapes or a CSG shape."""
    leaf = leaves(with_material)
    if depth <= 0:
        return leaf
    inner = shapes(with_material, depth - 1)
    group = st.builds(
        lambda children, ops: ShapeSpec("group", ops, children=tuple(children)),
        st.lists(inner, min_size=1, max_size=3),
        TRANSFORMS,
    )
    csg = st.builds(
        lambda op, left, right, ops: ShapeSpec("csg", ops, (op,), (left, right)),
        st.sampled_from(CSG_OPERATIONS),
        inner,
        inner,
        TRANSFORMS,
    )
    return st.one_of(leaf, leaf, group, csg)


def rays(spread: float = 6.0, target: float = 1.5) -> st.SearchStrategy[RaySpec]:
    """Rays from anywhere in a box of half-width ``spread`` aimed at a point near the origin
    (where the shapes are), unnormalized as the book allows; a few aimed anywhere."""

    def aim(origin: Triple, to: Triple) -> RaySpec:
        return RaySpec(origin, (to[0] - origin[0], to[1] - origin[1], to[2] - origin[2]))

    aimed = st.builds(aim, triples(-spread, spread), triples(-target, target))
    anywhere = st.builds(RaySpec, triples(-spread, spread), triples(-1, 1))
    return st.one_of(aimed, aimed, aimed, anywhere)


def unit(ray: RaySpec) -> RaySpec:
    """The ray with its direction normalized: the rays the pipeline shades (``ray_for_pixel``,
    reflection, refraction) are unit length, and chapter 6's ``lighting`` assumes it (an eye
    vector of length 2 squares into the specular term)."""
    length = math.sqrt(sum(c * c for c in ray.direction))
    if length == 0:
        return ray
    x, y, z = ray.direction
    return RaySpec(ray.origin, (x / length, y / length, z / length))


def lights() -> st.SearchStrategy[LightSpec]:
    return st.builds(LightSpec, triples(-10, 10), triples(0.2, 1))


def worlds(max_objects: int = 4) -> st.SearchStrategy[WorldSpec]:
    return st.builds(
        WorldSpec,
        objects=st.lists(shapes(with_material=True, depth=1), min_size=1, max_size=max_objects).map(
            tuple
        ),
        lights=st.lists(lights(), min_size=1, max_size=2).map(tuple),
    )


@st.composite
def cameras(draw: st.DrawFn, hsize: int = 8, vsize: int = 6) -> CameraSpec:
    """A camera 4 to 9 units from the scene, looking at a point near the origin (never
    straight down or up: the book's up vector would be parallel to the view)."""
    distance = draw(floats(4, 9))
    azimuth = draw(ANGLES)
    elevation = draw(floats(-1.2, 1.2))
    eye = (
        distance * math.cos(elevation) * math.sin(azimuth),
        distance * math.sin(elevation),
        -distance * math.cos(elevation) * math.cos(azimuth),
    )
    return CameraSpec(hsize, vsize, draw(floats(0.4, 2.0)), eye, draw(triples(-0.5, 0.5)))


# -------------------------------------------------------------------------------- matrices

Rows = tuple[tuple[float, ...], ...]


@st.composite
def general_matrices(draw: st.DrawFn) -> Rows:
    """Any 4x4 matrix (not only affine): random entries, or an ill-conditioned one whose
    last row is nearly a combination of the others (``10**-k`` away)."""
    rows: list[tuple[float, ...]] = [
        tuple(draw(st.lists(floats(-10, 10), min_size=4, max_size=4))) for _ in range(4)
    ]
    if draw(st.booleans()):
        a, b, c = draw(floats(-2, 2)), draw(floats(-2, 2)), draw(floats(-2, 2))
        tiny = 10.0 ** -draw(floats(3, 12))
        noise = draw(st.lists(floats(-1, 1), min_size=4, max_size=4))
        rows[3] = tuple(
            a * rows[0][j] + b * rows[1][j] + c * rows[2][j] + tiny * noise[j] for j in range(4)
        )
    return tuple(rows)


@st.composite
def affine_ops(draw: st.DrawFn) -> tuple[Op, ...]:
    """A transform made of the book's calls: well-conditioned (the shapes' ``TRANSFORMS``),
    or ill-conditioned, a rotation, a scaling by ``10**-k`` along some axes (condition up to
    1e8), another rotation and a translation."""
    if draw(st.booleans()):
        return draw(TRANSFORMS)
    axes = ("rotation_x", "rotation_y", "rotation_z")
    squash = tuple(10.0 ** -draw(floats(0, 8)) for _ in range(3))
    return (
        (draw(st.sampled_from(axes)), (draw(ANGLES),)),
        ("scaling", squash),
        (draw(st.sampled_from(axes)), (draw(ANGLES),)),
        ("translation", draw(triples(-2, 2))),
    )


@st.composite
def one_feature_set_worlds(draw: st.DrawFn) -> WorldSpec:
    """Worlds of one fixed structure (every shape kind, every pattern, reflection,
    refraction with Schlick, a group's box, CSG, one light) with random transforms,
    colours, amounts and light: numba compiles one specialized kernel for all of them."""

    def surface(pattern: str | None = None, reflective: bool = False, glass: bool = False) -> Any:
        spec = draw(materials())
        return replace(
            spec,
            pattern=(
                PatternSpec(pattern, draw(COLORS), draw(COLORS), draw(TRANSFORMS))
                if pattern
                else None
            ),
            reflective=draw(floats(0.05, 1)) if reflective or glass else 0.0,
            transparency=draw(floats(0.05, 1)) if glass else 0.0,
        )

    def shape(kind: str, material: MaterialSpec, params: tuple[Any, ...] = ()) -> ShapeSpec:
        return ShapeSpec(kind, draw(TRANSFORMS), params, material=material)

    corners = (draw(triples(-2, 2)), draw(triples(-2, 2)), draw(triples(-2, 2)))
    normals = (draw(triples(-1, 1)), draw(triples(-1, 1)), draw(triples(-1, 1)))
    floor = ShapeSpec(
        "plane", (("translation", (0.0, -2.0, 0.0)),), material=surface("checkers", True)
    )
    mesh = ShapeSpec(
        "group",
        draw(TRANSFORMS),
        children=(
            shape("triangle", surface(), corners),
            shape("smooth_triangle", surface(), (*corners, *normals)),
        ),
    )
    solid = ShapeSpec(
        "csg",
        draw(TRANSFORMS),
        ("difference",),
        (shape("cube", surface("stripe")), shape("sphere", surface(glass=True))),
    )
    return WorldSpec(
        objects=(
            floor,
            shape("cylinder", surface("ring"), (-1.0, 1.0, True)),
            shape("cone", surface("gradient"), (-1.0, 0.0, True)),
            mesh,
            solid,
        ),
        lights=(draw(lights()),),
    )
