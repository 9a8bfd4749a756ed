"""Embree beside the scene-size section's mesh rows (issue 36): the ``scene-size-embree`` entry.

For each mesh of the run, in a fresh process of its own (``python -m
harness.sections.scene_size.anchor JOB``), the section's scene file is read as the section's
renders read it (the same camera at the run's size, the mesh in world space through the
scene's transform) and ``harness.instruments.embree`` times every pixel's primary ray against
the mesh, intersection only, ``repeat`` times (median). Without ``embreex`` the entry says why
(``status: unavailable``) and has no points; the report prints that line instead of the rows.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from groundwork.sizes import Size
from harness.engine.jobs import job_main, run_in_child
from harness.instruments import embree
from scene import load_scene_text
from variants.registry import load_variant

SECTION = "scene-size-embree"
READER = "numba"  # whose book API reads the scene file (the OBJ file into arrays, not objects)

Log = Callable[[str], None]


def entry(
    meshes: dict[str, tuple[Path, int]],
    scene: Callable[[str, Size], str],
    size: Size,
    repeat: int,
    folders: Iterator[Path],
    log: Log,
) -> dict[str, Any]:
    """The entry: ``meshes`` maps a mesh's name to its file and triangle count; ``scene``
    writes the section's scene file for an OBJ file's name at a size; a point per mesh,
    each measured in a fresh process (one thread) in a folder of ``folders``."""
    result: dict[str, Any] = {"section": SECTION, "name": "Embree", "points": []}
    found = embree.find()
    if found is None:
        result.update(status="unavailable", error=embree.missing())
        log(f"{SECTION}: Embree not run: {result['error']}")
        return result
    result.update(status="ok", version=found.version)
    for name, (path, triangles) in meshes.items():
        log(f"{SECTION}: {found.version}, {name}")
        job = {
            "mesh": str(path.resolve()),
            "scene": scene(path.name, size),
            "repeat": repeat,
        }
        outcome = run_in_child(__name__, next(folders), job, 1)
        point = {"mesh": name, "triangles": triangles}
        if isinstance(outcome, int):
            point["error"] = f"the measuring process exited with {outcome}"
        else:
            point.update(outcome)
        result["points"].append(point)
    return result


def world_mesh(text: str, mesh: Path) -> tuple[Any, np.ndarray, np.ndarray]:
    """The scene file ``text`` (its OBJ file ``mesh``) read: its camera, and its one OBJ
    model's vertices in world space (n, 3) and triangles (m, 3)."""
    api = load_variant(READER).api
    scene = load_scene_text(text, api, path=mesh.parent / "scene.yml", variant=READER)
    spec = next(spec for spec in scene.objects if spec.mesh is not None)
    model, matrix = spec.mesh, np.array(spec.transform.rows, dtype=np.float64)
    assert model is not None  # found above
    return scene.camera, model.positions @ matrix[:3, :3].T + matrix[:3, 3], model.triangles


def measure_job(job: dict[str, Any], folder: Path) -> dict[str, Any]:
    """One mesh: Embree's primary rays (``embree.PrimaryRays.as_dict``)."""
    camera, positions, triangles = world_mesh(job["scene"], Path(job["mesh"]))
    return embree.primary_rays(camera, positions, triangles, int(job["repeat"])).as_dict()


def main(argv: list[str] | None = None) -> int:
    """``python -m harness.sections.scene_size.anchor JOB.json``: one mesh's job."""
    return job_main(measure_job, sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
