"""The numba variant (issue 5): same pictures as ``naive``, refusals, specialization, no
allocation per pixel, ray counts, options, regions of a frame, and its array-backed canvas.

Pictures: small scenes rendered by ``naive`` and by ``numba``, compared channel by channel
after clamping to [0, 1] (as the PNG shows them). Every comparison prints the maximum and
mean difference and the number of pixels differing by more than 1/255 (``pytest -s``).
Stated tolerances:

- float64 (the default): no pixel differs by more than ``FLOAT64_WORST`` (measured: at most
  6e-10 on these scenes), so none by 1/255, and the mean difference is below 1e-9. The
  kernels round differently from the reference (world-space balls, reciprocals, group
  transforms composed once, reflections summed in another order, the specular term left
  out below 1e-9), so a pixel could change where a ray grazes an edge exactly; on the
  reference scene at 640x480 ``rtc bench --numba-targets`` reports the count;
- float32 and fastmath: at most 2% of the pixels differ by more than 1/255, none by more
  than 0.5 (a shadow or acne decision may flip at an edge).

The first run compiles a kernel per scene feature set (seconds each); they are then cached
on disk (``variants.numba.specialize``).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from once_per_run import OncePerRun

from harness.instruments.raycount import count_rays
from raytracer.camera import RenderSettings
from raytracer.canvas import canvas_to_ppm, canvas_to_rgb8
from raytracer.materials import material
from raytracer.matrices import Matrix
from raytracer.patterns import Pattern
from raytracer.shapes.sphere import Sphere
from raytracer.tuples import Tuple
from scene import load_scene
from variants.arrays.canvas import ArrayCanvas
from variants.numba import layout as L
from variants.numba.api import EXTRA, NumbaTracer
from variants.numba.errors import PackError
from variants.numba.features import FeatureSet, analyse
from variants.numba.pack import pack_world
from variants.numba.render import GENERIC_CALLS, GENERIC_ONLY, Options
from variants.registry import Variant, VariantError, load_variant

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"
ONE_STEP = 1.0 / 255.0
FLOAT64_WORST = 1e-6
APPROXIMATE_SHARE = 0.02

Build = Callable[[Any], tuple[Any, Any]]


def _look(api: Any, c: Any, eye: tuple[float, ...], to: tuple[float, ...]) -> Any:
    view = api["view_transform"](api["point"](*eye), api["point"](*to), api["vector"](0, 1, 0))
    return replace(c, transform=view)


def default_world(api: Any) -> tuple[Any, Any]:
    """Chapter 7's default world, 16x16."""
    c = _look(api, api["camera"](16, 16, math.pi / 2), (0, 0, -5), (0, 0, 0))
    return c, api["default_world"]()


