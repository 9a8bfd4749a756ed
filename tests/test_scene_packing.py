"""The compiled and vectorized tracers pack a scene straight from its description (no book
shape built, an OBJ model's triangles from its arrays): the tables are the very ones they
pack from the book's world built of the same file, number for number."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from harness.scenery.make_meshes import provide
from scene import load_scene
from variants.numba.pack import pack_scene as numba_scene
from variants.numba.pack import pack_world as numba_world
from variants.registry import load_variant
from variants.wavefront.pack import pack as wavefront_world
from variants.wavefront.pack import pack_scene as wavefront_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"
SMALL = sorted(p.name for p in SCENES.glob("*.yml") if p.name != "six-knots.yml")
WAVEFRONT = [name for name in SMALL if name not in ("soft-shadows.yml", "textures.yml")]


def _equal(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))


@pytest.mark.parametrize("name", SMALL)
@pytest.mark.parametrize("structure", ["sah", "off"])
def test_numba_packs_a_description_as_it_packs_the_book_world(name: str, structure: str) -> None:
    scene = load_scene(SCENES / name, load_variant("numba").api, provide_mesh=provide)
    described = numba_scene(scene, structure=structure)
    built = numba_world(scene.book_world(), structure=structure, compact=True)
    tables = ("pf", "pi", "items", "boxes", "csg", "balls", "lights", "light_values", "tg", "tn")
    for table in tables:
        assert _equal(getattr(described, table), getattr(built, table)), table
    for a, b in zip(described.texture_table(), built.texture_table(), strict=True):
        assert _equal(a, b)
    assert all(shape is None for shape in described.shapes)  # nothing of the book's built
    assert len(described.pf) > 0


@pytest.mark.parametrize("name", WAVEFRONT)
def test_wavefront_packs_a_description_as_it_packs_the_book_world(name: str) -> None:
    scene = load_scene(SCENES / name, load_variant("wavefront").api, provide_mesh=provide)
    a, b = wavefront_scene(scene), wavefront_world(scene.book_world())
    for table in (
        "kind", "row", "xform", "shadow", "inv", "nrm", "caps", "tri", "smooth", "unit_prim",
        "unit_tree", "unit_lo", "unit_hi", "unit_ball", "light_pos", "light_int",
    ):  # fmt: skip
        assert _equal(getattr(a, table), getattr(b, table)), table
    # materials are shared by identity, so their rows may be ordered differently: compare
    # what each primitive gets
    for table in ("color", "ambient", "diffuse", "specular", "shininess", "reflective",
                  "transparency", "refractive", "pat_inv", "pat_a", "pat_b"):  # fmt: skip
        assert _equal(getattr(a, table)[..., a.mat], getattr(b, table)[..., b.mat]), table
    assert _equal(a.pattern[a.mat], b.pattern[b.mat])
    assert a.n_prims > 0 and all(shape is None for shape in a.shapes)


def test_wavefront_packs_an_area_light_of_a_description_for_the_path_integrator() -> None:
    from variants.wavefront.scene import Unsupported

    scene = load_scene(SCENES / "soft-shadows.yml", load_variant("wavefront").api)
    packed = wavefront_scene(scene)
    light = scene.lights[0]
    assert packed.light_steps.tolist() == [[light.usteps, light.vsteps]]
    assert _equal(packed.light_pos, wavefront_world(scene.book_world()).light_pos)
    with pytest.raises(Unsupported, match="light 0 of the world is an AreaLight"):
        packed.refuse_for_whitted()


def test_compact_triangles_draw_what_a_row_per_triangle_draws() -> None:
    """A run of triangles packed compactly (``tg``: one row per run of one material and
    shadow) renders every pixel as a row per triangle does: a mesh with a triangle of
    another material, one that casts no shadow and one of its own transform, flat and
    smooth, behind glass (n1/n2 through the triangles)."""
    from raytracer.camera import RenderSettings
    from raytracer.materials import material

    variant = load_variant("numba")
    api = variant.api
    scene = load_scene(SCENES / "mesh.yml", api)
    world = scene.book_world()
    model = world.objects[1]  # the icosphere: smooth triangles
    triangles = [s for g in model.children for s in getattr(g, "children", [])]
    assert len(triangles) == 20
    triangles[2].material = material(color=api["color"](1, 0, 0), transparency=0.5)
    triangles[4].casts_shadow = False
    api["set_transform"](triangles[6], api["translation"](0, 0.05, 0))
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](0, 1, -2) * api["scaling"](0.6, 0.6, 0.6))
    world.objects.append(glass)
    camera = scene.resized(32, 24).camera
    settings = RenderSettings(depth=4)
    compact = numba_world(world, compact=True)
    assert len(compact.tg) > 0 and (compact.pi[:, 6] >= 0).sum() >= 3  # several runs
    images = [
        np.asarray(variant.tracer.render(camera, packed, settings).array)
        for packed in (compact, numba_world(world, compact=False))
    ]
    assert np.array_equal(images[0], images[1])
    assert len(np.unique(images[0].reshape(-1, 3), axis=0)) > 20  # a picture, not a blank
