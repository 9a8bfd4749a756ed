"""What every part of the loader needs: the reader, the variant's API, and the defined names."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, NamedTuple

from yaml.nodes import Node

from groundwork.progress import LoadProgress
from raytracer.api import BOOK_API
from scene.limits import Limits
from scene.reader import Reader

Kind = Literal["material", "transform", "shape"]


class Definition(NamedTuple):
    """A ``- define: NAME`` item.

    kind: what the value is; value: material properties (a dict of the book's names), a
    transform (a matrix), or a resolved shape description (``ShapeSpec``); line: where.
    """

    name: str
    kind: Kind
    value: Any
    line: int


@dataclass(eq=False)  # a load's state: compared by identity
class Context:
    """The state of one load.

    reader: the scene file's YAML reader; api: the variant's book API; variant: its name
    (for errors); scope: the names defined so far, in file order; depth: how deep the shape
    being read is nested in groups and CSGs; notes: what the load did that ``--explain``
    reports (triangles skipped ...); images: the image textures decoded so far, by path
    (a scene may put one image on many faces); limits: how deep and how big the scene may be
    (``limits``); shapes: the shapes the world will hold so far, counted before they are
    built (OBJ triangles included); meshes: each OBJ model, once read (``scene.obj_mesh``);
    progress: the load's progress bar (None: no bar); provide_mesh: writes a missing OBJ
    file that the project generates (``harness.scenery.make_meshes.provide``), saying whether it
    exists now (None: never); inverses: the inverse of each transform the checks found
    invertible (``scene.transforms``), by the matrix's id, the matrix kept beside it, so
    that a packer inverts each transform once per load.
    """

    reader: Reader
    api: Mapping[str, Any]
    variant: str
    scope: dict[str, Definition] = field(default_factory=dict)
    depth: int = 0
    notes: list[str] = field(default_factory=list)
    images: dict[Path, Any] = field(default_factory=dict)
    limits: Limits = field(default_factory=Limits)
    shapes: int = 0
    meshes: dict[Path, Any] = field(default_factory=dict)
    progress: LoadProgress | None = None
    provide_mesh: Callable[[Path], bool] | None = None
    inverses: dict[int, tuple[Any, Any]] = field(default_factory=dict)

    def count_shapes(self, count: int, node: Node | int | None, what: str) -> None:
        """``count`` more shapes for the world (``what`` names them); past the limit, a
        ``SceneError`` at ``node`` before they are built."""
        self.shapes += count
        if self.shapes > self.limits.max_shapes:
            self.reader.fail(
                node,
                f"{what} would bring the scene to {self.shapes:,} shapes (every copy of a "
                f"defined shape and every triangle of an OBJ model counted), more than the "
                f"limit, {self.limits.max_shapes:,}; {self.limits.shapes_hint()}",
            )

    def need(self, name: str, node: Node, purpose: str) -> Any:
        """The variant's ``name``; a ``SceneError`` at ``node`` if the variant lacks it."""
        if name not in self.api:
            chapter = BOOK_API.get(name)
            where = f" (chapter {chapter} of the book)" if chapter else ""
            self.reader.fail(
                node,
                f"the variant {self.variant!r} has no {name!r}{where}, which {purpose} needs; "
                "choose a variant that implements it",
            )
        return self.api[name]

    def lookup(self, node: Node, kind: Kind, what: str) -> Definition:
        """The definition a name refers to; it must exist already and be of ``kind``."""
        name = self.reader.string(node, what)
        definition = self.scope.get(name)
        if definition is None:
            known = sorted(n for n, d in self.scope.items() if d.kind == kind)
            listed = f"defined {kind}s: {', '.join(known)}" if known else f"no {kind} is defined"
            self.reader.fail(
                node,
                f"{what}: {name!r} is not defined above this line ({listed}); "
                f"expected a name given earlier with '- define: {name}'",
            )
        if definition.kind != kind:
            self.reader.fail(
                node,
                f"{what}: {name!r} (defined at line {definition.line}) is a {definition.kind}, "
                f"not a {kind}",
            )
        return definition


def updated(value: Any, **changes: Any) -> Any:
    """``value`` with some attributes changed: a replaced copy of a frozen dataclass (the
    reference's ``Camera``, ``Material``), else the same object changed in place."""
    params = getattr(type(value), "__dataclass_params__", None)
    if params is not None and params.frozen:
        return dataclasses.replace(value, **changes)
    for name, new in changes.items():
        setattr(value, name, new)
    return value