def everything(api: Any) -> tuple[Any, Any]:
    """Chapters 9-16 in one small scene: patterned reflective floor, a glass sphere (Schlick),
    a group with a cube, a capped cylinder and a cone, a CSG shape, flat and smooth
    triangles; 20x15."""
    c = api["color"]
    floor = api["plane"]()
    checks = api["checkers_pattern"](c(1, 1, 1), c(0.1, 0.1, 0.1))
    api["set_pattern_transform"](checks, api["scaling"](0.5, 0.5, 0.5))
    floor.material = material(pattern=checks, reflective=0.3, specular=0)
    wall = api["plane"]()
    api["set_transform"](wall, api["translation"](0, 0, 5) * api["rotation_x"](math.pi / 2))
    rings = api["ring_pattern"](c(0.9, 0.5, 0.2), c(0.2, 0.3, 0.8))
    api["set_pattern_transform"](rings, api["scaling"](0.3, 0.3, 0.3))
    wall.material = material(pattern=rings)
    glass = api["glass_sphere"]()
    api["set_transform"](glass, api["translation"](-1.2, 1, 0) * api["scaling"](0.7, 0.7, 0.7))
    glass.material = replace(glass.material, reflective=0.8, diffuse=0.1, ambient=0.05)
    g = api["group"]()
    api["set_transform"](g, api["translation"](1.2, 0, 1) * api["rotation_y"](0.5))
    cube = api["cube"]()
    api["set_transform"](cube, api["translation"](0, 0.4, 0) * api["scaling"](0.4, 0.4, 0.4))
    stripes = api["stripe_pattern"](c(1, 0.2, 0.2), c(1, 1, 1))
    api["set_pattern_transform"](stripes, api["scaling"](0.2, 0.2, 0.2))
    cube.material = material(pattern=stripes)
    cyl = api["cylinder"]()
    cyl.minimum, cyl.maximum, cyl.closed = 0.0, 1.5, True
    api["set_transform"](cyl, api["translation"](0.9, 0, 0) * api["scaling"](0.3, 1, 0.3))
    cone = api["cone"]()
    cone.minimum, cone.maximum, cone.closed = -1.0, 0.0, True
    api["set_transform"](cone, api["translation"](-0.8, 1, -0.5) * api["scaling"](0.4, 1, 0.4))
    gradient = api["gradient_pattern"](c(0.2, 0.9, 0.2), c(0.1, 0.1, 0.8))
    cone.material = material(pattern=gradient, transparency=0.5, refractive_index=1.3)
    for shape in (cube, cyl, cone):
        api["add_child"](g, shape)
    left = api["cube"]()
    right = api["sphere"]()
    api["set_transform"](right, api["scaling"](1.3, 1.3, 1.3))
    carved = api["csg"]("difference", left, right)
    api["set_transform"](carved, api["translation"](0.2, 0.5, -1.8) * api["scaling"](0.4, 0.4, 0.4))
    carved.material = material(color=c(0.3, 0.5, 0.9))
    left.material = carved.material
    right.material = carved.material
    p = api["point"]
    v = api["vector"]
    flat = api["triangle"](p(-2.5, 0, 1), p(-1.5, 1.5, 1.5), p(-0.8, 0, 2))
    smooth = api["smooth_triangle"](
        p(0.5, 1.6, -0.8), p(-0.3, 1.2, -0.4), p(0.4, 0.9, -0.2),
        v(0, 1, -1), v(-1, 0, -1), v(1, 0, -1),
    )  # fmt: skip
    w = api["world"]()
    w.objects.extend([floor, wall, glass, g, carved, flat, smooth])
    w.light = api["point_light"](api["point"](-4, 6, -6), c(1, 1, 1))
    return _look(api, api["camera"](20, 15, math.pi / 3), (0, 1.6, -5), (0, 0.7, 0)), w


def scene_file(name: str, size: tuple[int, int]) -> Build:
    def build(api: Any) -> tuple[Any, Any]:
        scene = load_scene(SCENES / name, api).resized(*size)
        return scene.camera, scene.world

    return build


PICTURES: dict[str, tuple[Build, RenderSettings]] = {
    "default-world": (default_world, RenderSettings()),
    "default-world-3spp": (default_world, RenderSettings(samples=3, seed=7, depth=2)),
    "everything": (everything, RenderSettings()),
    "reference-16x12": (scene_file("reference.yml", (16, 12)), RenderSettings(epsilon=0.001)),
    "shapes-16x12": (scene_file("shapes.yml", (16, 12)), RenderSettings()),
    "csg-16x12": (scene_file("csg.yml", (16, 12)), RenderSettings()),
    # balls alone (their shadow rays' filter) and more samples than a block of camera rays,
    # not a multiple of it (``kernels_trace.block_ray``)
    "cpp-spheres-11spp": (
        scene_file("cpp-spheres.yml", (12, 9)), RenderSettings(samples=11, seed=5)
    ),
}


def _pixels(variant: Variant, picture: str) -> np.ndarray:
    build, settings = PICTURES[picture]
    camera, world = build(variant.api)
    image = variant.api["render"](camera, world, settings)
    pixel_at = variant.api["pixel_at"]
    rows = [
        [(p.red, p.green, p.blue) for p in (pixel_at(image, x, y) for x in range(image.width))]
        for y in range(image.height)
    ]
    return np.clip(np.array(rows, dtype=np.float64), 0.0, 1.0)


def _naive(picture: str, once: OncePerRun) -> np.ndarray:
    """``naive``'s picture, rendered once per run (``once_per_run``: the workers share it)."""
    return once.get(f"numba-{picture}", lambda: _pixels(load_variant("naive"), picture))


def _compare(name: str, picture: str, once: OncePerRun) -> tuple[float, float, int, int]:
    """(max, mean, pixels beyond 1/255, pixels) of ``name``'s picture against naive's."""
    expected = _naive(picture, once)
    got = _pixels(load_variant(name), picture)
    assert got.shape == expected.shape
    difference = np.abs(got - expected)
    worst_per_pixel = difference.max(axis=2)
    beyond = int((worst_per_pixel > ONE_STEP).sum())
    figures = (float(difference.max()), float(difference.mean()), beyond, worst_per_pixel.size)
    print(
        f"{picture} {name}: max difference {figures[0]:.3g}, mean {figures[1]:.3g}, "
        f"{beyond} of {figures[3]} pixels beyond 1/255"
    )
    return figures


