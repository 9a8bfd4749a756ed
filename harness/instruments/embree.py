"""Embree as a measuring stick for the mesh kernel (the bonus chapter "Bounding boxes and
hierarchies"): primary rays against a triangle mesh, intersection only, through ``embreex``.

Embree 4 is Intel's ray-intersection library in C++ (SIMD traversal of a hierarchy built for
the CPU); ``embreex`` is its Python binding on PyPI, an optional dependency (the ``anchors``
extra: ``pip install -e '.[anchors]'``). A section sets it beside its own mesh rows, in the
same run, on the same mesh and camera::

    found = embree.find()          # None: not installed (``embree.missing()`` says why)
    rays = embree.primary_rays(c, positions, triangles, repeat=3)
    rays.rays_per_second, rays.hits

What it times: ``EmbreeScene.run`` on every pixel's primary ray (chapter 7's
``ray_for_pixel``, one ray through each pixel's centre), the nearest hit only (no shading, no
shadow rays), on the calling thread; the scene's hierarchy is built before the clock starts.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np

from raytracer.camera import Camera

INSTALL = "pip install -e '.[anchors]'"


@dataclass(frozen=True)
class Embree:
    """The binding's two modules: the scene (``rtcore_scene``) and the meshes
    (``mesh_construction``), and the binding's version."""

    scenes: ModuleType
    meshes: ModuleType
    version: str


@dataclass(frozen=True)
class PrimaryRays:
    """One measurement: ``rays`` per pass, the wall and CPU seconds of each of ``repeat``
    passes (the calling thread's CPU: the pass runs on it), and how many rays hit the mesh."""

    rays: int
    seconds: tuple[float, ...]
    cpu: tuple[float, ...]
    hits: int
    version: str

    @property
    def median(self) -> float:
        return statistics.median(self.seconds)

    @property
    def rays_per_second(self) -> float:
        return self.rays / self.median

    def as_dict(self) -> dict[str, Any]:
        return {
            "rays": self.rays, "seconds": list(self.seconds), "median": self.median,
            "cpu": list(self.cpu), "cpu_median": statistics.median(self.cpu),
            "rays_per_second": self.rays_per_second, "hits": self.hits,
            "version": self.version,
        }  # fmt: skip


def find() -> Embree | None:
    """The binding if it can be imported, else None (``missing`` says why)."""
    try:
        from importlib.metadata import version

        from embreex import mesh_construction, rtcore_scene
    except ImportError:
        return None
    return Embree(rtcore_scene, mesh_construction, f"Embree through embreex {version('embreex')}")


def missing() -> str:
    """Why there is no Embree here, in one line."""
    return f"embreex (Embree's Python binding) is not installed ({INSTALL})"


def camera_rays(c: Camera) -> tuple[np.ndarray, np.ndarray]:
    """Chapter 7's ``ray_for_pixel`` for every pixel of ``c``, row by row: origins and unit
    directions, each (pixels, 3)."""
    inverse = np.array(c.inverse_transform.rows, dtype=np.float64)
    ys, xs = np.mgrid[0 : c.vsize, 0 : c.hsize]
    world_x = c.half_width - (xs.ravel() + 0.5) * c.pixel_size
    world_y = c.half_height - (ys.ravel() + 0.5) * c.pixel_size
    targets = np.stack([world_x, world_y, -np.ones_like(world_x), np.ones_like(world_x)])
    pixels = (inverse @ targets)[:3].T
    origin = inverse[:3, 3]
    directions = pixels - origin
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    return np.broadcast_to(origin, directions.shape).copy(), directions


def primary_rays(
    c: Camera,
    positions: np.ndarray,
    triangles: np.ndarray,
    repeat: int = 3,
    found: Embree | None = None,
) -> PrimaryRays:
    """Every pixel's primary ray of camera ``c`` against the mesh (world-space ``positions``,
    (n, 3); ``triangles``, (m, 3) indices into them), ``repeat`` times; ``LookupError``
    (``missing``) without the binding."""
    found = found or find()
    if found is None:
        raise LookupError(missing())
    if repeat < 1:
        raise ValueError(f"repeat must be at least 1, not {repeat}")
    origins, directions = (a.astype(np.float32) for a in camera_rays(c))
    scene = found.scenes.EmbreeScene()
    found.meshes.TriangleMesh(
        scene, np.ascontiguousarray(positions, np.float32),
        np.ascontiguousarray(triangles, np.int32),
    )  # fmt: skip
    hit = scene.run(origins[:1], directions[:1])  # the hierarchy is built on the first query
    seconds, cpu = [], []
    for _ in range(repeat):
        # the calling thread's CPU: Embree's own worker threads (its hierarchy builders)
        # may spin on the other cores after a build, which the query does not use
        started, started_cpu = time.perf_counter(), time.thread_time()
        hit = scene.run(origins, directions)
        seconds.append(time.perf_counter() - started)
        cpu.append(time.thread_time() - started_cpu)
    hits = int(np.count_nonzero(hit >= 0))
    return PrimaryRays(len(origins), tuple(seconds), tuple(cpu), hits, found.version)
