"""The generated meshes (``harness.scenery.make_meshes``): their counts, closed and consistently
wound surfaces, the same bytes on every run, atomic writes, and scene files that name them."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from harness.scenery import make_meshes
from harness.scenery.make_meshes import (
    CATALOGUE,
    GENERATED,
    SCALE_MESHES,
    MeshSpec,
    generate,
    is_current,
    mesh_lines,
    mesh_path,
    provide,
    write_atomically,
)
from raytracer.obj_file import parse_obj_file
from scene import SceneError, load_scene
from variants.registry import load_variant

ROOT = Path(__file__).resolve().parents[1]


def test_the_catalogue_has_the_counts_the_benchmarks_name() -> None:
    assert [CATALOGUE[n].triangles for n in SCALE_MESHES] == [1_000, 10_000, 100_000, 1_000_000]
    assert CATALOGUE["knot-23k.obj"].triangles == 23_000
    assert all(spec.vertices * 2 == spec.triangles for spec in CATALOGUE.values())
    assert GENERATED == ROOT / "scenes" / "meshes"


@pytest.mark.parametrize("name", ["ring-1k.obj", "knot-23k.obj"])
def test_a_mesh_parses_to_exactly_its_triangles_none_degenerate(name: str) -> None:
    spec = CATALOGUE[name]
    parser = parse_obj_file("\n".join(mesh_lines(spec)), require_faces=True)
    assert parser.triangles == spec.triangles
    assert parser.degenerate_triangles == 0
    assert len(parser.vertices) - 1 == spec.vertices
    assert len(parser.normals) - 1 == (spec.vertices if spec.smooth else 0)
    (named,) = parser.groups.values()
    assert len(named.children) == spec.triangles and not parser.default_group.children


@pytest.mark.parametrize(
    "spec", [MeshSpec("t.obj", "ring", 7, 5, "a test ring"), CATALOGUE["knot-23k.obj"]]
)
def test_every_edge_is_shared_by_two_faces_wound_opposite_ways(spec: MeshSpec) -> None:
    _, _, faces = generate(spec)
    directed = Counter(
        (a, b) for face in faces for a, b in zip(face, face[1:] + face[:1], strict=True)
    )
    assert set(directed.values()) == {1}  # no edge twice the same way: consistent winding
    assert all((b, a) in directed for a, b in directed)  # every edge has its twin: closed
    assert len(directed) == 3 * spec.triangles
    euler = spec.vertices - len(directed) // 2 + spec.triangles
    assert euler == 0  # a torus (and a knotted tube): genus 1


def _sub(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float]:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _cross(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@pytest.mark.parametrize("name", ["ring-1k.obj", "knot-23k.obj"])
def test_the_books_normal_of_every_face_points_out_of_the_tube(name: str) -> None:
    vertices, normals, faces = generate(CATALOGUE[name])
    for a, b, c in faces:
        e1, e2 = _sub(vertices[b], vertices[a]), _sub(vertices[c], vertices[a])
        n = (
            e2[1] * e1[2] - e2[2] * e1[1],
            e2[2] * e1[0] - e2[0] * e1[2],
            e2[0] * e1[1] - e2[1] * e1[0],
        )  # cross(e2, e1): the book's normal (chapter 15)
        out = [sum(normals[i][k] for i in (a, b, c)) for k in range(3)]
        assert sum(n[k] * out[k] for k in range(3)) > 0


def test_the_ring_is_a_torus_pushed_in_and_out_by_the_noise() -> None:
    vertices, _, _ = generate(CATALOGUE["ring-10k.obj"])
    tube = [math.hypot(math.hypot(x, z) - 10.0, y) for x, y, z in vertices]
    assert 4 - 1.2 <= min(tube) < 3.8 and 4.2 < max(tube) <= 4 + 1.2


def test_the_smallest_triangles_of_the_largest_ring_are_big_enough_for_the_books_test() -> None:
    # chapter 15 misses a triangle when |dot(e1, cross(d, e2))| < EPSILON (1e-4): a unit ray
    # head-on meets it only when |e1 x e2| is above that; the million ring keeps 10x more
    spec = MeshSpec("t.obj", "ring", 1000, 500, "the million ring's grid")
    vertices, _, faces = generate(spec)
    smallest = min(
        math.hypot(*_cross(_sub(vertices[b], vertices[a]), _sub(vertices[c], vertices[a])))
        for a, b, c in faces[::97]
    )
    assert smallest > 10 * 1e-4


def test_the_same_mesh_is_the_same_bytes_in_another_process(tmp_path: Path) -> None:
    here = "\n".join(mesh_lines(CATALOGUE["ring-1k.obj"])) + "\n"
    code = (
        "import sys; from pathlib import Path; from harness.scenery.make_meshes import mesh_path; "
        "sys.stdout.write(mesh_path('ring-1k.obj', Path(sys.argv[1])).read_text())"
    )
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    there = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, env=env,
        cwd=ROOT, check=True,
    ).stdout  # fmt: skip
    assert there == here
    assert here.startswith(
        f"# rtc-workbook generated mesh ring-1k.obj (generator {make_meshes.GENERATOR_VERSION})"
    )


# --- writing -----------------------------------------------------------------------------------


def test_mesh_path_writes_a_missing_mesh_once_and_keeps_a_current_one(tmp_path: Path) -> None:
    path = mesh_path("ring-1k.obj", tmp_path / "new")
    assert path == tmp_path / "new" / "ring-1k.obj" and is_current(path, CATALOGUE[path.name])
    before = path.stat().st_mtime_ns
    os.utime(path, ns=(before - 10**9, before - 10**9))
    assert mesh_path("ring-1k.obj", tmp_path / "new") == path
    assert path.stat().st_mtime_ns == before - 10**9  # not written again
    assert sorted(p.name for p in path.parent.iterdir()) == ["ring-1k.obj"]  # no leftovers


def test_a_mesh_of_another_generator_version_is_written_again(tmp_path: Path) -> None:
    stale = tmp_path / "ring-1k.obj"
    stale.write_text("# rtc-workbook generated mesh ring-1k.obj (generator 0)\nv 0 0 0\n")
    assert not is_current(stale, CATALOGUE["ring-1k.obj"])
    mesh_path("ring-1k.obj", tmp_path)
    assert is_current(stale, CATALOGUE["ring-1k.obj"])


def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "model.obj"
    target.write_text("old\n")

    def lines_then_failure() -> object:
        yield "v 0 0 0"
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_atomically(target, lines_then_failure())  # type: ignore[arg-type]
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["model.obj"]
    write_atomically(target, iter(["v 1 2 3", "v 4 5 6"]))
    assert target.read_text() == "v 1 2 3\nv 4 5 6\n"


def test_unknown_names_are_refused(tmp_path: Path) -> None:
    with pytest.raises(KeyError):
        mesh_path("teapot.obj", tmp_path)
    assert provide(tmp_path / "teapot.obj") is False
    assert not (tmp_path / "teapot.obj").exists()


def test_the_command_line_writes_the_generated_meshes_asked_for(tmp_path: Path) -> None:
    assert make_meshes.main(["--generated", "ring-1k.obj", "--folder", str(tmp_path)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["ring-1k.obj"]
    with pytest.raises(SystemExit):
        make_meshes.main(["--generated", "teapot.obj", "--folder", str(tmp_path)])


def test_the_generated_folder_is_ignored_by_git() -> None:
    done = subprocess.run(
        ["git", "check-ignore", "-q", "scenes/meshes/ring-1m.obj"], cwd=ROOT
    )
    assert done.returncode == 0


# --- scene files naming a generated mesh -----------------------------------------------------

SCENE = """\
- add: camera
  width: 4
  height: 3
  field-of-view: 1.0
  from: [0, 3, -4]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-4, 4, -4]
  intensity: [1, 1, 1]