@pytest.mark.parametrize("picture", list(PICTURES))
def test_the_picture_is_not_blank(picture: str, once_per_run: OncePerRun) -> None:
    pixels = _naive(picture, once_per_run)
    distinct = {tuple(np.round(p, 3)) for p in pixels.reshape(-1, 3)}
    assert len(distinct) > 5, f"{picture}: only {len(distinct)} distinct colours"


@pytest.mark.parametrize("picture", list(PICTURES))
def test_float64_draws_what_naive_draws(picture: str, once_per_run: OncePerRun) -> None:
    worst, mean, beyond, _ = _compare("numba", picture, once_per_run)
    assert worst <= FLOAT64_WORST, f"a pixel differs from naive by {worst:.3g}"
    assert beyond == 0
    assert mean < 1e-9, f"mean difference {mean:.3g}"


@pytest.mark.parametrize("name", ["numba[float32]", "numba[fastmath]", "numba[threads=1]"])
def test_options_stay_close_to_naive(name: str, once_per_run: OncePerRun) -> None:
    """Each option's render of the reference scene, through the gate's generic kernel of its
    precision (``test_differential.py`` renders random worlds with the same fast-math and
    float32 kernels, so the run builds each once; ``--thorough`` specializes them)."""
    worst, _, beyond, pixels = _compare(name, "reference-16x12", once_per_run)
    assert beyond <= APPROXIMATE_SHARE * pixels, f"{beyond} of {pixels} pixels beyond 1/255"
    assert worst <= 0.5


# ------------------------------------------------------------------------------ refusals


class OddSphere(Sphere):
    """A sphere that intersects differently: the kernels must not pretend to know it."""

    def local_intersect(self, local_ray: Any) -> list[Any]:
        return []


class OddPattern(Pattern):
    def local_pattern_at(self, point: Tuple) -> Any:
        raise NotImplementedError


def _world_with(shape: Any) -> Any:
    api = load_variant("numba").api
    w = api["default_world"]()
    w.objects.append(shape)
    return w


def test_an_unknown_shape_is_refused_naming_it() -> None:
    api = load_variant("numba").api
    with pytest.raises(PackError, match=r"world object 2 \(an OddSphere\).*changes how a Sphere"):
        api["render"](api["camera"](4, 4, 1.0), _world_with(OddSphere()))


def test_a_test_shape_is_refused_in_a_render() -> None:
    api = load_variant("numba").api
    with pytest.raises(PackError, match=r"TestShape.*records rays in Python"):
        api["render"](api["camera"](4, 4, 1.0), _world_with(api["test_shape"]()))


def test_an_unknown_pattern_is_refused_naming_it() -> None:
    api = load_variant("numba").api
    s = api["sphere"]()
    s.material = material(pattern=OddPattern())
    with pytest.raises(PackError, match=r"the pattern of world object 2.*OddPattern"):
        api["render"](api["camera"](4, 4, 1.0), _world_with(s))


def test_a_non_affine_transform_is_refused() -> None:
    api = load_variant("numba").api
    s = api["sphere"]()
    s.transform = Matrix(((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0.5, 0, 1)))
    with pytest.raises(PackError, match="not affine"):
        api["render"](api["camera"](4, 4, 1.0), _world_with(s))


def test_a_world_without_light_renders_black() -> None:
    """As the reference shades it: no light, black surfaces (no error); the book's
    ``is_shadowed(w, point)`` needs the first light, and says so."""
    api = load_variant("numba").api
    w = api["default_world"]()
    w.light = None
    image = api["render"](api["camera"](4, 4, 1.0), w)
    assert np.array_equal(image.array, np.zeros((4, 4, 3)))
    c = api["color_at"](w, api["ray"](api["point"](0, 0, -5), api["vector"](0, 0, 1)))
    assert (c.red, c.green, c.blue) == (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="is_shadowed: the world has no light source"):
        api["is_shadowed"](w, api["point"](0, 10, 0))


# ------------------------------------------------------------------------ specialization


@pytest.mark.usefixtures("specialized_kernels")
def test_an_opaque_spheres_scene_leaves_out_refraction_schlick_cylinders_patterns() -> None:
    api = load_variant("numba").api
    flags = analyse(pack_world(api["default_world"]())).flags
    assert flags == {"HAS_SPHERE", "HAS_SHADOWS"}
    variant = load_variant("numba")
    text = variant.tracer.explain(api["default_world"]())
    assert "left out:" in text
    for word in ("refraction", "schlick", "cylinder", "checkers"):
        assert word in text.split("left out:")[1]


