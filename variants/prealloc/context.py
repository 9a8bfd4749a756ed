"""The render context of the ``prealloc`` variant: everything one render (or one API call)
builds once and then reuses for every ray.

- a record per shape (flat inverse and inverse transpose, material, parent), made once,
- the lights as buffers (an area light's cells' points too), the offset epsilon,
- the sample being traced (``sample``: seed, x, y, i), for jittered area lights,
- per-depth scratch for the recursion of chapter 11 (``levels[remaining]``),
- the shadow ray and its intersection buffer (chapter 8), and small point buffers.

The context never changes a shape, so the world must not change while it is in use (a
render does not change it; each API call builds its own context).
"""

from __future__ import annotations

from collections.abc import Sequence

from raytracer.lights import Light
from raytracer.materials import Material
from raytracer.shapes.cone import Cone
from raytracer.shapes.csg import CSG
from raytracer.shapes.cube import Cube
from raytracer.shapes.cylinder import Cylinder
from raytracer.shapes.group import Group
from raytracer.shapes.plane import Plane
from raytracer.shapes.shape import Shape
from raytracer.shapes.smooth_triangle import SmoothTriangle
from raytracer.shapes.sphere import Sphere
from raytracer.shapes.test_shape import TestShape
from raytracer.shapes.torus import Torus
from raytracer.shapes.triangle import Triangle
from raytracer.tracer import NO_SAMPLE, Sample
from raytracer.world import World
from variants.prealloc.buffers import (
    DepthScratch,
    IntersectionBuffer,
    ShapeStack,
    new_color,
    new_ray,
    new_tuple,
)
from variants.prealloc.errors import PreallocUnsupported, check_reimplemented
from variants.prealloc.groups import CSGRecord, GroupRecord
from variants.prealloc.patterns import pattern_record
from variants.prealloc.records import LightRecord, MaterialRecord
from variants.prealloc.shapes import ShapeRecord
from variants.prealloc.solids import (
    ConeRecord,
    CubeRecord,
    CylinderRecord,
    PlaneRecord,
    SphereRecord,
    TestShapeRecord,
    TorusRecord,
)
from variants.prealloc.triangles import SmoothTriangleRecord, TriangleRecord

# reference class -> (record class, the methods the record reimplements)
SHAPE_RECORDS: dict[type[Shape], tuple[type[ShapeRecord], tuple[str, ...]]] = {
    Sphere: (SphereRecord, ("local_intersect", "local_normal_at")),
    Plane: (PlaneRecord, ("local_intersect", "local_normal_at")),
    TestShape: (TestShapeRecord, ("local_intersect", "local_normal_at")),
    Cube: (CubeRecord, ("local_intersect", "local_normal_at")),
    Cylinder: (CylinderRecord, ("local_intersect", "_intersect_caps", "local_normal_at")),
    Cone: (ConeRecord, ("local_intersect", "_intersect_caps", "local_normal_at")),
    Torus: (TorusRecord, ("local_intersect", "local_normal_at")),
    SmoothTriangle: (
        SmoothTriangleRecord,
        ("local_intersect", "intersection_at", "local_normal_at"),
    ),
    Triangle: (TriangleRecord, ("local_intersect", "intersection_at", "local_normal_at")),
    Group: (GroupRecord, ("local_intersect", "local_normal_at")),
    CSG: (CSGRecord, ("local_intersect", "local_normal_at")),
}


def record_class(shape: Shape) -> type[ShapeRecord]:
    """The record class for a reference shape (or a subclass that only caches, like
    ``cached``'s); ``PreallocUnsupported`` naming the type for anything else."""
    for cls in type(shape).__mro__:
        entry = SHAPE_RECORDS.get(cls)
        if entry is not None:
            record, methods = entry
            check_reimplemented(shape, cls, methods)
            return record
    raise PreallocUnsupported(
        f"prealloc: no implementation for shape type {type(shape).__name__}; it runs "
        f"{', '.join(cls.__name__ for cls in SHAPE_RECORDS)}"
    )


def material_record(m: Material) -> MaterialRecord:
    """A material's record, with its pattern's (chapters 6 and 10)."""
    return MaterialRecord(m, None if m.pattern is None else pattern_record(m.pattern))


class TraceContext:
    """Buffers and records reused by every ray of one render.

    eps: the offset epsilon (``RenderSettings.epsilon``); lights: ``LightRecord``s, in order
    (each knows its index, for the jitter); objects: the records of the world's objects, in
    order; sample: (seed, x, y, i) of the sample being traced (``NO_SAMPLE`` outside a
    render), which the pixel loop sets before each sample.
    """

    __slots__ = (
        "_records",
        "containers",
        "eps",
        "levels",
        "lights",
        "local_point",
        "objects",
        "sample",
        "shadow_ray",
        "shadow_xs",
        "surface",
    )

    def __init__(self, eps: float, lights: Sequence[Light] = (), depth: int = 0) -> None:
        self.eps = float(eps)
        self.lights = [LightRecord(light, k) for k, light in enumerate(lights)]
        self.sample: Sample = NO_SAMPLE
        self._records: dict[int, ShapeRecord] = {}
        self.objects: list[ShapeRecord] = []
        self.levels: list[DepthScratch] = []
        self.level(depth)
        self.shadow_ray = new_ray()
        self.shadow_xs = IntersectionBuffer()
        self.containers = ShapeStack()
        self.local_point = new_tuple()  # pattern_at_shape's object/pattern-space point
        self.surface = new_color()  # a pattern's colour in lighting

    @classmethod
    def for_world(cls, w: World, eps: float, depth: int = 0) -> TraceContext:
        """A context with records for every object of ``w`` and its lights."""
        ctx = cls(eps, w.lights, depth)
        ctx.objects = [ctx.record(shape) for shape in w.objects]
        return ctx

    def level(self, remaining: int) -> DepthScratch:
        """The scratch for recursion level ``remaining`` (levels <= 0 share level 0); made
        the first time it is needed, reused afterwards."""
        index = remaining if remaining > 0 else 0
        levels = self.levels
        while len(levels) <= index:
            levels.append(DepthScratch())
        return levels[index]

    def record(self, shape: Shape) -> ShapeRecord:
        """The one record of ``shape`` in this context (made on first use, with its parent's
        and its children's), so identity of records follows identity of shapes."""
        found = self._records.get(id(shape))
        if found is not None:
            return found
        rec = record_class(shape)(shape, material_record(shape.material), self.eps)
        self._records[id(shape)] = rec  # before parents and children, which point back
        # children first: a parent's ``finish`` walks its whole subtree (a CSG's ``in_left``),
        # this record included, so it must be finished before its parent's record is made
        rec.finish([self.record(child) for child in _children(shape)])
        if shape.parent is not None:
            rec.parent = self.record(shape.parent)
        return rec


def _children(shape: Shape) -> list[Shape]:
    """The shapes directly inside ``shape``: a group's children, a CSG's two operands."""
    if isinstance(shape, Group):
        return list(shape.children)
    if isinstance(shape, CSG):
        return [shape.left, shape.right]
    return []
