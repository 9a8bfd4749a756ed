"""Write the OBJ meshes the scenes and the benchmarks render (chapter 15's format).

    .venv/bin/python -m harness.scenery.make_meshes              # icosphere.obj, gem.obj
    .venv/bin/python -m harness.scenery.make_meshes --generated  # generated meshes (or NAMEs)

``icosphere.obj``: a unit icosahedron (20 triangles) with the sphere's normal at each vertex,
so that its faces become smooth triangles (``f v//vn``) and it shades almost like a sphere.
``gem.obj``: a faceted gem, a hexagonal crown and pavilion with polygon faces that the parser
fans into triangles (22 in all), in two named groups. Both are tiny on purpose (the naive
tracer has no bounding boxes, so every ray tests every triangle) and kept in git.

The generated meshes (``CATALOGUE``) are large, so they are not kept in git: they are written
into ``scenes/meshes/`` (ignored by git) when first needed, atomically (a temporary
file renamed into place), and are the same bytes every time. A scene file names one like any
OBJ file, relative to itself (``file: meshes/knot-23k.obj`` from ``scenes/``); the
scene loader asks ``provide`` for an OBJ file it cannot find, which writes it when its name is
in the catalogue. ``mesh_path(name)`` does the same for the benchmarks.

- ``ring-1k.obj``, ``ring-10k.obj``, ``ring-100k.obj``, ``ring-1m.obj``: a torus (radii 10 and
  4) with its tube pushed in and out by smooth noise (up to 1.2), so no two triangles are
  alike; an m x n grid of quads split in two, exactly 1,000, 10,000, 100,000 and 1,000,000
  flat triangles. Closed (every edge shared by two faces) and consistently wound: the book's
  normal, ``cross(e2, e1)``, points out of the tube. Ten times the size it is shown at (a
  scene scales it by 0.1): chapter 15's test misses a triangle when ``dot(e1, cross(d, e2))``
  is below EPSILON (1e-4) in object space, which at unit size (edges of about 0.005 for the
  million) would be every triangle of the largest ring for a ray of length 1.
- ``knot-23k.obj``: a stand-in for the bonus chapter's dragon: a tube (radius 0.16) along a
  (2, 3) torus knot (a trefoil), 575 rings of 20 corners, exactly 23,000 smooth triangles
  (``f v//vn``, a normal per vertex), closed, about 2.3 units across, centred on the origin.
- ``knot-368.obj``: the same knot, 23 rings of 8 corners: 368 smooth triangles, the size of
  the bonus chapter's low-poly teapot (``six-small-knots.yml`` renders six of them where
  ``six-knots.yml`` renders six of the large one: what the meshes themselves cost).
"""

from __future__ import annotations

import argparse
import math
import random
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from groundwork import files
from harness.scenery import SCENES

GENERATED = SCENES / "meshes"  # ignored by git (.gitignore): written when first needed
Vertex = tuple[float, float, float]
Face = tuple[int, int, int]


def _unit(v: Vertex) -> Vertex:
    length = math.sqrt(sum(c * c for c in v))
    return (v[0] / length, v[1] / length, v[2] / length)