def test_the_reference_scene_needs_what_it_has() -> None:
    """Its five spheres are balls (uniform scale and translation), tested in world space all
    at once, so the box of the group of three spheres is left out too."""
    api = load_variant("numba").api
    world = load_scene(SCENES / "reference.yml", api).world
    packed = pack_world(world)
    assert analyse(packed).flags == {
        "HAS_SPHERE", "HAS_PLANE", "HAS_CYLINDER", "HAS_PATTERNS", "HAS_CHECKERS_PATTERN",
        "HAS_SHADOWS", "HAS_REFLECTION", "HAS_REFRACTION", "HAS_SCHLICK",
    }  # fmt: skip
    assert packed.balls.shape[1] == 5
    assert len(packed.items) == 4  # three planes and the cylinder


def test_a_group_of_ellipsoids_keeps_its_box() -> None:
    """A sphere scaled unevenly is not a ball: it stays an item, tested in object space,
    and the box of its group stays."""
    api = load_variant("numba").api
    g = api["group"]()
    for x in (-1.0, 1.0):
        s = api["sphere"]()
        api["set_transform"](s, api["translation"](x, 0, 0) * api["scaling"](0.5, 1, 0.5))
        api["add_child"](g, s)
    w = api["default_world"]()
    w.objects.append(g)
    packed = pack_world(w)
    assert packed.balls.shape[1] == 2  # the default world's two spheres
    assert "HAS_BOXES" in analyse(packed).flags
    assert len(packed.items) == 3  # the box and the two ellipsoids


def test_a_sphere_with_a_similarity_transform_is_a_world_space_ball() -> None:
    """Rotation, uniform scale and translation: the centre and radius come out of the
    inverse; an uneven scale is no ball."""
    api = load_variant("naive").api
    s = api["sphere"]()
    api["set_transform"](
        s, api["translation"](1, -2, 3) * api["rotation_y"](0.7) * api["scaling"](2, 2, 2)
    )
    w = api["world"]()
    w.objects.append(s)
    packed = pack_world(w)
    assert packed.balls.shape[1] == 1
    centre = packed.balls[L.B_X : L.B_Z + 1, 0]
    assert np.allclose(centre, [1, -2, 3], atol=1e-12)
    assert packed.balls[L.B_R2, 0] == pytest.approx(4.0, rel=1e-12)
    api["set_transform"](s, api["scaling"](2, 2, 2.000001))
    assert pack_world(w).balls.shape[1] == 0


@pytest.mark.parametrize("sphere_first", [True, False])
def test_a_tie_between_a_ball_and_a_plane_goes_to_the_earlier_object(sphere_first: bool) -> None:
    """A ray meets the unit sphere and the plane y = -1 at exactly t = 4: the reference's
    stable sort puts the earlier object first, and so must ``intersect_world`` and the hit
    that ``color_at`` shades (a ball is tested after the items, so it wins ties by its
    row)."""
    results = {}
    for name in ("naive", "numba"):
        api = load_variant(name).api
        ball = api["sphere"]()
        ball.material = material(color=api["color"](1, 0, 0), ambient=1, diffuse=0, specular=0)
        floor = api["plane"]()
        api["set_transform"](floor, api["translation"](0, -1, 0))
        floor.material = material(color=api["color"](0, 0, 1), ambient=1, diffuse=0, specular=0)
        w = api["world"]()
        w.objects.extend([ball, floor] if sphere_first else [floor, ball])
        w.light = api["point_light"](api["point"](0, -10, -10), api["color"](1, 1, 1))
        r = api["ray"](api["point"](0, -5, 0), api["vector"](0, 1, 0))
        xs = api["intersect_world"](w, r)
        order = ["ball" if i.object is ball else "floor" for i in xs]
        c = api["color_at"](w, r)
        results[name] = ([i.t for i in xs], order, (c.red, c.green, c.blue))
    assert results["numba"] == results["naive"]
    assert results["naive"][1][0] == ("ball" if sphere_first else "floor")


RENDER_IN_A_FRESH_PROCESS = (
    "import sys\n"
    "import numpy as np\n"
    "sys.path.insert(0, 'tests')  # the suite's helpers, as pytest's rootdir conftest has them\n"
    "from tests.test_numba import default_world\n"
    "from variants.registry import load_variant\n"
    "from variants.numba import specialize\n"
    "api = load_variant('numba').api\n"
    "c, w = default_world(api)\n"
    "np.save(sys.argv[1], api['render'](c, w).to_array())\n"
    "print('numba' in sys.modules, [r.origin for r in specialize._renderers.values()])\n"
)


