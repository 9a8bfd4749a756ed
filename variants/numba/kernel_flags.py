"""The compile-time switches of the kernel template, at their generic values.

A generated kernel module (``variants.numba.specialize``) starts with its own copy of these
names, set for one scene's feature set and the variant's options; numba reads module globals
as constants, so a switch that is False removes its code from the compiled kernel. These
defaults (everything on, float64, no fastmath) are what the template files see when they are
imported directly, e.g. by mypy and ruff; nothing is ever compiled from them.
"""

import numpy as np

F = np.float64  # the float type of every computation (np.float32 with the float32 option)
FASTMATH: bool | set[str] = False  # LLVM fast-math flags (the fastmath option)
COUNT_RAYS = False  # count the rays traced (for Variant.count_rays; never in a timed render)
# the helpers inlined into every caller (a render); False for the book API's module, which
# then compiles in about two thirds of the time (its calls are not timed)
INLINE_HELPERS = True
# the helpers keep numba's Python and C wrappers (Python can call them: the tests call a
# few from the template files); False for the book API's module, whose helpers only its
# entry points call: it then compiles in about two thirds of the CPU time. The render's
# keep them: without, its machine code changes (and ran a few per cent slower)
HELPER_WRAPPERS = True

HAS_SPHERE = True
HAS_PLANE = True
HAS_CUBE = True
HAS_CYLINDER = True
HAS_CONE = True
HAS_TORUS = True
HAS_TRIANGLE = True
HAS_SMOOTH_TRIANGLE = True
HAS_TEST_SHAPE = True  # the chapter 9 test shape (the book API only, never a render)
HAS_CSG = True
HAS_BOXES = True  # bounding boxes (the hierarchy's nodes, or groups')
HAS_NODES = True  # a hierarchy over compact triangles alone, as compact nodes (``bvh``)

HAS_PATTERNS = True  # some material has a pattern; then one switch per pattern kind
HAS_STRIPE_PATTERN = True
HAS_GRADIENT_PATTERN = True
HAS_RING_PATTERN = True
HAS_CHECKERS_PATTERN = True
HAS_TEST_PATTERN = True
HAS_TEXTURE_MAP = True  # texture_map patterns: spherical, planar, cylindrical mappings
HAS_CUBE_MAP = True  # cube_map patterns
HAS_UV_IMAGE = True  # image textures (uv_image) among the texture patterns' uv patterns

HAS_SHADOWS = True  # some object casts a shadow
HAS_REFLECTION = True  # some material is reflective
HAS_REFRACTION = True  # some material is transparent
HAS_SCHLICK = True  # some material is both
HAS_AREA_LIGHTS = True  # some light is an area light (soft shadows, a shadow ray per cell)
HAS_JITTER = True  # ... whose cells' points are jittered at random
HAS_PATH = True  # the path integrator (chapter 21 here): a render asked for it (not the world)
