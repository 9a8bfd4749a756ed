"""The scene file loader (the book's YAML scene format): every key reaches the world, and every
mistake is one ``SceneError`` naming the file and the line."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from textwrap import dedent
from typing import Any

import pytest

import scenes
from harness.scenery import make_meshes
from scene import Scene, SceneError, load_scene, load_scene_text
from variants.registry import load_variant

SCENES = scenes.FOLDER

CAMERA_AND_LIGHT = """\
- add: camera
  width: 40
  height: 20
  field-of-view: 0.8
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 0.9, 0.8]
"""  # 10 lines: a scene's own items start at line 11


@pytest.fixture(scope="module")
def api() -> Mapping[str, Any]:
    return load_variant("naive").api


def load(tmp_path: Path, api: Mapping[str, Any], body: str, *, header: bool = True) -> Scene:
    path = tmp_path / "scene.yml"
    path.write_text((CAMERA_AND_LIGHT if header else "") + dedent(body), encoding="utf-8")
    return load_scene(path, api, variant="naive")


def error(tmp_path: Path, api: Mapping[str, Any], body: str, *, header: bool = True) -> str:
    with pytest.raises(SceneError) as raised:
        load(tmp_path, api, body, header=header)
    return str(raised.value)


def only(scene: Scene) -> Any:
    assert len(scene.world.objects) == 1
    return scene.world.objects[0]


def same(a: Any, b: Any) -> bool:
    """Matrices (and tuples) equal within the book's EPSILON."""
    rows_a = a.rows if hasattr(a, "rows") else [[a.x, a.y, a.z, a.w]]
    rows_b = b.rows if hasattr(b, "rows") else [[b.x, b.y, b.z, b.w]]
    return all(
        abs(x - y) < 1e-9
        for ra, rb in zip(rows_a, rows_b, strict=True)
        for x, y in zip(ra, rb, strict=True)
    )


# --- every key reaches the world ---------------------------------------------------------


def test_the_camera_and_the_light(tmp_path: Path, api: Mapping[str, Any]) -> None:
    scene = load(tmp_path, api, "- add: sphere\n")
    c = scene.camera
    assert (c.hsize, c.vsize, c.field_of_view) == (40, 20, 0.8)
    view = api["view_transform"](api["point"](0, 1.5, -5), api["point"](0, 1, 0),
                                 api["vector"](0, 1, 0))  # fmt: skip
    assert same(c.transform, view)
    light = scene.world.light
    assert light.position == api["point"](-10, 10, -10)
    assert light.intensity == api["color"](1, 0.9, 0.8)
    assert (scene.camera_line, scene.light_line) == (1, 8)
    assert scene.path == tmp_path / "scene.yml" and scene.variant == "naive"


