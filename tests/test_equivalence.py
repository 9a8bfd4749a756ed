"""Render equivalence: small scenes through every available variant, compared with ``naive``.

A variant whose ``tolerance`` is 0 (every pure-Python float64 variant) must give identical
pixels; any other must stay within its stated tolerance per colour channel. Every comparison
prints the maximum and mean difference (``pytest -s`` or ``-rA`` shows them).

Two sizes of each scene. The compiled variants (``numba``, ``wavefront``: a picture costs
them milliseconds, and their float32 and fast-math paths differ from naive's at single
pixels) are compared at the scene's own size. The pure-Python ones (``cached``,
``prealloc``, ``robust``, and the pools over them) are compared on the same scene, seen by
the same camera, at half its width and height: a quarter of the pixels, a quarter of the
cost, and every shape, light and pattern of the scene still in the picture. The exact ones
run naive's own arithmetic step for step, so a step they get wrong is wrong at every pixel
whose rays take it, not at one pixel in four (a ``prealloc`` whose Schlick reflectance
takes the power 4 for 5 differs from naive at 10 of the 70 pixels of the half-size
patterns-mirrors-glass scene, and at 52 of its 300 at full size). Three scenes keep their
size for every variant: the three of fewer than 150 pixels, christmas among them (at 14x10
its branches, stem and ornaments cover 34 pixels in 30 colours). Naive's picture of
christmas costs about 1.8 CPU seconds a pixel where the tree is: naive draws 12 chosen
pixels of it (``CHRISTMAS_PIXELS``: the background, branches lit and shaded, both balls,
the stem), through the same pixel loop as its ``render``, and every variant's whole picture
is compared there (a ``prealloc`` whose triangles miss where u > 0.5 differs from naive
there by up to 0.31).

``naive``'s pictures are rendered once per run, whichever worker process asks first
(``once_per_run``). The pools (``pooled``, ``dask``) render their inner variant's picture in
other processes: what they add is the split into jobs, the world sent to the workers and the
picture put together again, which a scene of many shapes does not change; the gate leaves
them out of the christmas scene (5,291 shapes: their inner variants render it here, the
pools render every other scene, the mesh scene's groups of triangles among them), and
``--thorough`` puts them back. A Dask variant keeps one cluster for the module (its
``session``), started once per test process instead of once per render: the cluster's start
is ``test_dask``'s subject, not this module's.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import budget
import numpy as np
import pytest
from once_per_run import OncePerRun
from reference_pixels import naive_at

from raytracer.camera import RenderSettings
from scene import load_scene
from variants.dask_cluster import DaskTracer
from variants.registry import Variant, available_variants, load_variant

SCENES_FOLDER = Path(__file__).resolve().parent.parent / "scenes"
REFERENCE_SCENE = SCENES_FOLDER / "reference.yml"
COVER_SCENE = SCENES_FOLDER / "cover.yml"
MESH_SCENE = SCENES_FOLDER / "mesh.yml"
TEXTURES_SCENE = SCENES_FOLDER / "textures.yml"
TORUS_SCENE = SCENES_FOLDER / "torus.yml"
CHRISTMAS_SCENE = SCENES_FOLDER / "christmas.yml"
# Compositions beyond the defaults that ``all`` gives: the pool over another variant, and
# each job granularity.
COMPOSED = (
    "pooled[workers=2]:cached",
    "pooled[granularity=pixel,workers=2]:cached",
    "pooled[granularity=tile,tile=5,workers=2]:cached",
)


@dataclass(frozen=True)
class Scene:
    """A scene built through a variant's API: ``build(api) -> (camera, world)``."""

    name: str
    build: Callable[[Any], tuple[Any, Any]]
    settings: RenderSettings = field(default_factory=RenderSettings)
    left_out: tuple[str, ...] = ()  # variants (and pools over them) not compared on it
    pools: bool = True  # False: the pools are compared on it only by ``--thorough``
    halve: bool = True  # False: every variant is compared at its own size
    pixels: tuple[tuple[int, int], ...] = ()  # (x, y): compared at these alone; () all


def _look(api: Any, c: Any, eye: tuple[float, float, float], to: tuple[float, float, float]) -> Any:
    view = api["view_transform"](api["point"](*eye), api["point"](*to), api["vector"](0, 1, 0))
    return replace(c, transform=view)


def default_world(api: Any, size: int = 24) -> tuple[Any, Any]:
    """Chapter 7's default world seen from the book's test position (0, 0, -5), at 24x24,
    with a field of view that the spheres fill."""
    c = _look(api, api["camera"](size, size, 0.5), (0, 0, -5), (0, 0, 0))
    return c, api["default_world"]()


