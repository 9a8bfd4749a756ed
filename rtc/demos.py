"""The "putting it together" programs of chapters 1 to 16, drawn with the reference tracer.

Each demo takes the canvas size and returns the picture (a ``Canvas``), or None for chapter
3, which only prints. Demos print what they compute as they go. Chapters 1 to 6 are small
programs; the scenes of chapters 7 to 16 are data (``rtc.chapter_scenes``), this project's
own compositions of what each chapter introduces, built here by one function.
"""

from __future__ import annotations

import functools
import math
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from raytracer import (
    CSG,
    Camera,
    Canvas,
    Color,
    Cone,
    Cube,
    Cylinder,
    Group,
    Material,
    Pattern,
    Plane,
    Shape,
    Sphere,
    Tuple,
    World,
    add_child,
    canvas,
    checkers_pattern,
    color,
    csg,
    gradient_pattern,
    group,
    hit,
    identity_matrix,
    intersect,
    inverse,
    lighting,
    material,
    matrix,
    normal_at,
    normalize,
    parse_obj_file,
    point,
    point_light,
    position,
    ray,
    render,
    ring_pattern,
    rotation_x,
    rotation_y,
    rotation_z,
    scaling,
    set_pattern_transform,
    shearing,
    stripe_pattern,
    translation,
    transpose,
    tuple_,
    vector,
    view_transform,
    write_pixel,
)
from raytracer.matrices import Matrix
from rtc.chapter_scenes import SCENES, Step
from rtc.chapter_scenes import Shape as ShapeRow

STEPS: dict[str, Callable[..., Matrix]] = {
    "translate": translation, "scale": scaling, "shear": shearing,
    "rotate_x": rotation_x, "rotate_y": rotation_y, "rotate_z": rotation_z,
}  # fmt: skip
"""A transform step of ``rtc.chapter_scenes`` by name."""
PATTERNS: dict[str, Callable[[Color, Color], Pattern]] = {
    "checkers": checkers_pattern, "stripes": stripe_pattern, "gradient": gradient_pattern,
    "rings": ring_pattern,
}  # fmt: skip
SHAPES: dict[str, Callable[..., Shape]] = {
    "sphere": Sphere, "plane": Plane, "cube": Cube, "cylinder": Cylinder, "cone": Cone,
}  # fmt: skip


@dataclass(frozen=True)
class Demo:
    """One chapter's program.

    chapter: the book chapter; title: what it draws; size: the default (width, height), or
    None when it draws nothing; draw: the program, given the size.
    """

    chapter: int
    title: str
    size: tuple[int, int] | None
    draw: Callable[[int, int], Canvas | None]


# --- small drawing helpers -------------------------------------------------------------


def fill(c: Canvas, paint: Color) -> None:
    """Paint every pixel of ``c``."""
    for y in range(c.height):
        for x in range(c.width):
            write_pixel(c, x, y, paint)


def dot_at(c: Canvas, x: float, y: float, paint: Color, radius: int = 1) -> None:
    """A square dot centred on (x, y), clipped to the canvas; radius 0 is a single pixel."""
    cx, cy = round(x), round(y)
    for py in range(cy - radius, cy + radius + 1):
        for px in range(cx - radius, cx + radius + 1):
            if 0 <= px < c.width and 0 <= py < c.height:
                write_pixel(c, px, py, paint)


# --- chapters 1 and 2: the projectile ---------------------------------------------------


def trajectory(
    start: Tuple, velocity: Tuple, gravity: Tuple, wind: Tuple, limit: int = 10_000
) -> list[Tuple]:
    """Chapter 1's ``tick`` repeated until the projectile is back on the ground (y <= 0).

    start: the launch point; velocity: per tick; gravity, wind: the environment's vectors.
    """
    positions = [start]
    where, speed = start, velocity
    while where.y > 0 and len(positions) < limit:
        where, speed = where + speed, speed + gravity + wind
        positions.append(where)
    return positions