def test_resizing_keeps_the_field_of_view_and_the_view(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: sphere\n")
    bigger = scene.resized(160, 80)
    assert (bigger.camera.hsize, bigger.camera.vsize) == (160, 80)
    assert bigger.camera.field_of_view == 0.8 and bigger.camera.transform == scene.camera.transform
    assert bigger.objects is scene.objects and scene.camera.hsize == 40  # nothing read again


@pytest.mark.parametrize(
    ("entry", "book"),
    [
        ("[translate, 1, -2, 3]", ("translation", (1, -2, 3))),
        ("[scale, 2, 0.5, 4]", ("scaling", (2, 0.5, 4))),
        ("[rotate-x, 0.5]", ("rotation_x", (0.5,))),
        ("[rotate-y, 0.25]", ("rotation_y", (0.25,))),
        ("[rotate-z, 1.5]", ("rotation_z", (1.5,))),
        ("[shear, 1, 0, 0, 0.5, 0, 0]", ("shearing", (1, 0, 0, 0.5, 0, 0))),
    ],
)
def test_each_transform_entry(
    tmp_path: Path, api: Mapping[str, Any], entry: str, book: tuple[str, tuple[float, ...]]
) -> None:
    shape = only(load(tmp_path, api, f"- add: sphere\n  transform:\n    - {entry}\n"))
    function, arguments = book
    assert same(shape.transform, api[function](*arguments))


def test_transform_entries_apply_in_order_first_to_last(tmp_path: Path, api: Any) -> None:
    shape = only(
        load(tmp_path, api, """\
            - add: sphere
              transform:
                - [rotate-x, 1.5707963267948966]
                - [scale, 5, 5, 5]
                - [translate, 10, 5, 7]
            """)
    )  # fmt: skip
    expected = (
        api["translation"](10, 5, 7) * api["scaling"](5, 5, 5) * api["rotation_x"](math.pi / 2)
    )
    assert same(shape.transform, expected)
    assert same(shape.transform * api["point"](1, 0, 1), api["point"](15, 0, 7))


def test_every_material_key(tmp_path: Path, api: Mapping[str, Any]) -> None:
    shape = only(
        load(tmp_path, api, """\
            - add: sphere
              material:
                color: [0.1, 0.2, 0.3]
                ambient: 0.15
                diffuse: 0.6
                specular: 0.4
                shininess: 77
                reflective: 0.25
                transparency: 0.75
                refractive-index: 1.33
            """)
    )  # fmt: skip
    expected = api["material"]()
    m = shape.material
    assert type(m) is type(expected)
    assert m.color == api["color"](0.1, 0.2, 0.3)
    assert (m.ambient, m.diffuse, m.specular, m.shininess) == (0.15, 0.6, 0.4, 77)
    assert (m.reflective, m.transparency, m.refractive_index) == (0.25, 0.75, 1.33)
    assert m.pattern is None


def test_unset_material_keys_keep_the_books_defaults(tmp_path: Path, api: Any) -> None:
    m = only(load(tmp_path, api, "- add: sphere\n  material:\n    diffuse: 0.3\n")).material
    default = api["material"]()
    assert m.diffuse == 0.3
    assert (m.color, m.ambient, m.specular, m.shininess) == (
        default.color, default.ambient, default.specular, default.shininess,
    )  # fmt: skip


@pytest.mark.parametrize(
    ("kind", "factory"),
    [
        ("stripes", "stripe_pattern"),
        ("gradient", "gradient_pattern"),
        ("rings", "ring_pattern"),
        ("checkers", "checkers_pattern"),
    ],
)
def test_each_pattern(tmp_path: Path, api: Mapping[str, Any], kind: str, factory: str) -> None:
    shape = only(
        load(tmp_path, api, f"""\
            - add: plane
              material:
                pattern:
                  type: {kind}
                  colors:
                    - [1, 0, 0]
                    - [0, 0, 1]
                  transform:
                    - [scale, 0.5, 0.5, 0.5]
            """)
    )  # fmt: skip
    pattern = shape.material.pattern
    red, blue = api["color"](1, 0, 0), api["color"](0, 0, 1)
    assert type(pattern) is type(api[factory](red, blue))
    assert (pattern.a, pattern.b) == (red, blue)
    assert same(pattern.transform, api["scaling"](0.5, 0.5, 0.5))


def test_shadow_false_means_the_shape_casts_no_shadow(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: sphere\n  shadow: false\n- add: sphere\n")
    casting, default = scene.world.objects
    assert casting.casts_shadow is False and default.casts_shadow is True


@pytest.mark.parametrize("kind", ["sphere", "plane", "cube"])
def test_plain_shapes_are_the_variants_own(tmp_path: Path, api: Any, kind: str) -> None:
    assert type(only(load(tmp_path, api, f"- add: {kind}\n"))) is type(api[kind]())


@pytest.mark.parametrize("kind", ["cylinder", "cone"])
def test_min_max_and_closed(tmp_path: Path, api: Mapping[str, Any], kind: str) -> None:
    scene = load(tmp_path, api, f"- add: {kind}\n  min: -1\n  max: 2.5\n  closed: true\n"
                 f"- add: {kind}\n")  # fmt: skip
    cut, default = scene.world.objects
    assert type(cut) is type(api[kind]())
    assert (cut.minimum, cut.maximum, cut.closed) == (-1, 2.5, True)
    assert (default.minimum, default.maximum, default.closed) == (-math.inf, math.inf, False)


def test_a_group_and_its_children(tmp_path: Path, api: Mapping[str, Any]) -> None:
    g = only(
        load(tmp_path, api, """\
            - add: group
              transform:
                - [translate, 0, 1, 0]
              children:
                - add: sphere
                  transform:
                    - [scale, 2, 2, 2]
                - add: group
                  children:
                    - add: cube
            """)
    )  # fmt: skip
    assert type(g) is type(api["group"]())
    assert same(g.transform, api["translation"](0, 1, 0))
    sphere, inner = g.children
    assert same(sphere.transform, api["scaling"](2, 2, 2))
    assert sphere.parent is g and inner.parent is g
    assert type(inner.children[0]) is type(api["cube"]()) and inner.children[0].parent is inner


def test_a_groups_material_and_shadow_pass_down_to_children_without_their_own(
    tmp_path: Path, api: Any
) -> None:
    g = only(
        load(tmp_path, api, """\
            - add: group
              shadow: false
              material:
                color: [1, 0, 0]
              children:
                - add: sphere
                - add: sphere
                  material:
                    color: [0, 1, 0]
                  shadow: true
            """)
    )  # fmt: skip
    inherits, own = g.children
    assert inherits.material.color == api["color"](1, 0, 0) and inherits.casts_shadow is False
    assert own.material.color == api["color"](0, 1, 0) and own.casts_shadow is True


OBJ_TEXT = """\
v -1 1 0
v -1 0 0
v 1 0 0
v 1 1 0
f 1 2 3 4
g Second
f 1 3 4
"""


def test_an_obj_file_relative_to_the_scene_file(tmp_path: Path, api: Mapping[str, Any]) -> None:
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "quad.obj").write_text(OBJ_TEXT, encoding="utf-8")
    scene = load(tmp_path, api, """\
        - add: obj
          file: models/quad.obj
          transform:
            - [translate, 0, 0, 5]
          material:
            color: [0, 0, 1]
        """)  # fmt: skip
    model = only(scene)
    assert type(model) is type(api["group"]())
    assert same(model.transform, api["translation"](0, 0, 5))
    default_group, second = model.children
    triangles = [*default_group.children, *second.children]
    assert len(triangles) == 3  # the quad fans into two triangles, plus one in "Second"
    first = triangles[0]
    assert type(first) is type(api["triangle"](api["point"](0, 1, 0), api["point"](-1, 0, 0),
                                               api["point"](1, 0, 0)))  # fmt: skip
    assert (first.p1, first.p2, first.p3) == (
        api["point"](-1, 1, 0), api["point"](-1, 0, 0), api["point"](1, 0, 0),
    )  # fmt: skip
    assert all(t.material.color == api["color"](0, 0, 1) for t in triangles)
    assert scene.obj_files == ((tmp_path / "models" / "quad.obj").resolve(),)


@pytest.mark.parametrize("operation", ["union", "intersection", "difference"])
def test_a_csg(tmp_path: Path, api: Mapping[str, Any], operation: str) -> None:
    c = only(
        load(tmp_path, api, f"""\
            - add: csg
              operation: {operation}
              left:
                add: sphere
                transform:
                  - [translate, 0, 0, 0.5]
              right:
                add: cube
            """)
    )  # fmt: skip
    assert c.operation == operation
    assert type(c.left) is type(api["sphere"]()) and type(c.right) is type(api["cube"]())
    assert same(c.left.transform, api["translation"](0, 0, 0.5))
    assert c.left.parent is c and c.right.parent is c


def test_defined_materials_extend_earlier_ones(tmp_path: Path, api: Mapping[str, Any]) -> None:
    scene = load(tmp_path, api, """\
        - define: base
          value:
            ambient: 0.2
            diffuse: 0.3
        - define: red
          extend: base
          value:
            color: [1, 0, 0]
            diffuse: 0.5
        - add: sphere
          material: red
        """)  # fmt: skip
    m = only(scene).material
    assert (m.color, m.ambient, m.diffuse) == (api["color"](1, 0, 0), 0.2, 0.5)


def test_defined_transforms_mix_with_entries(tmp_path: Path, api: Mapping[str, Any]) -> None:
    scene = load(tmp_path, api, """\
        - define: lift
          value:
            - [translate, 0, 1, 0]
        - define: big-lift
          extend: lift
          value:
            - [scale, 3, 3, 3]
        - add: sphere
          transform:
            - [scale, 2, 2, 2]
            - big-lift
            - [rotate-y, 0.5]
        - add: sphere
          transform: lift
        """)  # fmt: skip
    mixed, named = scene.world.objects
    expected = (
        api["rotation_y"](0.5)
        * api["scaling"](3, 3, 3)
        * api["translation"](0, 1, 0)
        * api["scaling"](2, 2, 2)
    )
    assert same(mixed.transform, expected)
    assert same(named.transform, api["translation"](0, 1, 0))


def test_a_defined_shape_is_added_by_name_with_its_own_keys_on_top(
    tmp_path: Path, api: Any
) -> None:
    scene = load(tmp_path, api, """\
        - define: post
          value:
            add: cylinder
            min: 0
            max: 2
            closed: true
            transform:
              - [scale, 0.5, 1, 0.5]
            material:
              color: [1, 1, 0]
        - add: post
          transform:
            - [translate, 3, 0, 0]
          material:
            color: [0, 1, 1]
        - add: post
        """)  # fmt: skip
    moved, plain = scene.world.objects
    assert moved is not plain
    assert (moved.minimum, moved.maximum, moved.closed) == (0, 2, True)
    assert same(moved.transform, api["translation"](3, 0, 0) * api["scaling"](0.5, 1, 0.5))
    assert moved.material.color == api["color"](0, 1, 1)
    assert same(plain.transform, api["scaling"](0.5, 1, 0.5))
    assert plain.material.color == api["color"](1, 1, 0)


def test_a_defined_group_gives_new_children_every_time(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, """\
        - define: pair
          value:
            add: group
            children:
              - add: sphere
              - add: cube
        - add: pair
        - add: pair
        """)  # fmt: skip
    first, second = scene.world.objects
    assert first.children[0] is not second.children[0]
    assert first.children[0].parent is first and second.children[0].parent is second


# --- the project's scenes ------------------------------------------------------------------


def test_the_reference_scene_loads_as_described(api: Mapping[str, Any]) -> None:
    scene = load_scene(SCENES / "reference.yml", api)
    kinds = [type(o).__name__ for o in scene.world.objects]
    assert kinds == ["Plane", "Plane", "Plane", "Sphere", "Sphere", "Cylinder", "Group"]
    glass = scene.world.objects[3]
    assert (glass.material.transparency, glass.material.refractive_index) == (1.0, 1.57)
    assert (scene.camera.hsize, scene.camera.vsize) == (640, 480)
    assert len(scene.world.objects[6].children) == 3


@pytest.mark.parametrize("name", ["csg.yml", "shapes.yml", "mesh.yml"])
def test_the_projects_own_scenes_load(api: Mapping[str, Any], name: str) -> None:
    scene = load_scene(SCENES / name, api)
    assert scene.world.objects and scene.world.light is not None
    assert scene.camera.hsize * scene.camera.vsize <= 160 * 120  # quick to render


def test_the_shipped_meshes_are_what_the_generator_writes() -> None:
    assert (SCENES / "icosphere.obj").read_text() == make_meshes.icosphere_obj()
    assert (SCENES / "gem.obj").read_text() == make_meshes.gem_obj()


# --- every mistake: one error, the file and the line ---------------------------------------


def test_bad_indentation_reports_yamls_own_line(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, """\
        - add: sphere
          transform:
            - [scale, 1, 1, 1]
           material: red
        """)  # fmt: skip
    path = tmp_path / "scene.yml"
    assert message.startswith(f"{path}:14: invalid YAML: ")
    assert "check the indentation" in message


def test_a_tab_is_invalid_yaml_at_its_line(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n\ttransform: []\n")
    assert message.startswith(f"{tmp_path / 'scene.yml'}:12: invalid YAML: ")


def test_an_unknown_thing_to_add_lists_the_known_ones(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n- add: spere\n")
    assert message == (
        f"{tmp_path / 'scene.yml'}:12: unknown thing to add: 'spere'; known: camera, light, "
        "area_light, sky, render, sphere, plane, cube, cylinder, cone, torus, group, obj, csg, "
        "fir_branch"
    )


def test_an_unknown_key_lists_the_known_ones(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: cylinder\n  closed: true\n  maximum: 2\n")
    assert message == (
        f"{tmp_path / 'scene.yml'}:13: unknown key 'maximum' in a cylinder (did you mean "
        "'max'?); known keys: add, transform, material, shadow, min, max, closed"
    )


def test_an_unknown_material_key_lists_the_known_ones(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n  material:\n    colour: [1, 0, 0]\n")
    assert message.startswith(f"{tmp_path / 'scene.yml'}:13: unknown key 'colour' in ")
    assert "known keys: color, ambient, diffuse, specular, shininess, reflective, " in message
    assert "transparency, refractive-index, pattern" in message


def test_an_unknown_camera_key(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, CAMERA_AND_LIGHT.replace("  up:", "  upp:"), header=False)
    assert message.startswith(f"{tmp_path / 'scene.yml'}:7: unknown key 'upp' in the camera")
    assert "known keys: add, width, height, field-of-view, from, to, up" in message


def test_a_wrong_transform_arity_says_which_transform(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, """\
        - add: sphere
          transform:
            - [scale, 2, 2, 2]
            - [translate, 1, 2]
        """)  # fmt: skip
    assert message == (
        f"{tmp_path / 'scene.yml'}:14: the sphere at line 11: transform entry: 'translate' "
        "takes 3 numbers (x, y, z), got 2"
    )


def test_a_wrong_rotation_arity(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n  transform:\n    - [rotate-y, 1, 2]\n")
    assert message.endswith(":13: the sphere at line 11: transform entry: 'rotate-y' takes "
                            "1 number (radians), got 2")  # fmt: skip


def test_an_unknown_transform(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n  transform:\n    - [move, 1, 2, 3]\n")
    assert message.endswith(
        ":13: the sphere at line 11: transform entry: unknown transform 'move'; known: "
        "translate, scale, rotate-x, rotate-y, rotate-z, shear"
    )


def test_a_missing_obj_file_names_the_resolved_path(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: obj\n  file: meshes/teapot.obj\n")
    resolved = (tmp_path / "meshes" / "teapot.obj").resolve()
    assert message == (
        f"{tmp_path / 'scene.yml'}:12: OBJ file not found: {resolved} ('meshes/teapot.obj' "
        "is read relative to the scene file's folder)"
    )


def test_a_broken_obj_line_names_the_obj_file_and_its_line(tmp_path: Path, api: Any) -> None:
    (tmp_path / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", encoding="utf-8")
    message = error(tmp_path, api, "- add: sphere\n- add: obj\n  file: broken.obj\n")
    obj = (tmp_path / "broken.obj").resolve()
    assert message.startswith(
        f"{tmp_path / 'scene.yml'}:12: the OBJ file of the obj at line 12 is broken: "
        f"{obj}, line 4: 'f 1 2': "
    )
    assert "at least 3 corners" in message


@pytest.mark.parametrize(
    ("body", "line", "text"),
    [
        ("- add: sphere\n  material: shiny\n", 12,
         "the sphere at line 11: material: 'shiny' is not defined above this line "
         "(no material is defined); expected a name given earlier with '- define: shiny'"),
        ("- add: sphere\n  transform:\n    - lift\n", 13,
         "the sphere at line 11: transform entry: 'lift' is not defined above this line "
         "(no transform is defined); expected a name given earlier with '- define: lift'"),
        ("- add: sphere\n  material: later\n- define: later\n  value:\n    ambient: 1\n", 12,
         "the sphere at line 11: material: 'later' is not defined above this line"),
        ("- define: a\n  value:\n    ambient: 1\n- add: sphere\n  transform: a\n", 15,
         "the sphere at line 14: transform: 'a' (defined at line 11) is a material, "
         "not a transform"),
        ("- define: b\n  extend: nothing\n  value:\n    ambient: 1\n", 12,
         "define 'b': extend: 'nothing' is not defined above this line"),
    ],
)  # fmt: skip
def test_an_undefined_or_wrong_name(
    tmp_path: Path, api: Any, body: str, line: int, text: str
) -> None:
    message = error(tmp_path, api, body)
    assert message.startswith(f"{tmp_path / 'scene.yml'}:{line}: {text}")


@pytest.mark.parametrize(
    ("body", "line", "text"),
    [
        ("- add: sphere\n  material:\n    ambient: high\n", 13,
         "the sphere at line 11: material: ambient must be a number, got 'high'"),
        ("- add: sphere\n  transform:\n    - [scale, 1, two, 1]\n", 13,
         "the sphere at line 11: transform entry: 'scale' y must be a number, got 'two'"),
        ("- add: sphere\n  material:\n    diffuse: true\n", 13,
         "the sphere at line 11: material: diffuse must be a number, got true"),
        ("- add: sphere\n  material:\n    color: [1, 0]\n", 13,
         "the sphere at line 11: material: color must be a list of 3 numbers, got 2"),
        ("- add: cone\n  min: [1]\n", 12, "the cone at line 11: min must be a single value"),
        ("- add: sphere\n  shadow: 0\n", 12, "the sphere at line 11: shadow must be true or false"),
    ],
)  # fmt: skip
def test_a_non_number_where_a_number_belongs(
    tmp_path: Path, api: Any, body: str, line: int, text: str
) -> None:
    assert error(tmp_path, api, body).startswith(f"{tmp_path / 'scene.yml'}:{line}: {text}")


def test_numbers_in_exponent_form_are_numbers(tmp_path: Path, api: Any) -> None:
    # PyYAML (YAML 1.1) reads 1e-3 as a string; the scene format means a number
    shape = only(load(tmp_path, api, "- add: sphere\n  material:\n    ambient: 1e-3\n"))
    assert shape.material.ambient == 0.001


@pytest.mark.parametrize(
    ("value", "text"),
    [(".nan", "must be a number, got NaN"), (".inf", "must be a finite number, got infinity"),
     ("-.inf", "must be a finite number, got -infinity")],
)  # fmt: skip
def test_nan_and_infinity_are_refused(tmp_path: Path, api: Any, value: str, text: str) -> None:
    body = f"- add: sphere\n  transform:\n    - [translate, 0, {value}, 0]\n"
    message = error(tmp_path, api, body)
    assert message == (
        f"{tmp_path / 'scene.yml'}:13: the sphere at line 11: transform entry: 'translate' y {text}"
    )


def test_infinity_is_allowed_for_min_and_max(tmp_path: Path, api: Any) -> None:
    shape = only(load(tmp_path, api, "- add: cylinder\n  min: -.inf\n  max: 1\n"))
    assert (shape.minimum, shape.maximum) == (-math.inf, 1)


def test_a_singular_transform_names_the_object_and_its_line(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, """\
        - add: sphere
        - add: cube
          transform:
            - [scale, 1, 0, 1]
        """)  # fmt: skip
    assert message == (
        f"{tmp_path / 'scene.yml'}:13: the transform of the cube at line 12 is not invertible: "
        "its determinant is 0 (a scale by 0, or a shear that flattens space onto a plane); "
        "expected an invertible transform"
    )


def test_a_singular_pattern_transform(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, """\
        - add: plane
          material:
            pattern:
              type: stripes
              colors: [[1, 1, 1], [0, 0, 0]]
              transform:
                - [scale, 0, 1, 1]
        """)  # fmt: skip
    assert message.startswith(
        f"{tmp_path / 'scene.yml'}:17: the transform of the stripes pattern at line 14 is not "
        "invertible"
    )


def test_several_lights_are_added_in_order(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, "- add: sphere\n- add: light\n  at: [0, 5, 0]\n"
                 "  intensity: [0.5, 0.5, 0.5]\n")  # fmt: skip
    lights = scene.world.lights
    assert [light.position for light in lights] == [api["point"](-10, 10, -10),
                                                    api["point"](0, 5, 0)]  # fmt: skip
    assert scene.world.light is lights[0] and scene.light_line == 8
    assert scene.warnings == ()


def test_a_scene_without_light_loads_with_a_warning(tmp_path: Path, api: Any) -> None:
    scene = load(tmp_path, api, CAMERA_AND_LIGHT.split("- add: light")[0] + "- add: sphere\n",
                 header=False)  # fmt: skip
    assert scene.world.lights == []
    assert scene.warnings == (
        f"{tmp_path / 'scene.yml'}: the scene has no light, so every surface renders black; "
        "add one with '- add: light' (at, intensity)",
    )


def test_a_second_camera_is_refused(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, CAMERA_AND_LIGHT + CAMERA_AND_LIGHT, header=False)
    assert message == (
        f"{tmp_path / 'scene.yml'}:11: a second camera (the first is at line 1); a scene has "
        "one camera"
    )


def test_a_missing_camera(tmp_path: Path, api: Any) -> None:
    no_light = error(tmp_path, api, "- add: light\n  at: [0, 1, 0]\n  intensity: [1, 1, 1]\n",
                     header=False)  # fmt: skip
    assert no_light.startswith(f"{tmp_path / 'scene.yml'}: the scene has no camera; expected "
                               "'- add: camera' with width, height, field-of-view")  # fmt: skip


def test_a_camera_without_a_key_says_which(tmp_path: Path, api: Any) -> None:
    body = CAMERA_AND_LIGHT.replace("  field-of-view: 0.8\n", "")
    assert error(tmp_path, api, body, header=False) == (
        f"{tmp_path / 'scene.yml'}:1: the camera has no 'field-of-view'; it needs one"
    )


def test_a_degenerate_camera(tmp_path: Path, api: Any) -> None:
    body = CAMERA_AND_LIGHT.replace("up: [0, 1, 0]", "up: [0, -1, 10]")
    message = error(tmp_path, api, body, header=False)
    assert message.startswith(f"{tmp_path / 'scene.yml'}:7: the camera's 'up' is zero or points "
                              "along the line from 'from' to 'to'")  # fmt: skip


def test_a_yaml_alias_inside_itself_is_an_error_not_a_hang(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- &loop\n  add: group\n  children:\n    - *loop\n")
    assert message.startswith(
        f"{tmp_path / 'scene.yml'}:14: the alias *loop is inside the item it names (&loop, "
        "line 11): a shape inside itself nests without end"
    )


def test_a_key_given_twice(tmp_path: Path, api: Any) -> None:
    message = error(tmp_path, api, "- add: sphere\n  shadow: false\n  shadow: true\n")
    assert message == (
        f"{tmp_path / 'scene.yml'}:13: an item gives 'shadow' twice (first at line 12)"
    )


def test_a_variant_without_a_shape_says_so(tmp_path: Path, api: Mapping[str, Any]) -> None:
    partial = {name: value for name, value in api.items() if name not in ("cylinder", "group")}
    path = tmp_path / "scene.yml"
    path.write_text(CAMERA_AND_LIGHT + "- add: cylinder\n", encoding="utf-8")
    with pytest.raises(SceneError) as raised:
        load_scene(path, partial, variant="chapter11")
    assert str(raised.value) == (
        f"{path}:11: the variant 'chapter11' has no 'cylinder' (chapter 13 of the book), which "
        "the cylinder at line 11 needs; choose a variant that implements it"
    )


def test_an_empty_or_unreadable_scene(tmp_path: Path, api: Any) -> None:
    assert error(tmp_path, api, "", header=False) == (
        f"{tmp_path / 'scene.yml'}: the scene file is empty; expected a list of '- add:' and "
        "'- define:'"
    )
    with pytest.raises(SceneError, match=r"missing\.yml: cannot read the scene file: No such"):
        load_scene(tmp_path / "missing.yml", api)


def test_load_scene_text_names_its_source(api: Mapping[str, Any]) -> None:
    with pytest.raises(SceneError) as raised:
        load_scene_text("- add: sphere\n  radius: 2\n", api, path="inline.yml")
    assert str(raised.value).startswith("inline.yml:2: unknown key 'radius' in a sphere")
