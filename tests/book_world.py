"""The book's default world (chapter 7) seen from the chapter's test camera, for the tests
that render a small picture through a variant's own book API."""

from __future__ import annotations

import dataclasses
import math
from typing import Any


def default_scene(variant: Any, width: int, height: int) -> tuple[Any, Any]:
    """(camera, world): ``default_world()`` seen from (0, 1.5, -5) at the origin, a third of
    pi wide, at ``width`` x ``height``, made by ``variant``'s book API."""
    api = variant.api
    view = api["view_transform"](
        api["point"](0, 1.5, -5), api["point"](0, 0, 0), api["vector"](0, 1, 0)
    )
    c = dataclasses.replace(api["camera"](width, height, math.pi / 3), transform=view)
    return c, api["default_world"]()