def chapter1(width: int, height: int) -> Canvas:
    """A ball thrown at 45 degrees, at unit speed, into a light headwind."""
    path = trajectory(
        point(0, 1, 0), normalize(vector(1, 1, 0)), vector(0, -0.1, 0), vector(-0.01, 0, 0)
    )
    for tick, where in enumerate(path):
        print(f"  tick {tick:2d}: x = {where.x:7.3f}  y = {where.y:7.3f}")
    print(f"  landed after {len(path) - 1} ticks, {path[-1].x:.3f} units away")
    c = canvas(width, height)
    fill(c, color(0.05, 0.05, 0.1))
    span_x = max(where.x for where in path) or 1.0
    span_y = max(where.y for where in path) or 1.0
    margin = 0.08
    for where in path:
        x = (margin + (1 - 2 * margin) * where.x / span_x) * (width - 1)
        y = (1 - margin - (1 - 2 * margin) * max(where.y, 0.0) / span_y) * (height - 1)
        dot_at(c, x, y, color(1, 0.8, 0.2), radius=max(1, min(width, height) // 60))
    return c


def chapter2(width: int, height: int) -> Canvas:
    """The book's stronger throw (speed 11.25 up a 1:1.8 slope) on a 900x550 sky."""
    path = trajectory(
        point(0, 1, 0),
        normalize(vector(1, 1.8, 0)) * 11.25,
        vector(0, -0.1, 0),
        vector(-0.01, 0, 0),
    )
    print(f"  {len(path) - 1} ticks, landing {path[-1].x:.1f} units away")
    c = canvas(width, height)
    fill(c, color(0.02, 0.04, 0.12))
    sx, sy = width / 900, height / 550  # the trajectory was planned for 900x550
    ground = height - 1
    for x in range(width):
        write_pixel(c, x, ground, color(0.2, 0.5, 0.2))
    for where in path:
        dot_at(
            c,
            where.x * sx,
            ground - where.y * sy,
            color(1, 0.3, 0.1),
            radius=max(1, min(width, height) // 250),
        )
    return c


# --- chapter 3: matrix experiments ------------------------------------------------------


def _show(m: Matrix) -> str:
    # round(...) + 0.0 turns a rounded -0.0 into 0.0
    cells = [[f"{round(value, 5) + 0.0:9.5f}" for value in row] for row in m.rows]
    return "\n".join("    " + " ".join(row) for row in cells)


def _tuple(t: Tuple) -> str:
    return f"tuple({t.x:g}, {t.y:g}, {t.z:g}, {t.w:g})"


def chapter3(width: int, height: int) -> None:
    """The chapter's questions about inverses and transposes, answered by experiment."""
    del width, height
    a = matrix([[3, -9, 7, 3], [3, -8, 2, -9], [-4, 4, 4, 1], [-6, 5, -1, 1]])
    print("  1. The inverse of the identity matrix:")
    print(_show(inverse(identity_matrix)))
    print("  2. A matrix times its inverse (the identity, up to rounding):")
    print(_show(a * inverse(a)))
    print("  3. inverse(transpose(A)) and transpose(inverse(A)) (the same):")
    print(_show(inverse(transpose(a))))
    print(_show(transpose(inverse(a))))
    t = tuple_(1, 2, 3, 4)
    almost = matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    print(f"  4. identity * {_tuple(t)} = {_tuple(identity_matrix * t)}")
    rows = [list(row) for row in almost.rows]
    rows[1][2] = 5.0
    print(f"     with [1, 2] = 5: {_tuple(matrix(rows) * t)} (y picks up 5 z)")


# --- chapter 4: the clock --------------------------------------------------------------


def chapter4(width: int, height: int) -> Canvas:
    """Twelve hour marks: 12 o'clock rotated around y by π/6 at a time, seen from above."""
    c = canvas(width, height)
    fill(c, color(0.1, 0.1, 0.12))
    radius = 3 / 8 * min(width, height)
    size = max(1, min(width, height) // 50)
    twelve = point(0, 0, 1)
    for hour in range(12):
        mark = rotation_y(hour * math.pi / 6) * twelve
        x = width / 2 + mark.x * radius
        y = height / 2 - mark.z * radius  # +z is up on the canvas
        paint = color(1, 0.2, 0.2) if hour == 0 else color(0.9, 0.9, 0.9)
        dot_at(c, x, y, paint, radius=size * (2 if hour % 3 == 0 else 1))
    dot_at(c, width / 2, height / 2, color(0.6, 0.6, 0.6), radius=size)
    return c


# --- chapters 5 and 6: casting rays at a sphere by hand ----------------------------------


def _cast_at_sphere(
    width: int, height: int, shape: Shape, shade: Callable[[Tuple, Tuple, Shape], Color]
) -> Canvas:
    """Rays from an eye at z = -5 through a 7x7 wall at z = 10, shaded where they hit.

    shade: (hit point, ray direction, shape) -> color.
    """
    eye = point(0, 0, -5)
    wall_z, wall_size = 10.0, 7.0
    pixel_size = wall_size / min(width, height)
    c = canvas(width, height)
    for y in range(height):
        world_y = pixel_size * height / 2 - pixel_size * (y + 0.5)
        for x in range(width):
            world_x = -pixel_size * width / 2 + pixel_size * (x + 0.5)
            r = ray(eye, normalize(point(world_x, world_y, wall_z) - eye))
            h = hit(intersect(shape, r))
            if h is not None:
                write_pixel(c, x, y, shade(position(r, h.t), r.direction, h.object))
    return c


def chapter5(width: int, height: int) -> Canvas:
    """The red silhouette of a sphere squashed and sheared into a leaning egg."""
    shape = Sphere(transform=shearing(0.4, 0, 0, 0, 0, 0) * scaling(0.8, 1.1, 1))
    return _cast_at_sphere(width, height, shape, lambda p, d, s: color(1, 0, 0))


def chapter6(width: int, height: int) -> Canvas:
    """A purple sphere lit from the upper left with the Phong model."""
    shape = Sphere(material=material(color=color(1, 0.2, 1)))
    light = point_light(point(-10, 10, -10), color(1, 1, 1))

    def shade(where: Tuple, direction: Tuple, obj: Shape) -> Color:
        return lighting(obj.material, obj, light, where, -direction, normal_at(obj, where))

    return _cast_at_sphere(width, height, shape, shade)


# --- chapters 7 to 16: the scenes of rtc.chapter_scenes, built and rendered -------------


def _matrix(steps: tuple[Step, ...]) -> Matrix:
    """The transform of ``steps`` as the book writes it: left to right, multiplied."""
    return functools.reduce(operator.mul, (STEPS[step[0]](*step[1:]) for step in steps))


def _material(values: Mapping[str, Any]) -> Material:
    """``material()`` of a row's values: ``color`` as (r, g, b), a ``Pattern`` as its own."""
    given = dict(values)
    if "color" in given:
        given["color"] = color(*given["color"])
    if "pattern" in given:
        row = given["pattern"]
        pattern = PATTERNS[row.kind](color(*row.a), color(*row.b))
        if row.transform:
            set_pattern_transform(pattern, _matrix(row.transform))
        given["pattern"] = pattern
    return material(**given)


def _shapes(row: ShapeRow, shadows: bool) -> list[Shape]:
    """The shape (or the shapes a builder makes) of ``row``."""
    if row.kind in BUILDERS:
        return BUILDERS[row.kind](row)
    arguments = dict(row.options)
    if row.transform:
        arguments["transform"] = _matrix(row.transform)
    if row.material:
        arguments["material"] = _material(row.material)
    if not shadows:
        arguments["casts_shadow"] = False
    return [SHAPES[row.kind](**arguments)]


def draw_scene(chapter: int, width: int, height: int) -> Canvas:
    """Chapter ``chapter``'s scene (``rtc.chapter_scenes.SCENES``), rendered by the book's
    camera at ``width`` x ``height``."""
    scene = SCENES[chapter]
    objects = [shape for row in scene.shapes for shape in _shapes(row, scene.shadows)]
    w = World(objects, [point_light(point(*scene.light), color(1, 1, 1))])
    if scene.count:
        print("  " + scene.count.format(count=len(w.objects)))
    cam = Camera(
        width, height, scene.field_of_view,
        view_transform(point(*scene.eye), point(*scene.to), vector(0, 1, 0)),
    )  # fmt: skip
    return render(cam, w)


def _scene(chapter: int) -> Callable[[int, int], Canvas]:
    return functools.partial(draw_scene, chapter)


# --- the builders: chapters 14 to 16's shapes made by a program -------------------------


def _hexagon() -> Group:
    """The chapter's hexagon: six sides, each a group of a corner sphere and an edge
    cylinder, turned into place around y; corners gold, edges silver."""
    hexagon = group()
    for n in range(6):
        corner = Sphere(
            transform=translation(0, 0, -1) * scaling(0.25, 0.25, 0.25),
            material=material(color=color(0.9, 0.7, 0.2), specular=0.8),
        )
        edge = Cylinder(
            minimum=0, maximum=1,
            transform=translation(0, 0, -1) * rotation_y(-math.pi / 6)
            * rotation_z(-math.pi / 2) * scaling(0.25, 1, 0.25),
            material=material(color=color(0.75, 0.78, 0.85), specular=0.8),
        )  # fmt: skip
        side = group()
        side.transform = rotation_y(n * math.pi / 3)
        add_child(side, corner)
        add_child(side, edge)
        add_child(hexagon, side)
    return hexagon


def _hexagon_shape(row: ShapeRow) -> list[Shape]:
    """The hexagon of spheres and cylinders, one group of six groups, placed by ``row``."""
    hexagon = _hexagon()
    hexagon.transform = _matrix(row.transform)
    leaves = sum(len(side.children) for side in hexagon.children if isinstance(side, Group))
    print(f"  1 group of {len(hexagon.children)} groups, {leaves} shapes in all")
    return [hexagon]


# --- chapter 15: triangles and OBJ files ------------------------------------------------


def icosahedron_obj() -> str:
    """OBJ text for a unit icosahedron, twice: group ``Flat`` has plain faces, group
    ``Smooth`` names a normal at every corner (pointing away from the centre)."""
    phi = (1 + math.sqrt(5)) / 2
    corners = [
        (-1, phi, 0), (1, phi, 0), (-1, -phi, 0), (1, -phi, 0),
        (0, -1, phi), (0, 1, phi), (0, -1, -phi), (0, 1, -phi),
        (phi, 0, -1), (phi, 0, 1), (-phi, 0, -1), (-phi, 0, 1),
    ]  # fmt: skip
    faces = [
        (1, 12, 6), (1, 6, 2), (1, 2, 8), (1, 8, 11), (1, 11, 12),
        (2, 6, 10), (6, 12, 5), (12, 11, 3), (11, 8, 7), (8, 2, 9),
        (4, 10, 5), (4, 5, 3), (4, 3, 7), (4, 7, 9), (4, 9, 10),
        (5, 10, 6), (3, 5, 12), (7, 3, 11), (9, 7, 8), (10, 9, 2),
    ]  # fmt: skip
    length = math.sqrt(1 + phi * phi)
    lines = ["# an icosahedron, generated by rtc demo 15", "o icosahedron"]
    lines += [f"v {x / length:.6f} {y / length:.6f} {z / length:.6f}" for x, y, z in corners]
    lines += [f"vn {x / length:.6f} {y / length:.6f} {z / length:.6f}" for x, y, z in corners]
    lines += ["g Flat"] + [f"f {a} {b} {c}" for a, b, c in faces]
    lines += ["g Smooth"] + [f"f {a}//{a} {b}//{b} {c}//{c}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def _icosahedra(row: ShapeRow) -> list[Shape]:
    """One icosahedron read from OBJ text twice: flat triangles on the left, smooth
    triangles (vertex normals) on the right, in ``row``'s material."""
    parser = parse_obj_file(icosahedron_obj())
    flat, smooth = parser.groups["Flat"], parser.groups["Smooth"]
    print(
        f"  parsed {len(parser.vertices) - 1} vertices, {len(parser.normals) - 1} normals, "
        f"{len(flat.children)} + {len(smooth.children)} triangles; "
        f"{parser.ignored_lines} line ignored"
    )
    paint = _material(row.material)
    for mesh, x in ((flat, -1.15), (smooth, 1.15)):
        mesh.transform = translation(x, 0, 0) * rotation_y(0.3)
        for face in mesh.children:
            face.material = paint
    return [flat, smooth]


# --- chapter 16: constructive solid geometry --------------------------------------------


def die() -> CSG:
    """A die: a cube with its edges rounded off by a sphere (an intersection), minus a group
    of small spheres for the pips (a difference). Faces 1 (front), 2 (top), 3 (right)."""
    ivory = material(color=color(0.95, 0.93, 0.85), diffuse=0.8, specular=0.4)
    ink = material(color=color(0.1, 0.1, 0.15), specular=0.2)
    body = csg("intersection", Cube(material=ivory), Sphere(
        transform=scaling(1.5, 1.5, 1.5), material=ivory
    ))  # fmt: skip
    pips = group()
    centres = [
        (0, 0, -1),  # one on the front
        (-0.45, 1, 0.45), (0.45, 1, -0.45),  # two on top
        (1, 0.45, -0.45), (1, 0, 0), (1, -0.45, 0.45),  # three on the right
    ]  # fmt: skip
    for x, y, z in centres:
        add_child(pips, Sphere(
            transform=translation(x, y, z) * scaling(0.2, 0.2, 0.2), material=ink
        ))  # fmt: skip
    return csg("difference", body, pips)


def _die_shape(row: ShapeRow) -> list[Shape]:
    """The die carved by CSG, placed by ``row``."""
    shape = die()
    shape.transform = _matrix(row.transform)
    print("  difference(intersection(cube, sphere), group of 6 spheres)")
    return [shape]


BUILDERS: dict[str, Callable[[ShapeRow], list[Shape]]] = {
    "hexagon": _hexagon_shape,
    "icosahedron": _icosahedra,
    "die": _die_shape,
}
"""The shapes of a row whose ``kind`` is none of the book's shapes, by kind."""


DEMOS: dict[int, Demo] = {
    demo.chapter: demo
    for demo in [
        Demo(1, "a projectile's flight, printed and plotted", (200, 100), chapter1),
        Demo(2, "a projectile's trajectory on a canvas", (900, 550), chapter2),
        Demo(3, "matrix experiments (printed, no picture)", None, chapter3),
        Demo(4, "a clock face: twelve hour marks", (200, 200), chapter4),
        Demo(5, "a sphere's silhouette", (100, 100), chapter5),
        Demo(6, "a shaded purple sphere", (100, 100), chapter6),
        Demo(7, "the first scene, no shadows", (100, 50), _scene(7)),
        Demo(8, "the first scene with shadows", (100, 50), _scene(8)),
        Demo(9, "spheres on planes", (100, 50), _scene(9)),
        Demo(10, "patterns", (100, 50), _scene(10)),
        Demo(11, "reflection and refraction", (64, 32), _scene(11)),
        Demo(12, "a table in a room, all cubes", (80, 40), _scene(12)),
        Demo(13, "cylinders and cones", (80, 40), _scene(13)),
        Demo(14, "a hexagon of groups", (64, 32), _scene(14)),
        Demo(15, "an OBJ icosahedron, flat and smooth", (48, 24), _scene(15)),
        Demo(16, "a die made by CSG", (56, 40), _scene(16)),
    ]
}
