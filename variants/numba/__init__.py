"""``numba``: the book's tracer compiled with numba: packed arrays, a render with no
allocation in compiled code, one kernel per scene feature set (chapters 1-16, and the
bonus chapters on bounding boxes, soft shadows and texture mapping).

Options (all off by default; the name spells the ones given, sorted):

- ``float32``: compute and store in float32 instead of float64;
- ``fastmath``: LLVM fast-math (reassociation, fused multiply-add, ...);
- ``threads=N``: render on N threads (default: the CPUs this process may use, or
  ``NUMBA_NUM_THREADS``); no shared-generator option (the C++ report's lesson): the path
  numbers are a hash with no state to share (docs/architecture.md, "No shared generator");
- ``specialize=off``: always the generic kernel, every feature compiled in;
- ``bvh=sah|sah4|sah-items|groups|off``: how the rays find the primitives they may hit
  (``bvh``): a bounding-volume hierarchy built by the surface area heuristic (the default;
  over triangles alone it is also laid out as compact nodes, ``sah4`` collapses those
  into wide nodes of four children, ``sah-items`` walks it as items only), the scene's
  own group boxes, or none (every ray visits every primitive).

The package: ``layout`` (array columns), ``pack`` (world -> arrays, into a ``packed``
world; ``lights`` and ``textures`` pack the light table and the texture patterns' records;
what cannot be packed is an ``errors.PackError``), ``bvh`` and ``bvh_kernel`` (the
hierarchy over the packed items, and its compiled builder), ``features`` (what a scene
needs), ``specialize`` (one generated kernel module per feature set; its render compiled
once into a shared library, loaded without numba), ``kernels_*`` (the kernel template),
``render`` (frames, and regions on threads over interleaved rows), ``api``
(``NumbaTracer``: the book's pipeline and API through the kernels; its canvas is
``variants.arrays``'). Its benchmark is ``rtc bench --numba-targets``
(``harness.numba_targets``).

Same pictures, not the same bits: at float64 without fastmath the kernels follow the
reference's arithmetic except where a faster formulation rounds differently, each one
documented where it lives: spheres with a similarity transform tested in world space with
a cancellation-free quadratic and their normals taken as (point - centre) / radius
(``kernels_geometry``, ``kernels_prims``); reciprocals instead of divisions when
normalizing; the specular term left out where it is below 1e-9 of the light, Schlick's
powers as products (``kernels_shading``); group transforms composed once (``pack``). Colors move by
about 1e-9 at most; ``tests/test_numba.py`` and ``rtc bench --numba-targets`` measure it.
The ``bvh`` structures change which primitives a ray visits and in what order, never the
hit it keeps (ties go to the earlier primitive, as in the reference's sorted list) nor a
shadow: their pictures are the same bits (``tests/test_numba_bvh.py``). Several lights
shade as the reference does: each light's diffuse and specular with its own shadow test,
the ambient term once, from the first (``tests/test_numba_lights.py``). An area light
casts a shadow ray per cell at every shaded point, its cells' points jittered by the
reference's ``light_jitter`` (the same uint64 arithmetic, bit for bit) or placed by its
sequence; texture maps (spherical, planar, cylindrical, cube; checkers, align check and
images, an image a block of floats in the texture table) color surfaces as the reference's
patterns do (``tests/test_numba_soft_textures.py``). A scene without them runs a kernel
without their code.
"""

from __future__ import annotations

import importlib.util

from variants.numba.api import EXTRA, NumbaTracer
from variants.numba.bvh import DEFAULT, STRUCTURES
from variants.numba.render import Options, max_threads
from variants.registry import (
    Unavailable,
    Variant,
    canonical_name,
    check_options,
    parse_bool,
    parse_choice,
    parse_int,
    reject_inner,
    tracer_variant,
)

NAME = "numba"
OPTIONS = ("bvh", "fastmath", "float32", "specialize", "threads")
USAGE = (
    "float32, fastmath, threads=N (default: every CPU this process may use), specialize=off, "
    "bvh=sah|sah4|sah-items|groups|off (default sah)"
)
ONE_STEP = 1.0 / 255.0
# float32 arithmetic: where it answers differently from naive beyond its tolerance (each
# reason starts with the rule ``tests/test_differential.py`` applies to it)
FLOAT32_DIFFERENCES = {
    name: "float32: hits, edges and shadow decisions within float32 rounding (about 1e-7 "
    "relative, more through an ill-conditioned transform) of a tangent, an edge or a "
    "light land on either side"
    for name in ("intersect", "normal_at", "world_to_object", "normal_to_world", "color_at")
} | {"render": "float32: as color_at, pixel by pixel"}
# float64: a shape's inverse composed with its groups' once (``pack``), where naive goes
# through each group: through ill-conditioned transforms the rounding differs
COMPOSED_DIFFERENCES = {
    name: "composed: a shape's inverse is multiplied with its groups' inverses once, so "
    "through ill-conditioned transforms (condition cond) points and normals differ by about "
    "cond * 2**-52"
    for name in ("world_to_object", "normal_to_world")
}
# fastmath (float64): reassociated, fused arithmetic; the same rule's tag for each name
FASTMATH_DIFFERENCES = {
    name: "fastmath: reassociation and fused multiply-adds change what cancellation leaves "
    "of a grazing quadratic (a ray down a cone's axis meets its tip or not) and which side "
    "of an edge or a shadow's boundary a point rounds to"
    for name in ("intersect", "normal_at", "color_at", "render")
} | COMPOSED_DIFFERENCES


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: ``numba``, ``numba[float32,fastmath,threads=1]``,
    ``numba[specialize=off]``, ``numba[bvh=off]``."""
    reject_inner(NAME, inner)
    check_options(NAME, options, OPTIONS)
    if importlib.util.find_spec("numba") is None:
        raise Unavailable("numba is not installed (pip install numba)")
    float32 = parse_bool(NAME, "float32", options.get("float32", "off"))
    fastmath = parse_bool(NAME, "fastmath", options.get("fastmath", "off"))
    specialize = parse_bool(NAME, "specialize", options.get("specialize", "on"))
    bvh = parse_choice(NAME, "bvh", options.get("bvh", DEFAULT), STRUCTURES)
    threads = (
        parse_int(NAME, "threads", options["threads"], 1, max_threads())
        if "threads" in options
        else None
    )
    tracer = NumbaTracer(
        Options(float32=float32, fastmath=fastmath, threads=threads, specialize=specialize, bvh=bvh)
    )
    name = canonical_name(
        NAME,
        {
            "float32": float32 or None,
            "fastmath": fastmath or None,
            "threads": threads,
            "specialize": None if specialize else False,
            "bvh": None if bvh == DEFAULT else bvh,
        },
    )
    exact = not (float32 or fastmath)
    return tracer_variant(
        name,
        "compiled with numba: packed arrays, threads over rows, a kernel per feature set",
        tracer,
        api=tracer.book_api(),
        overrides=EXTRA,
        base="naive",
        usage=USAGE,
        # float64 rounds differently from the reference in a few places (see above): colors
        # move by about 1e-9; float32 and fastmath can flip a shadow or acne decision
        tolerance=ONE_STEP if exact else 0.25,
        differences=(
            FLOAT32_DIFFERENCES
            if float32
            else FASTMATH_DIFFERENCES
            if fastmath
            else COMPOSED_DIFFERENCES
        ),
    )
