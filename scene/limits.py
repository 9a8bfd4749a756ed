"""How big and how deep a scene file may be, checked while it is read.

A scene file is a program of sorts: YAML aliases (``*name``) and defined shapes (``add:
NAME``) copy what they name, so twenty lines can describe a billion shapes, and groups
nested hundreds deep exhaust Python's stack before anything is drawn. Two limits stop both
early, with an error naming the limit and how to raise it:

- ``max_depth``: groups and CSGs nested inside each other (default 100). The YAML reader
  refuses text nested deeper than such a scene needs (``yaml_levels``) before it recurses;
  the loader refuses deeper nesting made by defined shapes. Environment:
  ``RTC_SCENE_MAX_DEPTH``.
- ``max_shapes``: every shape the world would hold, each copy counted, the triangles of OBJ
  models included (default 5,000,000: about 5 GB in the pure-Python variants). The YAML
  reader counts the shapes a file describes, aliases expanded, without expanding them; the
  loader counts defined shapes added by name and OBJ triangles before building them.
  Environment: ``RTC_SCENE_MAX_SHAPES``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import NamedTuple

from scene.errors import SceneError

DEPTH_VARIABLE = "RTC_SCENE_MAX_DEPTH"
SHAPES_VARIABLE = "RTC_SCENE_MAX_SHAPES"
DEFAULT_MAX_DEPTH = 100
DEFAULT_MAX_SHAPES = 5_000_000
# the most RTC_SCENE_MAX_DEPTH may ask (a recursion limit of about 12,000): deeper, recursion
# that passes through C functions (sum over a generator, pickle) risks the C stack
MAX_DEPTH_ALLOWED = 1000
# Python frames per level of nesting, at most, in the loader, the hierarchy code and the
# reference's group intersection; the interpreter's default limit (1000) fits the default depth
_FRAMES_PER_LEVEL = 12
_FRAMES_SPARE = 400


class Limits(NamedTuple):
    """max_depth: groups and CSGs inside each other; max_shapes: shapes in the world."""

    max_depth: int = DEFAULT_MAX_DEPTH
    max_shapes: int = DEFAULT_MAX_SHAPES

    @property
    def yaml_levels(self) -> int:
        """How deeply nested the YAML of a scene within the limits can be: two levels per
        group (the mapping and its ``children`` list), the top list, an item, and a
        material's pattern, UV pattern and colors below the deepest shape."""
        return 2 * self.max_depth + 10

    def depth_hint(self) -> str:
        """How to allow deeper nesting, for the end of an error message."""
        example = min(2 * self.max_depth, MAX_DEPTH_ALLOWED)
        return (
            f"to allow deeper nesting, set the environment variable {DEPTH_VARIABLE} (now "
            f"{self.max_depth}, at most {MAX_DEPTH_ALLOWED}), e.g. {DEPTH_VARIABLE}={example}"
        )

    def shapes_hint(self) -> str:
        """How to allow more shapes, for the end of an error message."""
        return (
            f"to allow more, set the environment variable {SHAPES_VARIABLE} (now "
            f"{self.max_shapes:,}), e.g. {SHAPES_VARIABLE}={2 * self.max_shapes}"
        )

    def make_room(self) -> None:
        """Raise the interpreter's recursion limit when ``max_depth`` is above the default,
        so that a scene nested that deep loads and renders (never lowers it)."""
        needed = _FRAMES_PER_LEVEL * self.max_depth + _FRAMES_SPARE
        if self.max_depth > DEFAULT_MAX_DEPTH and sys.getrecursionlimit() < needed:
            sys.setrecursionlimit(needed)


def _whole(path: Path, variable: str, default: int, low: int, high: int) -> int:
    text = os.environ.get(variable, "").strip()
    if not text:
        return default
    try:
        value = int(text.replace("_", ""))
    except ValueError:
        value = low - 1
    if not low <= value <= high:
        raise SceneError(
            path,
            None,
            f"the environment variable {variable}={text!r} must be a whole number from {low:,} "
            f"to {high:,} (default {default:,})",
        )
    return value


def limits_from_environment(path: Path) -> Limits:
    """The limits, ``RTC_SCENE_MAX_DEPTH`` and ``RTC_SCENE_MAX_SHAPES`` when set; a value
    that is not a whole number in range is a ``SceneError`` (naming ``path``, the scene)."""
    return Limits(
        _whole(path, DEPTH_VARIABLE, DEFAULT_MAX_DEPTH, 1, MAX_DEPTH_ALLOWED),
        _whole(path, SHAPES_VARIABLE, DEFAULT_MAX_SHAPES, 1, 10**12),
    )
