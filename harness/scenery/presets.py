"""The scenes the harness renders: scene files, named presets, and one built-in test scene
(the scene files themselves live in ``scenes/``).

A preset is a scene file plus the size, samples and depth it is meant to be measured at:

- ``reference``: the Go write-up's reference image (``scenes/reference.yml``),
  640x480, 1 sample per pixel, depth 5.
- ``cpp-spheres``: the C++ report's workload (``scenes/cpp-spheres.yml``): eight
  spheres and one light, 500x500, 8 samples per pixel, depth 5, reported in MRay/s.
- ``cpp-spheres-path``: the same scene as the C++ report ran it, path-traced (chapter 21
  here): 500x500, 8 rays per pixel, 5 bounces, its sky.
- ``default-world``: the book's chapter 7 test world seen by its chapter 7 camera, built in
  code (no scene file), for fast tests of the harness itself.

Anything else is a path to a scene file in the book's YAML format.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from groundwork.sizes import Size
from harness.scenery import SCENES
from harness.scenery.make_meshes import provide
from raytracer.camera import PATH, WHITTED
from scene import load_scene
from scene.context import updated

BUILTIN_DEFAULT_WORLD = "default-world"
PATH_PRESET = "cpp-spheres-path"


@dataclass(frozen=True)
class ScenePreset:
    """A named scene with the settings it is measured at.

    path: the scene file (None for a scene built in code); size, samples, depth: defaults
    for ``--full`` (the preset's own workload); about: one line for the report; integrator:
    how it is rendered (``RenderSettings.integrator``).
    """

    name: str
    path: Path | None
    size: Size
    samples: int
    depth: int
    about: str
    integrator: str = WHITTED


PRESETS: dict[str, ScenePreset] = {
    preset.name: preset
    for preset in [
        ScenePreset(
            "reference",
            SCENES / "reference.yml",
            Size(640, 480),
            1,
            5,
            "the Go write-up's reference image: planes, glass, a cylinder, a group of spheres",
        ),
        ScenePreset(
            "cpp-spheres",
            SCENES / "cpp-spheres.yml",
            Size(500, 500),
            8,
            5,
            "the C++ report's workload: eight spheres, one light, 8 samples per pixel",
        ),
        ScenePreset(
            PATH_PRESET,
            SCENES / "cpp-spheres.yml",
            Size(500, 500),
            8,
            5,
            "the C++ report's workload as it ran it: path-traced, 8 rays per pixel, 5 bounces, "
            "lit by its sky and its light",
            PATH,
        ),
        ScenePreset(
            BUILTIN_DEFAULT_WORLD,
            None,
            Size(40, 30),
            1,
            5,
            "the book's default world (chapter 7), built in code, for tests",
        ),
    ]
}


@dataclass(frozen=True)
class SceneRef:
    """What to render: a preset's name, or a scene file (``name`` is then its stem)."""

    name: str
    path: Path | None

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "path": None if self.path is None else str(self.path)}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> SceneRef:
        path = data.get("path")
        return cls(str(data["name"]), None if path is None else Path(path))


def resolve_scene(text: str) -> SceneRef:
    """A preset name or a scene file path; a ``ValueError`` naming it if neither exists."""
    if text in PRESETS:
        return SceneRef(text, PRESETS[text].path)
    path = Path(text)
    if not path.is_file():
        names = ", ".join(PRESETS)
        raise ValueError(f"--scene {text!r}: no such scene file, and not a preset ({names})")
    return SceneRef(path.stem, path.resolve())


def build_scene(ref: SceneRef, variant: Any, size: Size) -> Any:
    """(camera, world) for ``ref`` as ``variant`` (a registry ``Variant``) renders it: the
    world its tracer makes of the scene (``Variant.world_for``), the camera ``size``
    pixels."""
    if ref.path is None:
        if ref.name != BUILTIN_DEFAULT_WORLD:
            raise ValueError(f"scene {ref.name!r} has no file and is not built in")
        return _default_world_scene(variant.api, size)

    scene = load_scene(ref.path, variant.api, variant=variant.name, provide_mesh=provide)
    scene = scene.resized(size.width, size.height)
    return scene.camera, variant.world_for(scene)


def _default_world_scene(api: Mapping[str, Any], size: Size) -> Any:
    """Chapter 7: the default world through the camera of the book's render test."""
    view = api["view_transform"](
        api["point"](0, 0, -5), api["point"](0, 0, 0), api["vector"](0, 1, 0)
    )
    cam = api["camera"](size.width, size.height, math.pi / 2)

    return updated(cam, transform=view), api["default_world"]()
