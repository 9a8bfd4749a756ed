"""The book's public names, each with the chapter that introduces it.

This is the contract between the scenarios and a tracer: the step library evaluates the
book's notation (``s ← sphere()``, ``intersect(s, r)``) against a mapping from these names
to a variant's callables and constants. ``naive_api()`` gives the reference's mapping.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import raytracer  # the package, whose exports are the book's API (it never imports this)

CHAPTER_TITLES: dict[int, str] = {
    1: "Tuples, Points, and Vectors",
    2: "Drawing on a Canvas",
    3: "Matrices",
    4: "Matrix Transformations",
    5: "Ray-Sphere Intersections",
    6: "Light and Shading",
    7: "Making a Scene",
    8: "Shadows",
    9: "Planes",
    10: "Patterns",
    11: "Reflection and Refraction",
    12: "Cubes",
    13: "Cylinders",
    14: "Groups",
    15: "Triangles",
    16: "Constructive Solid Geometry",
    17: "Bounding Boxes and Hierarchies (bonus chapter)",
    18: "Rendering Soft Shadows (bonus chapter)",
    19: "Texture Mapping (bonus chapter)",
    20: "Tori (beyond the book)",
    21: "Path tracing (beyond the book)",
}

# name -> chapter that introduces it. Constants are listed too (EPSILON, identity_matrix).
BOOK_API: dict[str, int] = {
    # chapter 1
    "tuple": 1, "point": 1, "vector": 1, "magnitude": 1, "normalize": 1, "dot": 1,
    "cross": 1, "EPSILON": 1,
    # chapter 2
    "color": 2, "canvas": 2, "write_pixel": 2, "pixel_at": 2, "canvas_to_ppm": 2,
    # chapter 3
    "matrix": 3, "identity_matrix": 3, "transpose": 3, "determinant": 3, "submatrix": 3,
    "minor": 3, "cofactor": 3, "inverse": 3,
    # chapter 4
    "translation": 4, "scaling": 4, "rotation_x": 4, "rotation_y": 4, "rotation_z": 4,
    "shearing": 4,
    # chapter 5
    "ray": 5, "position": 5, "transform": 5, "sphere": 5, "intersect": 5,
    "intersection": 5, "intersections": 5, "hit": 5, "set_transform": 5,
    # chapter 6
    "normal_at": 6, "reflect": 6, "point_light": 6, "material": 6, "lighting": 6,
    # chapter 7
    "world": 7, "default_world": 7, "intersect_world": 7, "prepare_computations": 7,
    "shade_hit": 7, "color_at": 7, "view_transform": 7, "camera": 7, "ray_for_pixel": 7,
    "render": 7,
    # chapter 8
    "is_shadowed": 8,
    # chapter 9
    "test_shape": 9, "local_intersect": 9, "local_normal_at": 9, "plane": 9,
    # chapter 10
    "stripe_pattern": 10, "stripe_at": 10, "stripe_at_object": 10, "test_pattern": 10,
    "set_pattern_transform": 10, "pattern_at": 10, "pattern_at_shape": 10,
    "gradient_pattern": 10, "ring_pattern": 10, "checkers_pattern": 10,
    # chapter 11
    "reflected_color": 11, "refracted_color": 11, "schlick": 11, "glass_sphere": 11,
    # chapter 12
    "cube": 12,
    # chapter 13
    "cylinder": 13, "cone": 13,
    # chapter 14
    "group": 14, "add_child": 14, "world_to_object": 14, "normal_to_world": 14,
    # chapter 15
    "triangle": 15, "parse_obj_file": 15, "obj_to_group": 15, "smooth_triangle": 15,
    "intersection_with_uv": 15,
    # chapter 16
    "csg": 16, "intersection_allowed": 16, "filter_intersections": 16,
    # chapter 17: the bonus chapter "Bounding boxes and hierarchies" (transform: chapter 5)
    "bounding_box": 17, "add_point": 17, "add_box": 17, "box_contains_point": 17,
    "box_contains_box": 17, "bounds_of": 17, "parent_space_bounds_of": 17, "intersects": 17,
    "split_bounds": 17, "partition_children": 17, "make_subgroup": 17, "divide": 17,
    # chapter 18: the bonus chapter "Rendering soft shadows" (lighting: 6, is_shadowed: 8)
    "area_light": 18, "point_on_light": 18, "intensity_at": 18, "sequence": 18, "next": 18,
    # chapter 20: beyond the book, the torus (a quartic)
    "torus": 20,
    # chapter 19: the bonus chapter "Texture mapping"
    "uv_checkers": 19, "uv_pattern_at": 19, "spherical_map": 19, "planar_map": 19,
    "cylindrical_map": 19, "texture_map": 19, "uv_align_check": 19, "face_from_point": 19,
    "cube_uv_front": 19, "cube_uv_back": 19, "cube_uv_left": 19, "cube_uv_right": 19,
    "cube_uv_up": 19, "cube_uv_down": 19, "cube_map": 19, "uv_image": 19,
    "canvas_from_ppm": 19,
    # chapter 21: beyond the book, path tracing (render: 7)
    "path_random": 21, "orthonormal_basis": 21, "cosine_direction": 21, "choose_lobe": 21,
    "sky": 21, "gradient_sky": 21, "sky_color": 21, "scatter": 21, "direct_light": 21,
    "crossed_lights": 21, "path_color_at": 21, "russian_roulette": 21, "render_settings": 21,
}  # fmt: skip


def book_name(python_name: str) -> str:
    """The book's name for a Python name: ``tuple_`` is the book's ``tuple``, ``next_``
    the soft shadows chapter's ``next``."""
    return python_name.removesuffix("_")


def naive_api() -> Mapping[str, Any]:
    """The reference tracer's mapping from book names to callables and constants.

    Only names the reference defines are included, so the mapping grows chapter by chapter.
    """
    api: dict[str, Any] = {}
    for python_name in raytracer.__all__:
        name = book_name(python_name)
        if name in BOOK_API:
            api[name] = getattr(raytracer, python_name)
    return api
