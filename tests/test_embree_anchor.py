"""Embree beside the mesh rows (issue 36): the camera's rays, the measuring function on a tiny
mesh against the book's triangles, the scene-size entry with and without ``embreex``, and the
report's rows."""

from __future__ import annotations

import math
import threading
import time
import tomllib
from pathlib import Path
from types import ModuleType, SimpleNamespace
from typing import Any

import numpy as np
import pytest
from packaging.requirements import Requirement

import raytracer as book
from groundwork.sizes import Size
from harness.document.model import Table, to_markdown
from harness.instruments import embree
from harness.sections.ladder import mesh
from harness.sections.ladder import report as ladder_report
from harness.sections.scene_size import anchor
from harness.sections.scene_size import report as scene_size_report
from harness.sections.scene_size.measure import SECTION, scene_text
from scene.obj_mesh import read_mesh

ROOT = Path(__file__).resolve().parent.parent
ICOSPHERE = ROOT / "scenes" / "icosphere.obj"


def embree_installable_here() -> bool:
    """Whether the ``anchors`` extra (which the gate installs) brings ``embreex`` here."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    (spelled,) = [r for r in project["optional-dependencies"]["anchors"] if "embreex" in r]
    marker = Requirement(spelled).marker
    return marker is None or marker.evaluate()


def found_embree() -> embree.Embree:
    """The binding; a failure (not a skip) where the gate installs it."""
    found = embree.find()
    if found is None:
        if embree_installable_here():
            pytest.fail(f"the anchors extra installs embreex here, yet: {embree.missing()}")
        pytest.skip("embreex has no wheel for this platform (the anchors extra leaves it out)")
    return found


def small_camera(width: int = 16, height: int = 12) -> Any:
    c = book.camera(width, height, math.pi / 3)
    view = book.view_transform(book.point(0.3, 0.4, -3), book.point(0, 0, 0), book.vector(0, 1, 0))
    return book.Camera(c.hsize, c.vsize, c.field_of_view, view)


def test_the_camera_rays_are_chapter_7s_ray_for_pixel() -> None:
    c = small_camera(5, 3)
    origins, directions = embree.camera_rays(c)
    assert origins.shape == directions.shape == (15, 3)
    for y in range(3):
        for x in range(5):
            r = book.ray_for_pixel(c, x, y)
            i = y * 5 + x
            assert origins[i] == pytest.approx([r.origin.x, r.origin.y, r.origin.z], abs=1e-12)
            assert directions[i] == pytest.approx(
                [r.direction.x, r.direction.y, r.direction.z], abs=1e-12
            )


def test_primary_rays_hit_the_pixels_the_books_triangles_hit() -> None:
    found = found_embree()
    c = small_camera()
    model = read_mesh(ICOSPHERE.read_bytes(), str(ICOSPHERE))
    measured = embree.primary_rays(c, model.positions, model.triangles, repeat=2, found=found)
    triangles = [
        book.triangle(*(book.point(*map(float, model.positions[k])) for k in corners))
        for corners in model.triangles
    ]
    expected = 0
    for y in range(c.vsize):
        for x in range(c.hsize):
            r = book.ray_for_pixel(c, x, y)
            expected += any(book.hit(book.intersect(t, r)) is not None for t in triangles)
    assert 0 < expected < c.hsize * c.vsize  # the sphere and the sky both in the picture
    assert measured.hits == expected
    assert measured.rays == c.hsize * c.vsize and len(measured.seconds) == 2
    assert len(measured.cpu) == 2 and measured.rays_per_second > 0
    assert measured.version.startswith("Embree through embreex")
    assert set(measured.as_dict()) >= {"rays", "median", "cpu_median", "hits", "version"}


def burn_on_another_thread(burned: list[float]) -> None:
    """Another thread burns 0.2 s of its own CPU (its CPU seconds appended to ``burned``)
    while the calling thread sleeps in ``join``."""

    def burn() -> None:
        started = time.thread_time()
        while time.thread_time() - started < 0.2:
            pass
        burned.append(time.thread_time() - started)

    worker = threading.Thread(target=burn)
    worker.start()
    worker.join()


def test_the_cpu_counted_is_the_calling_threads_not_embrees_spinning_workers() -> None:
    """Embree's builder threads may spin after a build while the query runs on the calling
    thread alone; a fake binding whose query has another thread burn CPU meanwhile shows
    that only the calling thread's CPU is counted (the burn is joined before ``run`` returns,
    so it happens inside the timed call whatever the machine's load)."""
    burned: list[float] = []

    class Scene:
        def run(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
            burn_on_another_thread(burned)
            return np.full(len(origins), -1)

    scenes, meshes = ModuleType("fake_scenes"), ModuleType("fake_meshes")
    scenes.EmbreeScene = Scene  # type: ignore[attr-defined]
    meshes.TriangleMesh = lambda *args: None  # type: ignore[attr-defined]
    fake = embree.Embree(scenes, meshes, "fake")
    measured = embree.primary_rays(
        small_camera(2, 2), np.zeros((3, 3)), np.array([[0, 1, 2]]), 1, fake
    )
    assert len(burned) == 2 and min(burned) >= 0.2  # the first query builds, then one pass
    assert measured.cpu[0] < 0.1  # the process's CPU would be at least 0.2


def test_a_repeat_below_one_is_refused() -> None:
    with pytest.raises(ValueError, match="repeat must be at least 1"):
        embree.primary_rays(small_camera(), np.zeros((3, 3)), np.array([[0, 1, 2]]), 0)


def test_without_embreex_the_measure_says_why(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(embree, "find", lambda: None)
    with pytest.raises(LookupError, match=r"embreex .* not installed .*\[anchors\]"):
        embree.primary_rays(small_camera(), np.zeros((3, 3)), np.array([[0, 1, 2]]))


def test_the_scene_size_anchor_reads_the_sections_camera_and_world_mesh() -> None:
    camera, positions, triangles = anchor.world_mesh(scene_text(ICOSPHERE.name, Size(8, 6)),
                                                     ICOSPHERE)  # fmt: skip
    model = read_mesh(ICOSPHERE.read_bytes(), str(ICOSPHERE))
    assert (camera.hsize, camera.vsize) == (8, 6)
    assert positions == pytest.approx(model.positions * 0.1)  # the scene's scale
    assert (triangles == model.triangles).all()


def test_the_entry_measures_each_mesh_in_a_process_of_its_own(tmp_path: Path) -> None:
    found_embree()
    logged: list[str] = []
    folders = (tmp_path / f"job-{n}" for n in range(10))
    # the scene shows the mesh at a tenth of its size: a few pixels across at 80x60
    entry = anchor.entry({"icosphere.obj": (ICOSPHERE, 20)}, scene_text, Size(80, 60), 2,
                         folders, logged.append)  # fmt: skip
    assert entry["section"] == anchor.SECTION and entry["status"] == "ok"
    (point,) = entry["points"]
    assert point["mesh"] == "icosphere.obj" and point["triangles"] == 20
    assert point["rays"] == 4800 and 0 < point["hits"] < 100 and len(point["seconds"]) == 2
    assert "error" not in point and any("icosphere.obj" in line for line in logged)


def test_without_embreex_the_entry_has_no_points_and_one_line_why(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(embree, "find", lambda: None)
    logged: list[str] = []
    entry = anchor.entry({"icosphere.obj": (ICOSPHERE, 20)}, scene_text, Size(8, 6), 2,
                         iter([tmp_path / "never"]), logged.append)  # fmt: skip
    assert entry["status"] == "unavailable" and entry["points"] == []
    assert entry["error"] == embree.missing() and not (tmp_path / "never").exists()
    assert logged == [f"{anchor.SECTION}: Embree not run: {embree.missing()}"]


def run_with(embree_entry: dict[str, Any]) -> dict[str, Any]:
    ours = {
        "mesh": "ring-1k.obj", "triangles": 1000, "load": 0.01, "prepare": 0.01,
        "render": [0.04, 0.04], "render_median": 0.04, "cpu": [0.04, 0.04],
    }  # fmt: skip
    return {
        "settings": {
            "size": [100, 100], "samples": 1, "depth": 5, "threads": 1, "repeat": 2,
            "budget": None,
        },
        "series": [
            {"section": SECTION, "name": "numba", "status": "ok", "points": [ours]},
            embree_entry,
        ],
    }


def test_the_report_sets_embree_beside_our_renders() -> None:
    entry = {
        "section": anchor.SECTION, "name": "Embree", "status": "ok",
        "version": "Embree through embreex 4.4.0", "points": [
            {"mesh": "ring-1k.obj", "triangles": 1000, "rays": 10_000, "cpu_median": 0.01,
             "hits": 4_000},
            {"mesh": "ring-1m.obj", "triangles": 10**6, "error": "the process exited with 1"},
        ],
    }  # fmt: skip
    run = run_with(entry)
    blocks = scene_size_report.embree_blocks(run)
    text = to_markdown(blocks)
    assert "### Beside Embree" in text and "Embree through embreex 4.4.0" in text
    (table,) = [b for b in blocks if isinstance(b, Table)]
    first, failed = table.rows
    assert first[:4] == ["ring-1k.obj", "1,000", "10.0 ms (1.00 M/s)", "4,000 of 10,000"]
    assert first[4] == "`numba` 0.25 M/s (4.0x)"  # 10,000 pixels in 40 ms: 4x Embree's time
    assert failed[2].startswith("failed: the process exited")
    assert "### Beside Embree" in to_markdown(scene_size_report.blocks(run, None, ""))
    assert any(line.startswith("Embree ring-1k.obj") for line in
               scene_size_report.console_lines(run))  # fmt: skip


def test_the_report_says_in_one_line_why_embree_is_absent() -> None:
    entry = {"section": anchor.SECTION, "name": "Embree", "status": "unavailable",
             "error": embree.missing(), "points": []}  # fmt: skip
    run = run_with(entry)
    text = to_markdown(scene_size_report.embree_blocks(run))
    assert "**No Embree in this run:** embreex (Embree's Python binding) is not installed" in text
    assert text.count("\n\n") == 1  # the heading and one line
    assert not [b for b in scene_size_report.embree_blocks(run) if isinstance(b, Table)]
    assert "Embree: not run: embreex" in "\n".join(scene_size_report.console_lines(run))


# --- the ladder's mesh row -----------------------------------------------------------------


class FakeBench:
    """What ``mesh.entry`` uses of a bench: its log, its repeat and a folder for jobs."""

    def __init__(self, folder: Path) -> None:
        self.logged: list[str] = []
        self.settings = SimpleNamespace(repeat=2)
        self.folder = folder

    def log(self, line: str) -> None:
        self.logged.append(line)

    def jobs_folder(self, section: str) -> Path:
        return self.folder / section


def test_the_mesh_rows_render_counts_the_calling_threads_cpu_alone() -> None:
    """Another thread burning CPU during the render (Embree's builders spinning after its
    turn) is not counted: the burn is joined inside the timed render."""
    burned: list[float] = []

    class Tracer:
        def new_canvas(self, c: Any) -> None:
            return None

        def render_into(self, *args: Any) -> None:
            burn_on_another_thread(burned)

    assert mesh._render_cpu((Tracer(), None, None, None)) < 0.1  # the process's: >= 0.2
    assert burned and burned[0] >= 0.2


def test_the_mesh_job_renders_and_intersects_the_same_rays_in_turns() -> None:
    """At 8x6 (a third of 12x9's CPU seconds: naive's picture of 368 triangles is most of
    them) 20 of the 48 rays meet the knot: the picture still holds the knot and the sky."""
    found_embree()
    job = {"variant": "cached", "steps": ["naive"], "mesh": "knot-368.obj",
           "size": [8, 6], "rounds": 2}  # fmt: skip
    result = mesh.measure_job(job, Path("unused"))
    assert result["triangles"] == 368 and result["rays"] == 48
    assert 0 < result["hits"] < 48  # the knot and the sky around it
    assert len(result["ours"]) == len(result["embree"]) == len(result["ratios"]) == 2
    assert result["ratios"] == sorted(result["ratios"]) and result["ours_median"] > 0
    (step,) = result["steps"]  # the step rendered in the same turns
    assert step["variant"] == "naive" and len(step["ours"]) == len(step["ratios"]) == 2
    assert step["median"] > 0 and step["ratios"] == sorted(step["ratios"])


def test_the_mesh_jobs_warm_up_only_readies_the_variants_and_measures_nothing() -> None:
    # the bench's background compile runs it (``mesh.warm``): setups, no turns, no Embree
    job = {"variant": "cached", "steps": [], "mesh": "knot-368.obj", "size": [4, 3],
           "warm": True}  # fmt: skip
    assert mesh.measure_job(job, Path("unused")) == {"warmed": ["cached"]}


def test_without_embreex_the_mesh_row_says_why_and_runs_nothing(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(embree, "find", lambda: None)
    bench = FakeBench(tmp_path)
    entry = mesh.entry(bench, "ladder")  # type: ignore[arg-type]
    assert entry["status"] == "unavailable" and entry["error"] == embree.missing()
    assert entry["part"] == mesh.PART and list(tmp_path.iterdir()) == []
    assert bench.logged == [f"ladder: Embree not run: {embree.missing()}"]
    assert ladder_report.mesh_text(entry) == (
        f"**No Embree beside the mesh kernel in this run:** {embree.missing()}."
    )


def test_the_ladder_states_the_mesh_kernels_time_over_embrees() -> None:
    found = {
        "section": "ladder", "part": mesh.PART, "status": "ok", "variant": "numba[threads=1]",
        "mesh": "knot-23k.obj", "size": [640, 480], "triangles": 23000, "rays": 307200,
        "hits": 127282, "version": "Embree through embreex 4.4.0", "ours_median": 0.1,
        "embree_median": 0.04, "ratios": [2.0, 2.5, 3.0],
    }  # fmt: skip
    run = {"series": [found]}
    assert ladder_report.mesh_anchor(run) is found
    text = ladder_report.mesh_text(found)
    assert "`numba[threads=1]` renders" in text and "23,000 triangles" in text
    assert "in 100.0 ms CPU" in text and "in 40.0 ms: **2.50x** its time" in text
    assert "2.00-3.00x" in text
    assert "In the same turns" not in text  # no steps measured
    step, told = mesh.STEPS[0]
    stepped = {**found, "steps": [{"variant": step, "median": 0.12, "ratios": [3.0]}]}
    assert text + f" In the same turns: `{step}` ({told}) 120.0 ms, 3.00x." == (
        ladder_report.mesh_text(stepped)
    )
