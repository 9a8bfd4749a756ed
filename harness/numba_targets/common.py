"""What every figure of ``harness.numba_targets`` uses: the scenes, a timed render, a
median over runs with the CPU share each run got, a picture's difference."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from harness.scenery import SCENES
from harness.scenery.make_meshes import provide
from raytracer.camera import RenderSettings
from scene import load_scene
from variants.registry import load_variant

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = SCENES / "reference.yml"
CPP = SCENES / "cpp-spheres.yml"
ONE_STEP = 1.0 / 255.0
EPSILONS = (0.0001, 0.001)  # the project's (the book's) and the Go renderer's


def load(
    variant_name: str, path: Path, size: tuple[int, int] | None = None
) -> tuple[Any, Any, Any]:
    variant = load_variant(variant_name)
    scene = load_scene(path, variant.api, variant=variant.name, provide_mesh=provide)
    if size is not None:
        scene = scene.resized(*size)
    return variant, scene.camera, variant.world_for(scene)


def timed(action: Callable[[], Any]) -> tuple[float, float, Any]:
    """(wall seconds, CPU share, result) of one call."""
    cpu = time.process_time()
    wall = time.perf_counter()
    result = action()
    wall = time.perf_counter() - wall
    cpu = time.process_time() - cpu
    return wall, cpu / wall if wall > 0 else 0.0, result


def render_once(variant: Any, c: Any, w: Any, settings: Any) -> Any:
    return variant.api["render"](c, w, settings)


def median_runs(action: Callable[[], Any], runs: int) -> tuple[float, list[tuple[float, float]]]:
    samples = [timed(action)[:2] for _ in range(runs)]
    return statistics.median(w for w, _ in samples), samples


def shares(samples: list[tuple[float, float]]) -> str:
    return ", ".join(f"{w:.3f}s@{s:.2f}" for w, s in samples)


def verdict(ok: bool) -> str:
    return "met" if ok else "NOT met"


def render_settings(**changes: Any) -> Any:
    return RenderSettings(**changes)


def difference(got: np.ndarray, expected: np.ndarray) -> str:
    """Max and mean difference per channel, and pixels beyond 1/255, of clamped colors."""
    a = np.clip(got, 0.0, 1.0)
    b = np.clip(expected, 0.0, 1.0)
    difference = np.abs(a - b)
    beyond = int((difference.max(axis=-1) > ONE_STEP).sum())
    pixels = difference.size // 3
    return (
        f"max {difference.max():.2g}, mean {difference.mean():.2g}, {beyond} of {pixels} "
        "pixels beyond 1/255"
    )