- add: obj
  file: meshes/{name}
"""


def _leaves(shape: object) -> int:
    children = getattr(shape, "children", None)
    return 1 if children is None else sum(_leaves(child) for child in children)


def test_a_scene_naming_a_generated_mesh_gets_it_written_when_missing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(make_meshes, "GENERATED", tmp_path / "meshes")  # the project's, here
    scene = tmp_path / "scene.yml"
    scene.write_text(SCENE.format(name="ring-1k.obj"), encoding="utf-8")
    loaded = load_scene(scene, load_variant("naive").api, provide_mesh=provide)
    assert (tmp_path / "meshes" / "ring-1k.obj").is_file()
    (model,) = load_variant("naive").world_for(loaded).objects
    assert _leaves(model) == 1_000  # however the tracer divided the groups
    assert loaded.obj_files == ((tmp_path / "meshes" / "ring-1k.obj").resolve(),)


def test_a_generated_mesh_is_written_only_into_the_projects_mesh_folder(tmp_path: Path) -> None:
    scene = tmp_path / "scene.yml"
    scene.write_text(SCENE.format(name="ring-1k.obj"), encoding="utf-8")
    with pytest.raises(SceneError, match=r"scene.yml:12: OBJ file not found: .*ring-1k\.obj"):
        load_scene(scene, load_variant("naive").api, provide_mesh=provide)
    assert not (tmp_path / "meshes").exists()


def test_a_scene_naming_another_missing_file_is_still_an_error(tmp_path: Path) -> None:
    scene = tmp_path / "scene.yml"
    scene.write_text(SCENE.format(name="dragon.obj"), encoding="utf-8")
    with pytest.raises(SceneError, match=r"scene.yml:12: OBJ file not found: .*dragon\.obj"):
        load_scene(scene, load_variant("naive").api)
    assert not (tmp_path / "meshes").exists()
