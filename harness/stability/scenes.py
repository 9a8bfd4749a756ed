"""Scenes for the stability cases, built through a variant's API (chapters 7-11).

``scaled_reference`` rewrites the reference scene file as if its author had written it at
another scale or place: camera ``from``/``to`` and the light moved, and every top-level
shape's transform list extended by ``[scale, f, f, f]`` and ``[translate, o, o, o]``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import yaml

from harness.instruments.imagediff import canvas_array
from harness.scenery import SCENES
from scene import load_scene_text

REFERENCE_SCENE = SCENES / "reference.yml"


def scaled_reference_text(factor: float, offset: float = 0.0) -> str:
    """The reference scene file scaled by ``factor`` about the origin, then moved by
    ``(offset, offset, offset)``; the unchanged text for factor 1 and offset 0."""
    return scaled_scene_text(REFERENCE_SCENE.read_text(encoding="utf-8"), factor, offset)


def scaled_scene_text(text: str, factor: float, offset: float = 0.0) -> str:
    """A scene file's ``text`` scaled by ``factor`` about the origin, then moved by
    ``(offset, offset, offset)``: camera ``from``/``to`` and lights moved, every top-level
    shape's transform list extended (a sky and the render settings have no place); the
    unchanged text for factor 1 and offset 0."""
    if factor == 1 and offset == 0:
        return text
    items = yaml.safe_load(text)
    for item in items:
        kind = item.get("add")
        if kind == "camera":
            item["from"] = [factor * v + offset for v in item["from"]]
            item["to"] = [factor * v + offset for v in item["to"]]
        elif kind == "light":
            item["at"] = [factor * v + offset for v in item["at"]]
        elif kind not in (None, "sky", "render"):
            moved = [["scale", factor, factor, factor], ["translate", offset, offset, offset]]
            item["transform"] = list(item.get("transform") or []) + moved
    return yaml.safe_dump(items, sort_keys=False)


def reference_scene(
    api: Mapping[str, Any], size: tuple[int, int], factor: float, offset: float
) -> tuple[Any, Any]:
    """(camera, world) of the scaled reference scene at ``size``."""
    scene = load_scene_text(scaled_reference_text(factor, offset), api, path="reference.yml")
    scene = scene.resized(*size)
    return scene.camera, scene.world


def render_array(api: Mapping[str, Any], camera: Any, world: Any) -> np.ndarray:
    """The variant's render of ``world`` as a float array (height, width, 3), unclamped."""
    image = api["render"](camera, world)
    return canvas_array(image, api["pixel_at"])


def look(
    api: Mapping[str, Any],
    size: tuple[int, int],
    eye: tuple[float, float, float],
    to: tuple[float, float, float],
    field_of_view: float = math.pi / 3,
) -> Any:
    """A camera of ``size`` at ``eye`` looking at ``to`` (up is +y)."""
    c = api["camera"](size[0], size[1], field_of_view)
    view = api["view_transform"](api["point"](*eye), api["point"](*to), api["vector"](0, 1, 0))
    return with_transform(c, view)


def with_transform(c: Any, m: Any) -> Any:
    """``c.transform ← m`` for the (frozen) camera: a replaced copy."""
    return dataclasses.replace(c, transform=m)


def material(api: Mapping[str, Any], **values: Any) -> Any:
    """``material()`` with some properties changed (``color`` as a triple)."""
    m = api["material"]()
    if "color" in values:
        values["color"] = api["color"](*values["color"])
    return dataclasses.replace(m, **values)


def glowing(api: Mapping[str, Any], rgb: tuple[float, float, float]) -> Any:
    """A material that shows exactly ``rgb`` whatever the light: ambient 1, nothing else."""
    return material(api, color=rgb, ambient=1.0, diffuse=0.0, specular=0.0, reflective=0.0)


def checkered_wall(api: Mapping[str, Any], z: float) -> Any:
    """A plane facing -z at ``z`` with glowing black-and-white half-unit checks."""
    wall = api["plane"]()
    api["set_transform"](wall, api["translation"](0, 0, z) * api["rotation_x"](math.pi / 2))
    checks = api["checkers_pattern"](api["color"](1, 1, 1), api["color"](0.1, 0.1, 0.1))
    api["set_pattern_transform"](checks, api["scaling"](0.5, 0.5, 0.5))
    wall.material = dataclasses.replace(glowing(api, (1, 1, 1)), pattern=checks)
    return wall


def pure_glass(api: Mapping[str, Any], index: float) -> Any:
    """A unit sphere of clear glass with refractive ``index``: no surface color at all, no
    reflection, casting no shadow; what it shows is only what it refracts."""
    s = api["sphere"]()
    s.material = material(
        api, ambient=0.0, diffuse=0.0, specular=0.0, reflective=0.0, transparency=1.0,
        refractive_index=index,
    )  # fmt: skip
    s.casts_shadow = False
    return s


def world_of(
    api: Mapping[str, Any], objects: list[Any], light_at: tuple[float, float, float]
) -> Any:
    """A world with ``objects`` and a white point light at ``light_at``."""
    w = api["world"]()
    w.objects.extend(objects)
    w.light = api["point_light"](api["point"](*light_at), api["color"](1, 1, 1))
    return w
