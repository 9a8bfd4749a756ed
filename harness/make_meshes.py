"""Write the small OBJ meshes that ``harness/scenes/mesh.yml`` renders (chapter 15's format).

    .venv/bin/python -m harness.make_meshes     # rewrites harness/scenes/icosphere.obj, gem.obj

``icosphere.obj``: a unit icosahedron (20 triangles) with the sphere's normal at each vertex,
so that its faces become smooth triangles (``f v//vn``) and it shades almost like a sphere.
``gem.obj``: a faceted gem, a hexagonal crown and pavilion with polygon faces that the parser
fans into triangles (22 in all), in two named groups.

The meshes are tiny on purpose: the naive tracer has no bounding boxes, so every ray tests
every triangle.
"""

from __future__ import annotations

import math
from pathlib import Path

SCENES = Path(__file__).resolve().parent / "scenes"
Vertex = tuple[float, float, float]


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


def main() -> None:
    for name, text in (("icosphere.obj", icosphere_obj()), ("gem.obj", gem_obj())):
        (SCENES / name).write_text(text, encoding="ascii")
        print(f"wrote {SCENES / name}")


if __name__ == "__main__":
    main()