def small_default_world(api: Any) -> tuple[Any, Any]:
    """The default world at 12x12 (for several samples per pixel)."""
    return default_world(api, 12)


def patterns_mirrors_glass(api: Any) -> tuple[Any, Any]:
    """Chapters 9-11: a checkered reflective floor, a striped wall, a ringed sphere, a glass
    sphere in front of them, at 20x15."""
    white, black = api["color"](1, 1, 1), api["color"](0.1, 0.1, 0.1)
    floor = api["plane"]()
    checks = api["checkers_pattern"](white, black)
    api["set_pattern_transform"](checks, api["scaling"](0.5, 0.5, 0.5))
    floor.material = api["material"]()
    floor.material = replace(floor.material, pattern=checks, reflective=0.3, specular=0)
    wall = api["plane"]()
    api["set_transform"](wall, api["translation"](0, 0, 4) * api["rotation_x"](math.pi / 2))
    stripes = api["stripe_pattern"](api["color"](0.9, 0.5, 0.2), api["color"](0.2, 0.3, 0.8))
    api["set_pattern_transform"](stripes, api["rotation_y"](0.6) * api["scaling"](0.3, 1, 1))
    wall.material = replace(wall.material, pattern=stripes)
    ringed = api["sphere"]()
    api["set_transform"](ringed, api["translation"](1.2, 1, 1.5))
    rings = api["ring_pattern"](white, api["color"](0.8, 0.1, 0.1))
    api["set_pattern_transform"](rings, api["scaling"](0.2, 0.2, 0.2))
    ringed.material = replace(ringed.material, pattern=rings, reflective=0.2)
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](-0.6, 0.8, 0) * api["scaling"](0.8, 0.8, 0.8))
    glass.material = replace(glass.material, reflective=0.9, diffuse=0.1, ambient=0.05)
    w = api["world"]()
    w.objects.extend([floor, wall, ringed, glass])
    w.light = api["point_light"](api["point"](-4, 6, -6), api["color"](1, 1, 1))
    c = _look(api, api["camera"](20, 15, math.pi / 3), (0, 1.5, -5), (0, 0.8, 0))
    return c, w


def three_lights(api: Any) -> tuple[Any, Any]:
    """Several lights: the patterns-mirrors-glass world lit also by a dim blue light from
    the right and a warm one above the glass (each with its own shadows)."""
    c, w = patterns_mirrors_glass(api)
    for at, rgb in (((5, 3, -4), (0.2, 0.3, 0.6)), ((-0.5, 4, -1), (0.5, 0.4, 0.2))):
        w.lights.append(api["point_light"](api["point"](*at), api["color"](*rgb)))
    return c, w


def soft_shadows(api: Any) -> tuple[Any, Any]:
    """The bonus chapter "Rendering soft shadows": the patterns-mirrors-glass world, without
    its glass sphere, lit by a 3x3 area light whose cells are jittered per sample, at 12x9
    (rendered with two samples per pixel, so each sample draws its own jitter). The glass
    is left out because its paths inside the sphere are where robust's refraction differs
    from naive's (patterns-mirrors-glass tests them); here it is the shadows."""
    c, w = patterns_mirrors_glass(api)
    w.objects.pop()  # the glass sphere
    light = api["area_light"](api["point"](-5, 5.5, -7), api["vector"](2, 0, 0), 3,
                              api["vector"](0, 1.5, 1.5), 3, api["color"](1, 1, 1))  # fmt: skip
    w.light = replace(light, jitter=True)
    return replace(api["camera"](12, 9, math.pi / 3), transform=c.transform), w


def cover_scene(api: Any) -> tuple[Any, Any]:
    """The cubes of ``scenes/cover.yml`` (two lights, glass, mirror) at 16x16."""
    scene = load_scene(COVER_SCENE, api).resized(16, 16)
    return scene.camera, scene.world


def mesh_scene(api: Any) -> tuple[Any, Any]:
    """``scenes/mesh.yml`` at 16x10: OBJ meshes in groups, divided by the loader
    for the tracers that test boxes (the bonus chapter), flattened into numba's own
    hierarchy: the same picture either way."""
    scene = load_scene(MESH_SCENE, api).resized(16, 10)
    return scene.camera, scene.world


def textures_scene(api: Any) -> tuple[Any, Any]:
    """The bonus chapter "Texture mapping": ``scenes/textures.yml`` (spherical,
    planar, cylindrical and cube maps, checkers, align checks and two image files) at 16x12."""
    scene = load_scene(TEXTURES_SCENE, api).resized(16, 12)
    return scene.camera, scene.world