def icosphere(splits: int = 0) -> tuple[list[Vertex], list[tuple[int, int, int]]]:
    """An icosahedron on the unit sphere, each face split into 4 ``splits`` times."""
    t = (1 + math.sqrt(5)) / 2
    vertices = [
        _unit(v)
        for v in [
            (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
            (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
            (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1),
        ]
    ]  # fmt: skip
    faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
        (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
        (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
        (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1),
    ]  # fmt: skip
    midpoints: dict[tuple[int, int], int] = {}

    def midpoint(a: int, b: int) -> int:
        key = (min(a, b), max(a, b))
        if key not in midpoints:
            va, vb = vertices[a], vertices[b]
            vertices.append(_unit(((va[0] + vb[0]) / 2, (va[1] + vb[1]) / 2, (va[2] + vb[2]) / 2)))
            midpoints[key] = len(vertices) - 1
        return midpoints[key]

    for _ in range(splits):
        split = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    return vertices, faces


def _number(x: float) -> str:
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def icosphere_obj() -> str:
    vertices, faces = icosphere()
    lines = [f"# a unit icosahedron: {len(faces)} triangles, one normal per vertex (smooth)"]
    lines += [f"v {' '.join(_number(c) for c in v)}" for v in vertices]
    lines += [f"vn {' '.join(_number(c) for c in v)}" for v in vertices]  # normal = position
    lines.append("g sphere")
    lines += [f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def gem_obj(sides: int = 6) -> str:
    """A gem standing on its tip: crown (table, upper ring) and pavilion (down to the tip)."""
    lines = [f"# a faceted gem: {sides}-sided table and crown, pavilion to a point (flat faces)"]
    ring = [
        (math.cos(2 * math.pi * (i + 0.5) / sides), 1.0, math.sin(2 * math.pi * (i + 0.5) / sides))
        for i in range(sides)
    ]
    table = [(0.55 * x, 1.45, 0.55 * z) for x, _, z in ring]
    tip = (0.0, 0.0, 0.0)
    vertices = [*ring, *table, tip]  # 1..sides: girdle, sides+1..2*sides: table, last: tip
    lines += [f"v {' '.join(_number(c) for c in v)}" for v in vertices]
    girdle = list(range(1, sides + 1))
    top = list(range(sides + 1, 2 * sides + 1))
    tip_index = 2 * sides + 1
    lines.append("g crown")
    lines.append("f " + " ".join(str(i) for i in reversed(top)))  # the table: one polygon
    for i in range(sides):
        j = (i + 1) % sides
        lines.append(f"f {girdle[i]} {girdle[j]} {top[j]} {top[i]}")  # a quad, fanned in two
    lines.append("g pavilion")
    for i in range(sides):
        j = (i + 1) % sides
        lines.append(f"f {girdle[j]} {girdle[i]} {tip_index}")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- generated meshes

GENERATOR_VERSION = 2  # in every generated file's first line: a file of another version is stale


@dataclass(frozen=True)
class MeshSpec:
    """One generated mesh: a tube around a closed curve, an ``around`` x ``across`` grid.

    name: the file name; kind: ``ring`` (a noisy torus, flat triangles) or ``knot`` (a
    trefoil tube, smooth triangles); around: rings of corners along the curve; across:
    corners around the tube; about: one line for listings.
    """

    name: str
    kind: str
    around: int
    across: int
    about: str

    @property
    def triangles(self) -> int:
        return 2 * self.around * self.across

    @property
    def vertices(self) -> int:
        return self.around * self.across

    @property
    def smooth(self) -> bool:
        return self.kind == "knot"

    def header(self) -> str:
        """The file's first line (``is_current`` compares it)."""
        return (
            f"# rtc-workbook generated mesh {self.name} (generator {GENERATOR_VERSION}): "
            f"{self.about}; {self.triangles} triangles, {self.vertices} vertices"
        )


CATALOGUE: dict[str, MeshSpec] = {
    spec.name: spec
    for spec in (
        MeshSpec("ring-1k.obj", "ring", 25, 20, "a noisy torus"),
        MeshSpec("ring-10k.obj", "ring", 100, 50, "a noisy torus"),
        MeshSpec("ring-100k.obj", "ring", 250, 200, "a noisy torus"),
        MeshSpec("ring-1m.obj", "ring", 1000, 500, "a noisy torus"),
        MeshSpec("knot-23k.obj", "knot", 575, 20, "a trefoil knot tube (the dragon's stand-in)"),
        MeshSpec("knot-368.obj", "knot", 23, 8, "a coarse trefoil knot tube (the teapot's size)"),
    )
}
SCALE_MESHES = ("ring-1k.obj", "ring-10k.obj", "ring-100k.obj", "ring-1m.obj")
"""The meshes of the scene-size benchmark, smallest first."""

RING_RADIUS, RING_TUBE, RING_BUMPS = 10.0, 4.0, 1.2  # the torus and how far noise moves it
RING_SCALE = 10.0  # the ring's unit: a scene scales it by 1 / RING_SCALE (see the module)
KNOT_P, KNOT_Q, KNOT_RADIUS, KNOT_LOOP, KNOT_TUBE = 2, 3, 0.8, 0.35, 0.16
NOISE_SEED, NOISE_WAVES = 15, 8

Curve = Callable[[float], Vertex]


def _sub(a: Vertex, b: Vertex) -> Vertex:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _dot(a: Vertex, b: Vertex) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a: Vertex, b: Vertex) -> Vertex:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def noise(seed: int = NOISE_SEED, waves: int = NOISE_WAVES) -> Callable[[Vertex], float]:
    """A smooth function of space between -1 and 1: a sum of plane waves in random
    directions (``random.Random(seed)``: the same waves on every run and machine)."""
    rng = random.Random(seed)
    terms = []
    for _ in range(waves):
        direction = _unit((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        frequency = rng.uniform(2.0, 7.0)
        terms.append(
            (
                direction[0] * frequency,
                direction[1] * frequency,
                direction[2] * frequency,
                rng.uniform(0, 2 * math.pi),
                1 / frequency,
            )
        )
    total = sum(t[4] for t in terms)
    terms = [(a, b, c, phase, weight / total) for a, b, c, phase, weight in terms]

    def value(p: Vertex) -> float:
        x, y, z = p
        return sum(w * math.sin(a * x + b * y + c * z + ph) for a, b, c, ph, w in terms)

    return value


def _ring_curve(t: float) -> Vertex:
    return (RING_RADIUS * math.cos(t), 0.0, RING_RADIUS * math.sin(t))


def _ring_outward(t: float) -> Vertex:
    return (math.cos(t), 0.0, math.sin(t))


def _knot_curve(t: float) -> Vertex:
    """The (p, q) torus knot around the y axis: p turns around it, q loops through it."""
    r = KNOT_RADIUS + KNOT_LOOP * math.cos(KNOT_Q * t)
    return (r * math.cos(KNOT_P * t), KNOT_LOOP * math.sin(KNOT_Q * t), r * math.sin(KNOT_P * t))


def _knot_outward(t: float) -> Vertex:
    """From the knot's core circle to the knot: never zero, so the tube's frame is smooth."""
    core = (KNOT_RADIUS * math.cos(KNOT_P * t), 0.0, KNOT_RADIUS * math.sin(KNOT_P * t))
    return _sub(_knot_curve(t), core)


def tube(
    spec: MeshSpec, curve: Curve, outward: Curve, radius: Callable[[Vertex, Vertex], float]
) -> tuple[list[Vertex], list[Vertex], list[Face]]:
    """Vertices, unit normals of the undisturbed tube, and faces (0-based) of a tube around
    the closed ``curve`` (t from 0 to 2π).

    outward: a direction across the curve at t (the frame's first axis, made perpendicular
    to the tangent); radius(on_tube, direction): the tube's radius at a corner, given where
    the corner would be on a tube of radius 1 and the direction from the curve to it. Faces
    are wound so that the book's normal, ``cross(p3 - p1, p2 - p1)``, points away from the
    curve.
    """
    vertices: list[Vertex] = []
    normals: list[Vertex] = []
    h = 1e-5
    for i in range(spec.around):
        t = 2 * math.pi * i / spec.around
        centre = curve(t)
        tangent = _unit(_sub(curve(t + h), curve(t - h)))
        u = outward(t)
        along = _dot(u, tangent)
        n = _unit((u[0] - along * tangent[0], u[1] - along * tangent[1], u[2] - along * tangent[2]))
        b = _cross(tangent, n)
        for j in range(spec.across):
            phi = 2 * math.pi * j / spec.across
            c, s = math.cos(phi), math.sin(phi)
            d = (c * n[0] + s * b[0], c * n[1] + s * b[1], c * n[2] + s * b[2])
            r = radius((centre[0] + d[0], centre[1] + d[1], centre[2] + d[2]), d)
            vertices.append((centre[0] + r * d[0], centre[1] + r * d[1], centre[2] + r * d[2]))
            normals.append(d)
    faces: list[Face] = []
    for i in range(spec.around):
        i1 = (i + 1) % spec.around
        for j in range(spec.across):
            j1 = (j + 1) % spec.across
            a, b2 = i * spec.across + j, i1 * spec.across + j
            c2, d2 = i1 * spec.across + j1, i * spec.across + j1
            faces.append((a, b2, d2))
            faces.append((b2, c2, d2))
    return vertices, normals, faces


def generate(spec: MeshSpec) -> tuple[list[Vertex], list[Vertex], list[Face]]:
    """The mesh ``spec`` describes: vertices, normals (one per vertex) and 0-based faces."""
    if spec.kind == "ring":
        bumps = noise()

        def ring_radius(on_tube: Vertex, direction: Vertex) -> float:
            # the noise of the undisturbed surface's point, in the ring's unit
            at = [
                (p + (RING_TUBE - 1) * d) / RING_SCALE
                for p, d in zip(on_tube, direction, strict=True)
            ]
            return RING_TUBE + RING_BUMPS * bumps((at[0], at[1], at[2]))

        return tube(spec, _ring_curve, _ring_outward, ring_radius)
    if spec.kind == "knot":
        return tube(spec, _knot_curve, _knot_outward, lambda p, d: KNOT_TUBE)
    raise ValueError(f"unknown mesh kind {spec.kind!r}")


def mesh_lines(spec: MeshSpec) -> Iterator[str]:
    """The OBJ text of ``spec``, line by line (no newlines)."""
    vertices, normals, faces = generate(spec)
    yield spec.header()
    for v in vertices:
        yield f"v {_number(v[0])} {_number(v[1])} {_number(v[2])}"
    if spec.smooth:
        for n in normals:
            yield f"vn {_number(n[0])} {_number(n[1])} {_number(n[2])}"
        yield f"g {spec.name.removesuffix('.obj')}"
        for a, b, c in faces:
            yield f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}"
    else:
        yield f"g {spec.name.removesuffix('.obj')}"
        for a, b, c in faces:
            yield f"f {a + 1} {b + 1} {c + 1}"


def write_atomically(path: Path, lines: Iterator[str]) -> Path:
    """Write ``lines`` to ``path`` through a temporary file in the same folder, renamed
    into place: a reader sees the whole file or none (an interrupted write leaves nothing)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return files.write_atomically(path, "".join(f"{line}\n" for line in lines).encode("ascii"))


def is_current(path: Path, spec: MeshSpec) -> bool:
    """Whether ``path`` is this generator's ``spec`` (its first line says so)."""
    try:
        with path.open(encoding="ascii", errors="replace") as text:
            return text.readline().rstrip("\n") == spec.header()
    except OSError:
        return False


def mesh_path(name: str, folder: Path = GENERATED) -> Path:
    """The path of the generated mesh ``name`` in ``folder``, written first if it is missing
    or from another version of the generator. ``KeyError`` for a name not in ``CATALOGUE``."""
    spec = CATALOGUE[name]
    path = folder / name
    if not is_current(path, spec):
        write_atomically(path, mesh_lines(spec))
    return path


def provide(path: Path) -> bool:
    """For the scene loader: write the missing OBJ file ``path`` if it is a generated mesh
    in the project's own mesh folder (``GENERATED``); whether it exists now (False for any
    other name or folder: a scene elsewhere never makes the loader write, or for a folder
    not writable)."""
    if path.name not in CATALOGUE or path.parent.resolve() != GENERATED.resolve():
        return False
    try:
        mesh_path(path.name, path.parent)
    except OSError:
        return False
    return path.is_file()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m harness.scenery.make_meshes", description=(__doc__ or "").split("\n\n")[0]
    )
    parser.add_argument(
        "--generated", nargs="*", metavar="NAME", default=None,
        help=f"write the generated meshes into {GENERATED} (all, or the names given: "
        f"{', '.join(CATALOGUE)}) instead of the two small ones",
    )  # fmt: skip
    parser.add_argument(
        "--folder", type=Path, default=GENERATED, metavar="DIR",
        help="where --generated writes (default: scenes/meshes)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.generated is None:
        for name, text in (("icosphere.obj", icosphere_obj()), ("gem.obj", gem_obj())):
            write_atomically(SCENES / name, iter(text.splitlines()))
            print(f"wrote {SCENES / name}")
        return 0
    unknown = [name for name in args.generated if name not in CATALOGUE]
    if unknown:
        parser.error(f"unknown mesh {', '.join(unknown)}; known: {', '.join(CATALOGUE)}")
    for name in args.generated or list(CATALOGUE):
        spec = CATALOGUE[name]
        path = mesh_path(name, args.folder)
        print(f"{path}: {spec.triangles:,} triangles, {spec.vertices:,} vertices ({spec.about})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
