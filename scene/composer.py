"""PyYAML's composer with the scene limits (``limits``) checked while the node tree is built.

PyYAML composes a node for each level of nesting by recursion, so text nested a few hundred
levels deep ends in ``RecursionError`` inside the YAML library; and an alias (``*name``)
becomes the very node its anchor (``&name``) names, so twenty lines of aliases of aliases
make a tree that a reader walking it sees as a billion shapes. ``LimitedLoader`` counts, as
each node is composed: how deep the text nests (refused past ``Limits.yaml_levels``, before
the library recurses further), how tall each anchored node is and how many shapes (mappings
with an ``add`` key) it holds with its aliases expanded, without expanding them. An alias
used inside the item it names (a shape inside itself) is refused too.
"""

from __future__ import annotations

from typing import Any, NoReturn

import yaml
from yaml.events import AliasEvent, ScalarEvent
from yaml.nodes import MappingNode, Node, ScalarNode

from groundwork.progress import LoadProgress
from scene.errors import SceneError
from scene.limits import Limits

_PROGRESS_EVERY = 1024  # nodes between two progress updates


def _is_shape(node: Node) -> bool:
    """A mapping with an ``add`` key: a shape (or the camera, a light) the loader builds."""
    return isinstance(node, MappingNode) and any(
        isinstance(key, ScalarNode) and key.value == "add" for key, _ in node.value
    )


class LimitedLoader(yaml.SafeLoader):
    """A safe YAML loader whose composer enforces ``limits``; see the module's docstring.

    path: the scene file (named in errors); progress: told how far through the text the
    composer is. After ``get_single_node``, ``shapes`` is the number of shapes the text
    describes, each alias counted as the copy it is.
    """

    def __init__(
        self, text: str, path: Any, limits: Limits, progress: LoadProgress | None = None
    ) -> None:
        super().__init__(text)
        self.scene_path = path
        self.limits = limits
        self.progress = progress
        self.shapes = 0
        self._depth = 0
        self._nodes = 0
        self._open: dict[str, int] = {}  # anchors being composed -> their line
        self._measured: dict[int, tuple[int, int]] = {}  # id(anchored node) -> shapes, height
        self._frames: list[list[int]] = []  # per open collection: [shapes, height] so far

    def _fail(self, mark: Any, message: str) -> NoReturn:
        line = None if mark is None else int(mark.line) + 1
        raise SceneError(self.scene_path, line, message)

    def _counted(self, shapes: int, height: int) -> None:
        """A child of ``shapes`` shapes and ``height`` levels of collections was composed."""
        if self._frames:
            frame = self._frames[-1]
            frame[0] += shapes
            frame[1] = max(frame[1], height)

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        event = self.peek_event()
        if isinstance(event, AliasEvent):
            return self._alias(parent, index, event)
        self._nodes += 1
        if self.progress is not None and self._nodes % _PROGRESS_EVERY == 0:
            self.progress.update(int(event.start_mark.index))
        anchor = event.anchor
        if isinstance(event, ScalarEvent):
            node: Node = super().compose_node(parent, index)
            if anchor is not None:
                self._measured[id(node)] = (0, 0)  # a scalar is no level of nesting
            self._counted(0, 0)
            return node
        if self._depth >= self.limits.yaml_levels:
            self._fail(
                event.start_mark,
                f"the scene nests too deep here: more than {self.limits.yaml_levels} levels of "
                f"YAML, more than groups and CSGs nested {self.limits.max_depth} deep need; "
                f"{self.limits.depth_hint()}",
            )
        self._depth += 1
        self._frames.append([0, 0])
        if anchor is not None:
            self._open[anchor] = int(event.start_mark.line) + 1
        try:
            node = super().compose_node(parent, index)
        finally:
            self._depth -= 1
            shapes, height = self._frames.pop()
            if anchor is not None:
                self._open.pop(anchor, None)
        height += 1
        if _is_shape(node):
            shapes += 1
            self.shapes += 1
            self._check_total(node.start_mark, "")
        if anchor is not None:
            self._measured[id(node)] = (shapes, height)
        self._counted(shapes, height)
        return node

    def _alias(self, parent: Node | None, index: Any, event: AliasEvent) -> Node:
        anchor = event.anchor
        if anchor in self._open:
            self._fail(
                event.start_mark,
                f"the alias *{anchor} is inside the item it names (&{anchor}, line "
                f"{self._open[anchor]}): a shape inside itself nests without end; expected an "
                "alias of an item that ends before it",
            )
        node: Node = super().compose_node(parent, index)  # an unknown anchor is YAML's error
        shapes, height = self._measured.get(id(node), (0, 0))
        if self._depth + height > self.limits.yaml_levels:
            self._fail(
                event.start_mark,
                f"the alias *{anchor} nests the scene too deep here: more than "
                f"{self.limits.yaml_levels} levels of YAML, more than groups and CSGs nested "
                f"{self.limits.max_depth} deep need; {self.limits.depth_hint()}",
            )
        if shapes:
            self.shapes += shapes
            self._check_total(
                event.start_mark,
                f" (the alias *{anchor} here copies {shapes:,} shape{'s' if shapes > 1 else ''})",
            )
        self._counted(shapes, height)
        return node

    def _check_total(self, mark: Any, why: str) -> None:
        if self.shapes > self.limits.max_shapes:
            self._fail(
                mark,
                f"the scene describes more than {self.limits.max_shapes:,} shapes here{why}, "
                f"counting each copy a YAML alias makes; {self.limits.shapes_hint()}",
            )


try:  # libyaml's scanner and parser, in PyYAML's wheels (absent from a pure-Python build)
    from yaml._yaml import CParser
except ImportError:  # pragma: no cover - PyYAML built without libyaml
    CParser = None


class LibyamlLimitedLoader(LimitedLoader):
    """``LimitedLoader`` composing the events libyaml reads from the text, about five times
    faster than PyYAML's own scanner and parser in Python: the same composer, limits and
    nodes (a plain scalar's style is None, as PyYAML gives it). Only for text both read
    alike: on any YAML error the caller reads the text again with ``LimitedLoader``, whose
    messages the scene errors quote."""

    def __init__(
        self, text: str, path: Any, limits: Limits, progress: LoadProgress | None = None
    ) -> None:
        super().__init__(text, path, limits, progress)  # PyYAML's check of the characters
        assert CParser is not None
        self._events = CParser(text)

    def check_event(self, *choices: Any) -> bool:
        return bool(self._events.check_event(*choices))

    def peek_event(self) -> Any:
        return self._events.peek_event()

    def get_event(self) -> Any:
        event = self._events.get_event()
        if isinstance(event, ScalarEvent) and event.style == "":
            event.style = None  # a plain scalar, in PyYAML's spelling
        return event

    def dispose(self) -> None:
        self._events.dispose()
        super().dispose()
