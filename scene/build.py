"""The book's shapes made from a scene description (chapters 5-16), through a variant's API:
what the Python tracers render (``Tracer.world_for``), and ``Scene.world``.

Every ``ShapeSpec`` becomes new shapes each time it is built: a leaf with its kind's factory
and parameters (``scene.kinds``), a group with ``group`` and ``add_child``, a CSG with
``csg``, an OBJ model (its ``Mesh``) as chapter 15's ``obj_to_group`` makes it: a group of a
group per OBJ group, each holding its triangles (``triangle``, ``smooth_triangle``). A
material or ``shadow: false`` on a group, an OBJ model or a CSG applies to every shape
inside it that does not set its own; an OBJ model's triangles share one material value.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple, NoReturn

from groundwork.progress import LoadProgress
from raytracer.obj_file import collector_paused
from scene.context import updated
from scene.errors import SceneError
from scene.shapes import GROUPS, ShapeSpec

if TYPE_CHECKING:  # an OBJ's reader (and numpy) only for a scene that reads one
    from scene.obj_mesh import Mesh


class Inherited(NamedTuple):
    """What a group, OBJ model or CSG passes down to the shapes inside it."""

    material: dict[str, Any] | None = None
    shadow: bool = True


OUTSIDE = Inherited()
"""What a shape outside any group, OBJ model or CSG inherits: nothing."""


def make_material(api: Mapping[str, Any], properties: Mapping[str, Any]) -> Any:
    """The variant's default ``material()`` with ``properties`` replaced."""
    return updated(api["material"](), **properties)


class Builder:
    """Builds the book's shapes through ``api``; ``path`` (the scene file) and each spec's
    line name any problem (a variant may refuse what the loader accepted)."""

    def __init__(
        self, api: Mapping[str, Any], path: Path, progress: LoadProgress | None = None
    ) -> None:
        self.api = api
        self.path = path
        self.progress = progress

    def fail(self, line: int, message: str) -> NoReturn:
        raise SceneError(self.path, line, message)

    def shape(self, spec: ShapeSpec, inherited: Inherited = OUTSIDE) -> Any:
        """A new shape (with new children) from ``spec``."""
        api = self.api
        if self.progress is not None:
            self.progress.advance()
        material = spec.material if spec.material is not None else inherited.material
        shadow = spec.shadow if spec.shadow is not None else inherited.shadow
        passed = Inherited(material, shadow)
        if spec.kind in GROUPS:
            shape = api["group"]()
            for child in spec.children:
                api["add_child"](shape, self.shape(child, passed))
        elif spec.kind == "obj":
            shape = self.model(spec, passed)
        elif spec.kind == "csg":
            assert spec.left is not None and spec.right is not None
            left, right = self.shape(spec.left, passed), self.shape(spec.right, passed)
            shape = api["csg"](spec.operation, left, right)
        else:
            shape = api[spec.kind]()
            for attribute, value in spec.params.items():
                setattr(shape, attribute, value)
        self._finish(shape, spec, material, shadow)
        return shape

    def _finish(
        self, shape: Any, spec: ShapeSpec, material: dict[str, Any] | None, shadow: bool
    ) -> None:
        if spec.transform is not None:
            try:
                self.api["set_transform"](shape, spec.transform)
            except ValueError as error:  # already checked; a variant may be stricter
                self.fail(spec.line, f"{spec.label}: {error}")
        if material is not None:
            shape.material = make_material(self.api, material)
        if not shadow:
            shape.casts_shadow = False

    def model(self, spec: ShapeSpec, inherited: Inherited) -> Any:
        """Chapter 15: the OBJ model as ``obj_to_group`` makes it, every triangle with the
        model's material (one value, made once) and shadow."""
        mesh = spec.mesh
        assert mesh is not None, "an OBJ model is read when it is added"
        api = self.api
        group, add_child = api["group"], api["add_child"]
        made = None if inherited.material is None else make_material(api, inherited.material)
        result = group()
        with collector_paused():
            for part in self.triangle_groups(mesh, spec):
                for triangle in part.children:
                    if made is not None:
                        triangle.material = made
                    if not inherited.shadow:
                        triangle.casts_shadow = False
                if made is not None:
                    part.material = made
                if not inherited.shadow:
                    part.casts_shadow = False
                add_child(result, part)
        return result

    def triangle_groups(self, mesh: Mesh, spec: ShapeSpec) -> Iterator[Any]:
        """One group per OBJ group (``mesh.groups``), holding its triangles."""
        api = self.api
        point, vector = api["point"], api["vector"]
        group, add_child, triangle = api["group"], api["add_child"], api["triangle"]
        smooth = mesh.smooth()
        if smooth.any() and "smooth_triangle" not in api:
            self.fail(
                spec.line,
                f"the variant has no 'smooth_triangle' (chapter 15 of the book), which the "
                f"smooth triangles of {spec.label} need; choose a variant that implements it",
            )
        points = [point(x, y, z) for x, y, z in mesh.positions.tolist()]
        normals = [vector(x, y, z) for x, y, z in mesh.normals.tolist()]
        corners = mesh.triangles.tolist()
        corner_normals = mesh.corner_normals.tolist() if mesh.corner_normals is not None else []
        start = 0
        for _, count in mesh.groups:
            part = group()
            for t in range(start, start + count):
                a, b, c = corners[t]
                if smooth[t]:
                    na, nb, nc = corner_normals[t]
                    shape = api["smooth_triangle"](
                        points[a], points[b], points[c], normals[na], normals[nb], normals[nc]
                    )
                else:
                    shape = triangle(points[a], points[b], points[c])
                add_child(part, shape)
            start += count
            yield part


# After loading, every top-level group, OBJ model and CSG shape is divided (the bonus chapter
# 'Bounding boxes and hierarchies'): a group of this many children or more is split into
# subgroups by where they lie. 8: a box test costs about what a triangle test costs in
# Python, so leaves of a few shapes keep the boxes a ray meets few while a missed box still
# skips several shapes. Timed on a 1,280-triangle icosphere at 40x30 (cached, prealloc):
# thresholds 2 to 16 within about 10% of each other, 32 slower; 8 was at or near the best
# for both, with half the groups of 2.
DIVIDE_THRESHOLD = 8


def _count_groups(shape: Any) -> int:
    """The groups in ``shape`` (itself included), through children and CSG operands."""
    children = getattr(shape, "children", None)
    count = 0 if children is None else 1 + sum(_count_groups(c) for c in children)
    for operand in ("left", "right"):
        inside = getattr(shape, operand, None)
        if inside is not None:
            count += _count_groups(inside)
    return count


def divide_groups(
    objects: list[Any], divide: Callable[[Any, int], object] | None, variant: str,
    threshold: int = DIVIDE_THRESHOLD, progress: LoadProgress | None = None,
) -> tuple[str, ...]:  # fmt: skip
    """Divide every group, OBJ model and CSG shape among ``objects`` with the variant's
    ``divide`` (the bonus chapter; None: it has none); what was done, as notes (none
    without such a shape)."""
    composite = [s for s in objects if hasattr(s, "children") or hasattr(s, "left")]
    if not composite:
        return ()
    if divide is None:
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