def reference_scene(api: Any) -> tuple[Any, Any]:
    """The reference scene file (cylinders, groups, glass) at 16x12."""
    scene = load_scene(REFERENCE_SCENE, api).resized(16, 12)
    return scene.camera, scene.world


def torus_scene(api: Any) -> tuple[Any, Any]:
    """Tori (chapter 20, beyond the book): ``scenes/torus.yml`` (linked rings, a glass
    ring, a ring whose tube nearly closes its hole) at 20x12."""
    scene = load_scene(TORUS_SCENE, api).resized(20, 12)
    return scene.camera, scene.world


def christmas_scene(api: Any) -> tuple[Any, Any]:
    """``scenes/christmas.yml`` (eleven fir branches, 5,291 shapes) at 14x10."""
    scene = load_scene(CHRISTMAS_SCENE, api).resized(14, 10)
    return scene.camera, scene.world


# christmas's chosen pixels (x, y) at 14x10: naive takes about 1.8 CPU s a pixel where
# the tree is (0.15 where it is not), so it draws these 12 alone, and every variant's
# picture is compared there: the background, six of the branches (lit, in the shade, the
# top one and the lowest), the red ball (lit and in the shade), the silver one (its
# highlight and its reflection) and the stem in the shade of the branches
CHRISTMAS_PIXELS = (
    (0, 0), (7, 4), (2, 5), (10, 5), (3, 6), (8, 6), (6, 9),
    (4, 5), (6, 6), (9, 8), (10, 8), (7, 8),
)  # fmt: skip

SCENES = [
    Scene("default-world", default_world),
    Scene(
        "default-world-12x12-3spp",
        small_default_world,
        RenderSettings(samples=3, seed=11),
        halve=False,
    ),
    Scene("patterns-mirrors-glass", patterns_mirrors_glass),
    Scene("reference-16x12", reference_scene, RenderSettings(epsilon=0.001)),
    Scene("three-lights", three_lights),
    Scene("cover-16x16", cover_scene),
    Scene("mesh-16x10", mesh_scene),
    Scene("torus-20x12", torus_scene),
    # naive's picture is needed at the compiled variants' size: one size for every variant
    # (naive's 16x12 cost about 100 CPU s; at 12x9 robust differs from naive by 0.019 at one
    # pixel, over its tolerance; at 10x8 fifteen pixels hold the branches)
    Scene("christmas-14x10", christmas_scene, pools=False, halve=False, pixels=CHRISTMAS_PIXELS),
    # wavefront refuses area lights and texture maps (it says so, naming the light or the
    # pattern): it is left out of these two scenes, not skipped
    Scene(
        "soft-shadows-12x9-2spp",
        soft_shadows,
        RenderSettings(samples=2, seed=5),
        left_out=("wavefront",),
        halve=False,
    ),
    Scene("textures-16x12", textures_scene, left_out=("wavefront",)),
]


# compared at each scene's own size; every other variant (pure Python) at half of it
FULL_SIZE = ("numba", "wavefront")


