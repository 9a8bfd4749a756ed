"""Reading the YAML of a scene file while keeping every node's line (``yaml.compose``).

``Reader`` turns YAML nodes into numbers, strings, booleans and triples, and raises a
``SceneError`` naming the node's line for anything that is not what the format expects.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from pathlib import Path
from typing import NamedTuple, NoReturn

import yaml
from yaml.constructor import ConstructorError, SafeConstructor
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.reader import ReaderError

from groundwork.progress import LoadProgress
from scene.composer import CParser, LibyamlLimitedLoader, LimitedLoader
from scene.errors import SceneError
from scene.limits import Limits

INDENTATION_HINT = (
    "check the indentation: the keys of one item line up, and every item of a list starts with '- '"
)
# YAML 1.1 (PyYAML) reads 1e-3 as a string; the scene format means a number.
_NUMBER_TEXT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
_STR_TAG = "tag:yaml.org,2002:str"


def compose(
    text: str, path: Path, limits: Limits | None = None, progress: LoadProgress | None = None
) -> tuple[Node | None, int]:
    """The YAML node tree of ``text`` (None for an empty document) and the number of shapes
    it describes (aliases counted as copies), within ``limits`` (``composer``); YAML's own
    errors become a ``SceneError`` at the line YAML reports."""
    limits = limits or Limits()
    if CParser is not None:  # libyaml reads the events; any YAML error: read again below
        fast = None
        try:
            fast = LibyamlLimitedLoader(text, path, limits, progress)
            return fast.get_single_node(), fast.shapes
        except (yaml.YAMLError, UnicodeError):
            pass  # PyYAML's reading names what is wrong, and where, in the words users see
        finally:
            if fast is not None:
                fast.dispose()
    loader = None
    try:
        loader = LimitedLoader(text, path, limits, progress)  # checks characters
        return loader.get_single_node(), loader.shapes
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        problem = error.problem or "cannot be read"
        context = ""
        if error.context and error.context_mark is not None:
            context = f" ({error.context} at line {error.context_mark.line + 1})"
        line = mark.line + 1 if mark is not None else None
        raise SceneError(
            path, line, f"invalid YAML: {problem}{context}; {INDENTATION_HINT}"
        ) from None
    except ReaderError as error:  # a character YAML text may not hold
        line = text.count("\n", 0, error.position) + 1
        code = error.character if isinstance(error.character, int) else 0
        raise SceneError(
            path, line, f"invalid YAML: the character #x{code:04x} is not allowed in YAML text "
            f"({error.reason}); is this a binary file?",
        ) from None  # fmt: skip
    except yaml.YAMLError as error:
        raise SceneError(path, None, f"invalid YAML: {' '.join(str(error).split())}") from None
    finally:
        if loader is not None:
            loader.dispose()


def _yaml11_surprise(node: Node, value: object) -> str:
    """Why a plain scalar YAML 1.1 (PyYAML) read as a number means another number than it
    shows, or "": ``020`` is octal 16, ``1:30`` base 60 (90)."""
    if not isinstance(node, ScalarNode) or node.style or not isinstance(value, int | float):
        return ""
    text = str(node.value).strip().lstrip("+-").replace("_", "")
    if ":" in text:
        return (
            f"{text!r} is a base-60 number to YAML 1.1 ({value}); write the number itself, "
            "or quote it if it is a name"
        )
    if _OCTAL.fullmatch(text) and int(text, 8) != int(text, 10):
        return (
            f"{text!r} starts with 0, so YAML 1.1 reads it as the octal number {value}; write "
            f"{int(text, 10)} without the leading 0"
        )
    return ""


_OCTAL = re.compile(r"0[0-7]+")


def line_of(node: Node) -> int:
    """The 1-based line where ``node`` starts."""
    return int(node.start_mark.line) + 1


def describe(node: Node) -> str:
    """A short account of a node for an error message: its text, or what kind it is, and
    a YAML tag the scene format does not read (``!!python/name:...``)."""
    if isinstance(node, ScalarNode):
        text = str(node.value)
        text = text if len(text) <= 60 else text[:57] + "..."  # a message stays readable
        shown = repr(text) if node.tag == _STR_TAG else text
    else:
        shown = "a list" if isinstance(node, SequenceNode) else "a mapping"
    return shown + _foreign_tag(node)


_YAML_TAG = "tag:yaml.org,2002:"
_CORE_TAGS = ("str", "int", "float", "bool", "null", "seq", "map")


def _foreign_tag(node: Node) -> str:
    """`` tagged !!python/name:os.system (...)`` for a tag outside YAML's core schema."""
    tag = str(node.tag)
    short = tag.removeprefix(_YAML_TAG)
    if short in _CORE_TAGS:
        return ""
    shown = f"!!{short}" if tag.startswith(_YAML_TAG) else tag
    return f" tagged {shown} (the scene format reads no YAML tags)"


class Entry(NamedTuple):
    """One ``key: value`` of a mapping, with the key's node (for its line)."""

    key: str
    key_node: Node
    value: Node


