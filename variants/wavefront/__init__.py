"""``wavefront``: the C++ write-up's data-oriented design in NumPy (issue 16): no recursion,
rays laid out as a structure of arrays and advanced a whole pass at a time, passes sized
to a memory budget (chapters 5-16).

Options (the name spells the ones that differ from the defaults, sorted):

- ``max_mb=N``: the most MiB a pass's arrays take, all threads together (default 256): it
  sets how many rays a batch holds, so a 4000x3000 image at 16 samples renders in bounded
  memory;
- ``float32``: rays and the packed world in 32-bit floats;
- ``threads=N``: passes traced on N threads at once; they share only the read-only packed
  world. NumPy lets go of the GIL inside its loops, but the Python between them holds it,
  and a thread that comes back from a loop while another holds the GIL waits until the
  holder lets go, which CPython asks of it only after the switch interval (5 ms): so while
  threaded passes run, the interval is 0.1 ms (``handoff``). Measured on the reference scene
  at 640x480 on 2 cores: two threads 1.13-1.16x one's speed at 5 ms, 1.28-1.31x at 0.1 ms,
  1.54x with ``max_mb=1024`` (fewer, bigger calls a ray). The ceiling is NumPy's own: its
  loops on arrays of a pass's size ran 1.7x on two threads and 1.8x in two processes on
  the same machine. There is no shared-generator option (the C++ report's lesson): the
  path numbers are a hash with no state to share (docs/architecture.md, "No shared
  generator").

The package: ``scene`` (a world as tables), ``pack`` (a world packed into them, meshes with
NumPy; what the passes cannot vectorize, it refuses by name), ``geometry`` (each primitive
kind's intersection and normal over arrays), ``bvh`` (a linear hierarchy walked by whole
passes), ``hits`` (nearest hit, shadow rays, every intersection along a line; CSG trees),
``shading`` (computations, patterns, lights, Schlick, refraction), ``indices`` (n1 and n2
without sorted lists), ``camera`` (camera rays and the project's samples in uint64 NumPy),
``wave`` (the loop over depth and the passes), ``paths`` (the path integrator: every ray
of a pass carries its throughput, the pass goes one bounce at a time, finished rays are
dropped), ``tracer`` (``WavefrontTracer``). Its
benchmark section is ``rtc bench --sections pass-size`` (``harness.sections.pass_size.measure``).

Same pictures: at float64 each step is the reference's arithmetic in the reference's
order, so most pixels are naive's bits; sums differ in their last bits where the book's
recursion adds reflected and refracted colors (here weights carried on the rays), where a
shape sits in transformed groups (its transforms composed once) and where the canvas
stores float32; path-traced pictures add each bounce's light as it comes rather than nested,
and draw the reference's random numbers from each ray's sample key, so they too are the
reference's to rounding, whatever ``threads`` and ``max_mb`` cut.
"""

from __future__ import annotations

from variants.registry import (
    Variant,
    canonical_name,
    check_options,
    parse_bool,
    parse_int,
    reject_inner,
    tracer_variant,
)
from variants.wavefront.tracer import Options, WavefrontTracer

NAME = "wavefront"
OPTIONS = ("float32", "max_mb", "threads")
USAGE = "max_mb=N (MiB per pass, default 256), float32, threads=N (default 1)"
MAX_THREADS = 64
ONE_STEP = 1.0 / 255.0
# float32 passes: where they answer differently from naive beyond the tolerance (the rule
# ``tests/test_differential.py`` applies, then why); the book's geometry API is naive's
FLOAT32_DIFFERENCES = {
    "color_at": "float32: hits and shadow decisions within float32 rounding (about 1e-7 "
    "relative) of a silhouette, an edge or a light land on either side",
    "render": "float32: as color_at, pixel by pixel",
}


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: ``wavefront``, ``wavefront[max_mb=64]``,
    ``wavefront[float32,threads=2]``."""
    reject_inner(NAME, inner)
    check_options(NAME, options, OPTIONS)
    defaults = Options()
    max_mb = parse_int(NAME, "max_mb", options.get("max_mb", str(defaults.max_mb)), 1, 1 << 20)
    float32 = parse_bool(NAME, "float32", options.get("float32", "off"))
    threads = parse_int(NAME, "threads", options.get("threads", "1"), 1, MAX_THREADS)
    tracer = WavefrontTracer(Options(max_mb=max_mb, float32=float32, threads=threads))
    name = canonical_name(
        NAME,
        {
            "max_mb": None if max_mb == defaults.max_mb else max_mb,
            "float32": float32 or None,
            "threads": None if threads == 1 else threads,
        },
    )
    return tracer_variant(
        name,
        "data-oriented passes in NumPy: structure-of-arrays rays, no recursion, "
        "passes bounded by max_mb",
        tracer,
        base="naive",
        usage=USAGE,
        # float64: the reference's arithmetic but for a few sums and the float32 canvas;
        # float32 can flip a shadow or acne decision
        tolerance=ONE_STEP if not float32 else 0.25,
        differences=FLOAT32_DIFFERENCES if float32 else None,
    )
