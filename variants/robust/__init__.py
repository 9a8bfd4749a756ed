"""``robust``: ``cached`` made numerically robust, so that a scene renders the same at any
scale and distance from the origin (chapters 5-15; ``rtc stability`` measures it).

What changes (everything else is ``cached``'s, which is the reference's):

- ``geometry``: shapes whose quadratics are solved without cancellation, whose parallel
  tests are exact (or relative, for triangles) instead of comparing with ``EPSILON``, and
  whose singular transforms are reported by name;
- ``shading``: ``RobustTracer``, which overrides five steps of the reference's pipeline:
  the over/under-point offset scaled to the object's size in world space and
  bounded below by the rounding error of the hit point; shadows that ignore what touches the
  light, and a light on the lit point that adds only the ambient; refraction without
  ``inf * 0`` at very high indices.

The book's scenarios pass unchanged (``pytest tests/test_features.py --variant robust``): at
the book's scales the offsets are the book's. Pictures differ from ``naive``'s where the
book's fixed offsets differ from the scaled ones (contact shadows of scaled objects) and in
the last bits of the quadratics: by at most 0.001 per channel on
``tests/test_equivalence.py``'s scenes and 0.0033 on the reference scene at 64x48, so
``tolerance`` is one 8-bit step (1/255).
"""

from __future__ import annotations

from raytracer.api import naive_api
from variants.cached import twin_api
from variants.registry import Variant, check_options, reject_inner, tracer_variant
from variants.robust.geometry import ROBUST_CLASSES
from variants.robust.shading import RobustTracer

NAME = "robust"
TOLERANCE = 1.0 / 255.0
# where robust answers differently from naive on purpose, beyond ``TOLERANCE`` (each reason
# starts with the rule ``tests/test_differential.py`` applies to it)
DIFFERENCES = {
    "intersect": "epsilon: parallel tests are exact (relative for triangles) instead of the "
    "book's |d| < EPSILON, so a ray within EPSILON of parallel to a plane, a cube's face or "
    "a cylinder's axis still hits; a hit at an infinite distance (1 / 1e-313 overflows) "
    "is none",
    "color_at": "epsilon: over/under-point offsets scaled to the object's size, exact "
    "parallel tests and shadows that ignore what touches the light (a light on the lit point "
    "adds only the ambient): contact shadows, acne "
    "and near-parallel hits differ where naive's fixed EPSILON decides them",
    "render": "epsilon: as color_at, pixel by pixel",
}


def variant(inner: Variant | None = None, **options: str) -> Variant:
    """The registry's factory: no options, no inner variant."""
    reject_inner(NAME, inner)
    check_options(NAME, options)
    api, overrides = twin_api(naive_api(), ROBUST_CLASSES)
    return tracer_variant(
        NAME,
        "cached, with offsets scaled to the scene, cancellation-free quadratics and "
        "exact parallel tests: the same picture at any scale",
        RobustTracer(),
        api=api,
        overrides=overrides,
        base="cached",
        tolerance=TOLERANCE,
        differences=DIFFERENCES,
    )