def _render_in_a_fresh_process(folder: str, **env: str) -> tuple[str, np.ndarray]:
    """The default world rendered by ``numba`` in a new interpreter: what it printed
    (whether numba was imported, where the render came from) and the picture."""
    saved = Path(folder) / "image.npy"
    done = subprocess.run(
        [sys.executable, "-c", RENDER_IN_A_FRESH_PROCESS, str(saved)], cwd=ROOT,
        capture_output=True, text=True, env={**os.environ, **env},
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return done.stdout, np.load(saved)


def test_a_render_needs_no_numba_once_its_library_is_built() -> None:
    """The render entry is a shared library, built once (this test's first render) and
    then loaded with ctypes: a fresh process renders without importing numba."""
    api = load_variant("numba").api
    c, w = default_world(api)
    expected = api["render"](c, w).to_array()
    with tempfile.TemporaryDirectory() as folder:
        printed, picture = _render_in_a_fresh_process(folder)
        assert printed.startswith("False ['shared library "), printed
        assert np.array_equal(picture, expected)


def test_without_a_c_compiler_the_render_falls_back_to_numba(specialized_kernels: None) -> None:
    """When the library cannot be linked (here: CC=/bin/false), the same compiled function
    runs from numba's own cache, and draws the same picture. The kernel is the default
    world's (specialized): the subject is the fallback, and the generic kernel compiled again
    in this test's own folder cost minutes."""
    api = load_variant("numba").api
    c, w = default_world(api)
    expected = api["render"](c, w).to_array()
    with tempfile.TemporaryDirectory() as folder:
        printed, picture = _render_in_a_fresh_process(
            folder, CC="/bin/false", RTC_NUMBA_KERNELS=folder
        )
        assert "numba cfunc with numba's disk cache" in printed, printed
        assert "could not link" in printed, printed
        assert not list(Path(folder).glob("*.so"))
        assert np.array_equal(picture, expected)


def test_specialize_off_uses_the_generic_kernel() -> None:
    variant = load_variant("numba[specialize=off]")
    assert variant.name == "numba[specialize=off]"
    assert "generic, every feature" in variant.tracer.explain(variant.api["default_world"]())


def test_the_gates_generic_kernel_calls_its_helpers_and_a_users_inlines_them(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``RTC_NUMBA_GENERIC_CALLS=on`` (the gate's, tests/conftest.py) makes the generic
    kernel the book API's module, helpers called (compiled in two thirds of the time); a
    specialized kernel, and any kernel without it, inlines them as a user's render does."""
    features = FeatureSet.from_key("sphere+shadows")
    generic, specialized = Options(specialize=False), Options()
    monkeypatch.setenv(GENERIC_ONLY, "on")
    monkeypatch.setenv(GENERIC_CALLS, "on")
    assert not generic.config(features).inline and specialized.config(features).inline
    assert generic.config(features) == generic.generic()
    assert "helpers called" in generic.config(features).describe()
    for value in ("off", None):
        if value is None:
            monkeypatch.delenv(GENERIC_CALLS)
        else:
            monkeypatch.setenv(GENERIC_CALLS, value)
        assert generic.config(features).inline
        assert "helpers called" not in generic.config(features).describe()


# ------------------------------------------------------------------------ allocations


def test_no_numba_allocation_per_pixel() -> None:
    """NRT allocation counts of a render do not grow with the image: they are 0, since the
    render entry is compiled without the numba runtime (a subprocess: the statistics are
    switched on before numba is imported; a function that does allocate shows that they
    count)."""
    code = (
        "import json, math\n"
        "import numpy as np\n"
        "from numba import njit\n"
        "from numba.core.runtime import rtsys\n"
        "from variants.registry import load_variant\n"
        "allocating = njit(lambda n: np.zeros(n).sum())\n"
        "allocating(3)\n"
        "before = rtsys.get_allocation_stats().alloc\n"
        "allocating(3)\n"
        "counts = {'control': rtsys.get_allocation_stats().alloc - before}\n"
        "for name in ('numba[threads=1]', 'numba[threads=2]'):\n"
        "    api = load_variant(name).api\n"
        "    w = api['default_world']()\n"
        "    for size in (4, 16, 64):\n"
        "        c = api['camera'](size, size, math.pi / 2)\n"
        "        api['render'](c, w)\n"
        "        before = rtsys.get_allocation_stats().alloc\n"
        "        api['render'](c, w)\n"
        "        counts[f'{name} {size}'] = rtsys.get_allocation_stats().alloc - before\n"
        "print(json.dumps(counts))\n"
    )
    env = {**os.environ, "NUMBA_NRT_STATS": "1"}
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    print(counts)
    assert counts["control"] >= 1, f"the NRT statistics do not count: {counts}"
    for name in ("numba[threads=1]", "numba[threads=2]"):
        per_size = {counts[f"{name} {size}"] for size in (4, 16, 64)}
        assert per_size == {0}, f"{name}: a render allocates through numba: {counts}"


# ------------------------------------------------------------------------ rays, options


def mirrored_default_world(api: Any, mirror: int) -> tuple[Any, Any]:
    """The default world (16x16) with one of its spheres a mirror: the inner one (``mirror``
    1: inside the outer, no ray meets it) or the outer one (0)."""
    camera, world = default_world(api)
    shape = world.objects[mirror]
    shape.material = replace(shape.material, reflective=0.5)
    return camera, world


@pytest.mark.usefixtures("specialized_kernels")
def test_count_rays_counts_camera_shadow_and_secondary_rays() -> None:
    """Counted by a kernel of the scene's own features, as a user's count is (the generic
    counting kernel is a build of its own: every feature, about 100 CPU s cold), with the
    camera and secondary counts naive's. One kernel (sphere, shadows, reflection) for both
    worlds: with the hidden inner sphere the mirror, no ray reflects though the reflection
    code is in; with the outer one, every camera ray that meets it reflects once."""
    numba, naive = load_variant("numba"), load_variant("naive")
    settings = RenderSettings(samples=2)
    counted = {}
    for mirror in (1, 0):
        counts = numba.tracer.count_rays(*mirrored_default_world(numba.api, mirror), settings)
        found = count_rays(naive, *mirrored_default_world(naive.api, mirror), settings)
        assert _counted(counts) == _counted(found), f"mirror {mirror}: {counts} != {found}"
        counted[mirror] = counts
    assert counted[1]["camera"] == counted[0]["camera"] == 16 * 16 * 2
    assert counted[1]["secondary"] == 0  # nothing a ray meets reflects or refracts
    assert 0 < counted[1]["shadow"] <= counted[1]["camera"]
    assert counted[0]["secondary"] > 0


def _counted(counts: dict[str, Any] | None) -> tuple[int, int]:
    """The camera and secondary rays of a count (numba casts no shadow ray from a point that
    faces away from the light, naive does: their shadow counts differ)."""
    assert counts is not None
    return counts["camera"], counts["secondary"]


def test_option_names_are_canonical_and_checked() -> None:
    assert load_variant("numba[threads=1,fastmath,float32]").name == (
        "numba[fastmath,float32,threads=1]"
    )
    assert load_variant("numba[fastmath=off,specialize=on]").name == "numba"
    with pytest.raises(VariantError, match="threads"):
        load_variant("numba[threads=0]")
    with pytest.raises(VariantError, match="no option 'colour'"):
        load_variant("numba[colour=red]")
    with pytest.raises(VariantError, match="does not wrap"):
        load_variant("numba:naive")


def test_the_book_api_is_answered_by_compiled_code() -> None:
    variant = load_variant("numba")
    for name in ("intersect", "normal_at", "lighting", "shade_hit", "color_at", "render"):
        assert name in variant.overrides
        assert getattr(variant.api[name], "__self__", None) is not None, name
    assert (
        "tuple" not in variant.overrides
        and variant.api["point"] is load_variant("naive").api["point"]
    )
    assert isinstance(variant.tracer, NumbaTracer)
    assert variant.overrides == EXTRA | {
        "lighting", "intersect_world", "prepare_computations", "shade_hit", "color_at",
        "is_shadowed", "reflected_color", "refracted_color", "schlick", "ray_for_pixel",
        "render", "intensity_at",
    }  # fmt: skip
    assert {"prepare", "render_region", "render_into"} <= set(variant.steps)
    assert variant.api["color_at"] == variant.tracer.color_at
    assert variant.api["stripe_at"] == variant.tracer.pattern_at


# ------------------------------------------------------------------------ regions

REGIONS = [
    (0, 0, 20, 1),  # the first row
    (0, 9, 20, 10),  # a row
    (3, 2, 11, 7),  # a tile
    (19, 14, 20, 15),  # the last pixel
    (7, 5, 8, 6),  # a pixel
    (0, 0, 20, 15),  # the whole image
]


@pytest.mark.parametrize("name", ["numba", "numba[threads=1]", "numba[float32]"])
@pytest.mark.parametrize("samples", [1, 4])
def test_a_region_is_the_same_pixels_as_the_whole_render(name: str, samples: int) -> None:
    """``render_region`` (absolute pixel coordinates and sample offsets) gives exactly the
    pixels of those coordinates in ``render``'s image."""
    variant = load_variant(name)
    tracer = variant.tracer
    camera, world = everything(variant.api)
    settings = RenderSettings(samples=samples, seed=3)
    whole = variant.api["render"](camera, world, settings).array
    for region in REGIONS:
        x0, y0, x1, y1 = region
        values = tracer.render_region(camera, world, settings, region)
        assert isinstance(values, list) and all(type(v) is float for v in values[:3])
        got = np.array(values, dtype=whole.dtype).reshape(y1 - y0, x1 - x0, 3)
        assert np.array_equal(got, whole[y0:y1, x0:x1]), region
    assert tracer.render_region(camera, world, settings, (4, 4, 4, 9)) == []
    tracer.forget()


def test_the_regions_of_a_frame_share_one_prepared_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    """A worker renders many regions of one frame: the world is packed once for all of
    them; another settings object (another frame) packs it again, and ``render`` always
    packs afresh."""
    from variants.numba import render as numba_render

    packed: list[Any] = []
    original = numba_render.pack_world

    def counting(*args: Any, **kwargs: Any) -> Any:
        packed.append(args[0])
        return original(*args, **kwargs)

    monkeypatch.setattr(numba_render, "pack_world", counting)
    variant = load_variant("numba")
    tracer = variant.tracer
    camera, world = default_world(variant.api)
    settings = RenderSettings()
    rows = [tracer.render_region(camera, world, settings, (0, y, 16, y + 1)) for y in range(16)]
    tracer.render_region(camera, world, settings, (2, 2, 6, 6))
    frame = tracer.prepared(camera, world, settings)
    assert tracer.prepared(camera, world, settings) is frame
    assert len(packed) == 1
    tracer.render_region(camera, world, RenderSettings(), (0, 0, 1, 1))
    assert len(packed) == 2
    image = tracer.render(camera, world, settings)
    assert len(packed) == 3
    assert np.array_equal(np.array(rows).reshape(16, 16, 3), image.array)


def test_render_reports_progress_chunk_by_chunk_with_every_row() -> None:
    """With a progress callback each thread renders its rows in chunks (how many depends on
    their time: ``tests/test_progress.py`` fixes it), the same picture."""
    variant = load_variant("numba")
    camera, world = default_world(variant.api)
    calls: list[int] = []
    image = variant.api["render"](camera, world, RenderSettings(), calls.append)
    assert isinstance(image, ArrayCanvas)
    assert sum(calls) == 16 and all(n > 0 for n in calls)
    assert np.array_equal(image.array, variant.api["render"](camera, world).array)


def test_the_tracer_pickles_as_its_options() -> None:
    """A pool may send the tracer to a worker: its kernels and prepared frame stay behind."""
    import pickle

    variant = load_variant("numba[float32,threads=1]")
    camera, world = default_world(variant.api)
    variant.tracer.render_region(camera, world, RenderSettings(), (0, 0, 2, 2))
    copy = pickle.loads(pickle.dumps(variant.tracer))
    assert isinstance(copy, NumbaTracer) and copy.options == variant.tracer.options
    assert copy.render_region(camera, world, RenderSettings(), (0, 0, 2, 2)) == (
        variant.tracer.render_region(camera, world, RenderSettings(), (0, 0, 2, 2))
    )


# ------------------------------------------------------------------------ the canvas


def test_the_array_canvas_is_a_canvas_over_its_array() -> None:
    api = load_variant("naive").api
    data = np.array(
        [[[0.0, 0.5, 1.5], [-0.2, 0.25, 1.0]], [[0.1, 0.2, 0.3], [1.0, 0.999, float("nan")]]]
    )
    image = ArrayCanvas(data)
    assert (image.width, image.height) == (2, 2)
    assert api["pixel_at"](image, 1, 0) == api["color"](-0.2, 0.25, 1.0)
    api["write_pixel"](image, 0, 1, api["color"](0.4, 0.5, 0.6))
    assert data[1, 0].tolist() == [0.4, 0.5, 0.6]
    listed = api["canvas"](2, 2)
    for y in range(2):
        for x in range(2):
            api["write_pixel"](listed, x, y, api["pixel_at"](image, x, y))
    assert image.to_rgb8() == canvas_to_rgb8(listed)
    assert canvas_to_ppm(image) == canvas_to_ppm(listed)


@pytest.mark.usefixtures("specialized_kernels")
def test_rtc_render_explain_prints_the_feature_set(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The soft shadows scene: its kernel (specialized) is the one
    ``test_numba_soft_textures`` compiles for its soft shadows, not one of this test's own."""
    from rtc.cli import main

    out = tmp_path / "out.png"
    scene = str(SCENES / "soft-shadows.yml")
    assert (
        main(["render", scene, "--variant", "numba", "--size", "8x6", "--explain", "-o", str(out)])
        == 0
    )
    printed = capsys.readouterr().out
    assert "shapes: sphere, plane, cube, cylinder\n" in printed
    assert "shading: shadows, area lights (a shadow ray per cell), jittered area lights" in printed
    assert "left out: cone, torus, triangle" in printed
    assert out.is_file()


def test_the_option_kernel_is_narrowed_only_where_the_scene_fits(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``RTC_NUMBA_OPTION_FEATURES`` (the gate's: tests/conftest.py) narrows the generic
    kernel of float32 and fast math to what it names, for a scene that needs no more; a
    scene that needs more, and float64, run every feature; a name no switch has is refused."""
    from variants.numba.features import OPTION_FEATURES, FeatureSet
    from variants.numba.render import GENERIC_ONLY, Options

    monkeypatch.setenv(GENERIC_ONLY, "off")  # the gate's (``--thorough`` specializes)
    monkeypatch.setenv(OPTION_FEATURES, "sphere+plane+shadows+reflection")
    sphere = FeatureSet.from_key("sphere+shadows")
    narrowed = FeatureSet.from_key("sphere+plane+shadows+reflection")
    for options in (Options(float32=True, specialize=False), Options(fastmath=True)):
        assert options.config(sphere).features == narrowed
        assert options.config(sphere.with_path()).features == FeatureSet.everything()
    assert Options(specialize=False).config(sphere).features == FeatureSet.everything()
    monkeypatch.setenv(GENERIC_ONLY, "on")
    assert Options(float32=True).config(sphere).features == sphere  # specialized: its own
    monkeypatch.setenv(OPTION_FEATURES, "sphere+sphears")
    from variants.registry import RenderError  # rtc render's one line, not a traceback

    spelled = r"RTC_NUMBA_OPTION_FEATURES='sphere\+sphears': no kernel feature is named 'sphears'"
    with pytest.raises(RenderError, match=spelled):
        Options(float32=True, specialize=False).config(sphere)


def test_rtc_bench_numba_targets(capsys: pytest.CaptureFixture[str]) -> None:
    """``rtc bench --numba-targets`` runs the numba benchmark (here its regions and
    balance sections: each calls the render entry itself); its options need the flag."""
    from harness.numba_targets import SECTIONS
    from rtc.cli import main

    run = ("regions", "balance")
    skip = [arg for section in SECTIONS if section not in run for arg in ("--skip", section)]
    assert main(["bench", "--numba-targets", "--runs", "1", *skip]) == 0
    printed = capsys.readouterr().out
    assert "480 render_region rows of a prepared frame" in printed
    assert "same picture: True" in printed
    assert "2-thread balance (reference 640x480, CPU seconds, best of 1): all rows" in printed
    assert main(["bench", "--numba-targets", "--runs", "0"]) == 2
    assert "--runs must be at least 1" in capsys.readouterr().err
    assert main(["bench", "--numba-targets", "--naive-size", "0x0"]) == 2
    assert "--naive-size: bad size '0x0'" in capsys.readouterr().err
    assert main(["bench", "--numba-targets", "--naive-pixels", "-1"]) == 2
    assert "--naive-pixels must be 0 or more" in capsys.readouterr().err
    assert main(["bench", "--runs", "3"]) == 2
    assert "only with --numba-targets" in capsys.readouterr().err


def test_a_camera_transform_is_inverted_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """``pack_camera`` (every frame) inverts a camera transform the first time only, with
    the reference's numbers; another transform gets its own inverse."""
    from raytracer.camera import camera
    from raytracer.transformations import view_transform
    from raytracer.tuples import point, vector
    from variants.numba import pack

    inverted: list[Matrix] = []
    real = pack.inverse

    def counting(m: Matrix, what: str) -> Matrix:
        inverted.append(m)
        return real(m, what)

    monkeypatch.setattr(pack, "inverse", counting)
    c = replace(
        camera(8, 6, math.pi / 3),
        transform=view_transform(point(1, 2, -5), point(0, 1, 0), vector(0, 1, 0)),
    )
    first = pack.pack_camera(c).array
    again = pack.pack_camera(c).array
    assert len(inverted) == 1 and np.array_equal(first, again)
    expected = real(c.transform, "the camera transform")
    assert list(first[:12]) == [expected[r, k] for r in range(3) for k in range(4)]
    c = replace(c, transform=view_transform(point(1, 2, -6), point(0, 1, 0), vector(0, 1, 0)))
    other = pack.pack_camera(c).array
    assert len(inverted) == 2 and not np.array_equal(first, other)