def halved(scene: Scene) -> Scene:
    """``scene`` seen by the same camera (position, field of view) at half its width and
    height: the size the pure-Python variants are compared at; a scene that is small
    already (``halve=False``) as it is."""

    def build(api: Any) -> tuple[Any, Any]:
        c, w = scene.build(api)
        small = api["camera"](c.hsize // 2, c.vsize // 2, c.field_of_view)
        return replace(small, transform=c.transform), w

    if not scene.halve:
        return scene
    return replace(scene, name=f"{scene.name}-halved", build=build)


HALVED = {scene.name: halved(scene) for scene in SCENES}


def _variants() -> list[str]:
    names = [variant.name for variant in available_variants() if variant.name != "naive"]
    return names + [name for name in COMPOSED if name not in names]


def _pixels(variant: Variant, scene: Scene) -> list[tuple[float, float, float]]:
    """The variant's whole picture of ``scene``, at the scene's chosen pixels (all if none
    are chosen), row by row."""
    camera, world = scene.build(variant.api)
    image = variant.api["render"](camera, world, scene.settings)
    pixel_at = variant.api["pixel_at"]
    where = scene.pixels or [(x, y) for y in range(image.height) for x in range(image.width)]
    colors = [pixel_at(image, x, y) for x, y in where]
    return [(float(c.red), float(c.green), float(c.blue)) for c in colors]


def _reference_pixels(scene: Scene) -> list[tuple[float, float, float]]:
    """``naive``'s picture of ``scene``; of a scene with chosen pixels, those alone
    (tests/reference_pixels.py: the whole picture's pixels, bit for bit)."""
    if not scene.pixels:
        return _pixels(load_variant("naive"), scene)
    found = naive_at(scene.build, scene.settings, scene.pixels).tolist()
    return [(r, g, b) for r, g, b in found]


def _naive_pixels(scene: Scene, once: OncePerRun) -> list[tuple[float, float, float]]:
    """``naive``'s picture of ``scene``, rendered once per run."""
    found = once.get(f"equivalence-{scene.name}", lambda: _reference_pixels(scene))
    return [(float(r), float(g), float(b)) for r, g, b in np.asarray(found).tolist()]


BOTH_SIZES = [*SCENES, *(small for small in HALVED.values() if small not in SCENES)]


@pytest.mark.slow
@pytest.mark.parametrize("scene", BOTH_SIZES, ids=[scene.name for scene in BOTH_SIZES])
def test_the_scene_is_not_blank(scene: Scene, once_per_run: OncePerRun) -> None:
    """A comparison of black images would prove nothing. (One test a scene and size: each
    renders ``naive``'s picture that the comparisons then share.)"""
    pixels = _naive_pixels(scene, once_per_run)
    distinct = {tuple(round(v, 3) for v in p) for p in pixels}
    assert len(distinct) > 5, f"{scene.name}: only {len(distinct)} distinct colours"


POOLS = ("pooled", "dask")


def _base(name: str) -> str:
    """The variant that traces the rays: ``cached`` for ``pooled[workers=2]:cached``."""
    return name.rsplit(":", 1)[-1].split("[", 1)[0]


def _left_out(name: str, scene: Scene) -> bool:
    """Whether ``scene`` leaves out the variant ``name`` (or the one a pool wraps)."""
    pool = name.split("[", 1)[0].split(":", 1)[0] in POOLS
    return _base(name) in scene.left_out or (pool and not scene.pools and not budget.THOROUGH)


def _sized(name: str, scene: Scene) -> Scene:
    """The size of ``scene`` that variant ``name`` is compared at (see the docstring)."""
    pool = name.split("[", 1)[0].split(":", 1)[0] in POOLS
    return scene if _base(name) in FULL_SIZE and not pool else HALVED[scene.name]


# the Dask variant's comparisons last: its cluster, kept to the module's end, starts late
# and idles (polling, heartbeats: CPU seconds) for as short a time as can be
PAIRS = sorted(
    (
        (name, _sized(name, scene))
        for scene in SCENES
        for name in _variants()
        if not _left_out(name, scene)
    ),
    key=lambda pair: pair[0].startswith("dask"),
)


@pytest.fixture(scope="module")
def variants() -> Iterator[Callable[[str], Variant]]:
    """``load_variant``, except that a Dask variant is loaded once per test process and
    keeps its cluster (started with it) for the module, closed at its end."""
    clusters: dict[str, Variant] = {}
    with contextlib.ExitStack() as stack:

        def load(name: str) -> Variant:
            if name in clusters:
                return clusters[name]
            variant = load_variant(name)
            if isinstance(variant.tracer, DaskTracer):
                stack.enter_context(variant.tracer.session())
                clusters[name] = variant
            return variant

        yield load


@pytest.mark.parametrize(
    ("name", "scene"), PAIRS, ids=[f"{name}-{scene.name}" for name, scene in PAIRS]
)
def test_every_variant_renders_what_naive_renders(
    name: str, scene: Scene, once_per_run: OncePerRun, variants: Callable[[str], Variant]
) -> None:
    variant = variants(name)
    expected = _naive_pixels(scene, once_per_run)
    got = _pixels(variant, scene)
    assert len(got) == len(expected)
    differences = [
        abs(a - b) for p, q in zip(got, expected, strict=True) for a, b in zip(p, q, strict=True)
    ]
    worst = max(differences)
    mean = sum(differences) / len(differences)
    identical = got == expected
    print(
        f"{scene.name} {variant.name}: max difference {worst:.3g}, mean {mean:.3g}, "
        f"tolerance {variant.tolerance:g}, {'identical' if identical else 'not identical'}"
    )
    if variant.tolerance == 0:
        assert identical, (
            f"{variant.name} differs from naive by up to {worst:.3g} (mean {mean:.3g})"
        )
    else:
        assert worst <= variant.tolerance, (
            f"{variant.name} differs from naive by up to {worst:.3g} (mean {mean:.3g}), "
            f"more than its tolerance {variant.tolerance:g}"
        )