class Reader:
    """Typed access to the nodes of one scene file; every mistake is a ``SceneError``.

    path: the scene file, named in every error.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self._constructor = SafeConstructor()

    def fail(self, at: Node | int | None, message: str) -> NoReturn:
        """Raise a ``SceneError`` at a node's line, at a line number, or for the whole file."""
        line = line_of(at) if isinstance(at, Node) else at
        raise SceneError(self.path, line, message)

    def mapping(self, node: Node, what: str) -> dict[str, Entry]:
        """A mapping's entries by key; keys must be unique strings."""
        if not isinstance(node, MappingNode):
            self.fail(node, f"{what} must be a mapping of 'key: value' lines, got {describe(node)}")
        try:
            self._constructor.flatten_mapping(node)  # YAML merge keys (<<: *anchor)
        except ConstructorError as error:
            self.fail(node, f"invalid YAML merge in {what}: {error.problem}")
        entries: dict[str, Entry] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, ScalarNode) or key_node.tag != _STR_TAG:
                self.fail(key_node, f"{what} has a key {describe(key_node)}; keys are words")
            key = str(key_node.value)
            if key in entries:
                first = line_of(entries[key].key_node)
                self.fail(key_node, f"{what} gives '{key}' twice (first at line {first})")
            entries[key] = Entry(key, key_node, value_node)
        return entries

    def check_keys(self, entries: dict[str, Entry], known: Iterable[str], what: str) -> None:
        """Every key of ``entries`` must be one of ``known``; the error lists the known ones."""
        known = list(known)
        for entry in entries.values():
            if entry.key not in known:
                import difflib  # deferred: only a misspelt key needs it

                close = difflib.get_close_matches(entry.key, known, n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else ""
                self.fail(
                    entry.key_node,
                    f"unknown key '{entry.key}' in {what}{hint}; known keys: {', '.join(known)}",
                )

    def require(self, entries: dict[str, Entry], key: str, owner: Node, what: str) -> Node:
        """The value of a key that must be present."""
        if key not in entries:
            self.fail(owner, f"{what} has no '{key}'; it needs one")
        return entries[key].value

    def sequence(self, node: Node, what: str) -> list[Node]:
        if not isinstance(node, SequenceNode):
            self.fail(node, f"{what} must be a list, got {describe(node)}")
        return list(node.value)

    def scalar(self, node: Node, what: str) -> object:
        """A scalar's Python value (YAML 1.1 rules, as PyYAML's safe loader reads it)."""
        if not isinstance(node, ScalarNode):
            self.fail(node, f"{what} must be a single value, got {describe(node)}")
        try:
            return self._constructor.construct_object(node, deep=True)
        except (ConstructorError, ValueError) as error:
            self.fail(node, f"{what}: cannot read {describe(node)}: {error}")

    def string(self, node: Node, what: str) -> str:
        if not isinstance(node, ScalarNode) or node.tag != _STR_TAG:
            self.fail(node, f"{what} must be a name, got {describe(node)}")
        return str(node.value)

    def boolean(self, node: Node, what: str) -> bool:
        value = self.scalar(node, what)
        if not isinstance(value, bool):
            self.fail(node, f"{what} must be true or false, got {describe(node)}")
        return value

    def number(self, node: Node, what: str, *, allow_infinity: bool = False) -> float:
        """A finite number (or ±infinity when allowed); never NaN, never a boolean; never a
        number YAML 1.1 reads otherwise than it looks (``_yaml11_surprise``)."""
        value = self.scalar(node, what)
        surprise = _yaml11_surprise(node, value)
        if surprise:
            self.fail(node, f"{what}: {surprise}")
        if isinstance(value, str) and _NUMBER_TEXT.fullmatch(value.strip()):
            value = float(value)
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(node, f"{what} must be a number, got {describe(node)}")
        try:
            number = float(value)
        except OverflowError:  # an integer literal of hundreds of digits
            if not allow_infinity:
                self.fail(
                    node, f"{what} must be a finite number, got a whole number of "
                    f"{len(str(abs(value)))} digits (above the largest float, about 1.8e308)",
                )  # fmt: skip
            return math.inf if value > 0 else -math.inf
        if math.isnan(number):
            self.fail(node, f"{what} must be a number, got NaN")
        if math.isinf(number) and not allow_infinity:
            sign = "-" if number < 0 else ""
            self.fail(node, f"{what} must be a finite number, got {sign}infinity")
        return number if isinstance(value, float) else value  # keep ints as ints

    def whole(self, node: Node, what: str, low: int, high: int) -> int:
        """A whole number from ``low`` to ``high`` (3.0 counts as 3)."""
        number = self.number(node, what)
        if number != int(number) or not low <= number <= high:
            self.fail(node, f"{what} must be a whole number from {low} to {high}, got {number}")
        return int(number)

    def numbers(self, node: Node, what: str, count: int) -> list[float]:
        """A list of exactly ``count`` finite numbers, e.g. ``[1, 0.5, 0]``."""
        items = self.sequence(node, what)
        if len(items) != count:
            self.fail(node, f"{what} must be a list of {count} numbers, got {len(items)}")
        return [self.number(item, f"{what}[{i}]") for i, item in enumerate(items)]
