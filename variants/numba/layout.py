"""Where everything sits in the packed arrays: shared by the packer and the kernel template.

A packed world is a handful of arrays (see ``variants.numba.pack``), built as 2-D tables and
handed to the kernels flattened (row-major): ``pf[p * NF + column]``. Flat indexing reads
the same from a numpy array (the book-API kernels) and from a raw pointer (the render
entry point, called through ctypes), and takes no row views (no reference counting).

- ``pf[p, column]`` (floats) and ``pi[p, column]`` (ints): one row per primitive (a leaf shape:
  sphere, plane, cube, cylinder, cone, triangle, smooth triangle, test shape), holding its
  composed world-to-object transform, the transform for normals, its material and pattern,
  and its own parameters (chapters 5-15); and one row per *run* of triangles packed
  compactly (a mesh, chapter 15): their shared transform, material and shadow, and where
  their numbers are in ``tg`` (``TRI_FIRST``, ``TRI_COUNT``) and ``tn`` (``TN_FIRST``);
- ``tg[t, column]``: a compact triangle's corner p1, edges e1, e2 and face normal (``NTG``
  floats), ``tn[k, column]``: a smooth one's corner normals (``NTN``). A ray meets triangle
  t of run row r through an ``I_TRI`` item; its hit is (r, t): the run's row stands for
  every triangle in it, and t (its "local" number) orders them, as the world's order does;
- ``items[i, column]`` and ``boxes[i, column]``: the order in which a ray visits the world,
  depth first: a primitive, a bounding box (skip what it holds when the ray misses it:
  a node of the bounding-volume hierarchy, ``bvh``, or a group's box, chapter 14), or a
  CSG tree (chapter 16);
- ``balls[row, j]``: the spheres with a similarity transform outside CSG trees, column by
  column (centre, radius², casts a shadow, primitive row), so that a ray meets all of them
  in one loop that the compiler turns into vector instructions; their items are dropped;
- ``csg[n, column]``: CSG operations in post-order, each over a range of primitives;
- ``lights[k, column]``: light k's position and intensity, and an area light's cells
  (``NLIGHT`` columns), then the area lights' jitter sequences; ``cam`` (the inverse view
  transform and pixel geometry);
- ``ti`` and ``tf``: the texture patterns' records (the bonus chapter on texture mapping):
  a map record per ``TextureMap`` or ``CubeMap``, a uv record per uv pattern (ints), their
  colors and images' pixels (floats); a primitive row names its map record (``PAT_TEX``).

This file is also the first part of every generated kernel module (see
``variants.numba.specialize``), so the kernels read these names as compile-time constants.
"""

# ---- kernel template ----

from scene.kinds import kind as _kind  # the kind table (``scene.kinds``) numbers the kinds
from scene.pattern_kinds import NO_PATTERN as _NO_PATTERN  # and the pattern table patterns
from scene.pattern_kinds import pattern_kind as _pattern_kind

# pf: primitive floats
INV = 0  # 12: world -> object space, rows 0-2 of the composed inverse transform (row-major)
NRM = 12  # 9: object -> world for normals: rows 0-2 of the inverse transpose (3x3)
PAT = 21  # 12: object -> pattern space, rows 0-2 of the pattern's inverse transform
COLOR = 33  # 3: the material's color
AMBIENT = 36
DIFFUSE = 37
SPECULAR = 38
SHININESS = 39
REFLECTIVE = 40
TRANSPARENCY = 41
REFRACTIVE_INDEX = 42
PAT_A = 43  # 3: the pattern's first color
PAT_B = 46  # 3: the pattern's second color
PARAMS = 49  # 2: a kind's number parameters, in the kind table's order: cylinders and cones
MINIMUM = PARAMS  # ... their y range (minimum, maximum)
MAXIMUM = PARAMS + 1
TORUS_MAJOR = PARAMS  # tori: the centre circle's radius
TORUS_MINOR = PARAMS + 1  # ... and the tube's
TRI_P1 = 51  # 3: triangles: the first corner
TRI_E1 = 54  # 3: p2 - p1
TRI_E2 = 57  # 3: p3 - p1
TRI_NORMAL = 60  # 3: the flat normal
TRI_N1 = 63  # 3: smooth triangles: the corner normals
TRI_N2 = 66
TRI_N3 = 69
BOUND = 72  # 4: a world-space sphere holding the primitive: centre, radius (inf: none)
POW_FLOOR = 76  # reflect_dot_eye at or below which reflect_dot_eye ** shininess < 1e-9
SPH_CENTER = 77  # 3: spheres whose transform is a similarity: the world-space centre
SPH_R2 = 80  # ... the radius squared
SPH_INV_R = 81  # ... and 1 / radius
EMISSIVE = 82  # 3: the light the surface gives off (the path integrator's, chapter 21 here)
NF = 85

# pi: primitive ints
KIND = 0  # one of the K_ values
PATTERN = 1  # one of the P_ values
CASTS_SHADOW = 2  # 0 or 1
CLOSED = 3  # a kind's boolean parameter (cylinders and cones: 1 when capped)
WORLD_SPHERE = 4  # 1: a sphere tested in world space (SPH_*): its transform is a similarity
PAT_TEX = 5  # texture patterns (P_MAP, P_CUBE_MAP): where their map record starts in ``ti``
TRI_FIRST = 6  # a run of compact triangles: its first triangle in ``tg`` (-1: not a run)
TN_FIRST = 7  # ... a smooth run: its first entry in ``tn`` (-1: flat)
TRI_COUNT = 8  # ... how many triangles
NI = 9

# tg (compact triangles, floats): per triangle
TG_P1 = 0  # 3: the first corner
TG_E1 = 3  # 3: p2 - p1
TG_E2 = 6  # 3: p3 - p1
TG_NORMAL = 9  # 3: the flat normal
NTG = 12
# tn (compact smooth triangles, floats): per smooth triangle, n1, n2, n3
NTN = 9

# shape kinds
# shape kinds: their numbers in the kind table (a generated kernel module's header lists
# them, so that a change of the table gives new kernels)
K_SPHERE = _kind("sphere").number
K_PLANE = _kind("plane").number
K_CUBE = _kind("cube").number
K_CYLINDER = _kind("cylinder").number
K_CONE = _kind("cone").number
K_TORUS = _kind("torus").number
K_TRIANGLE = _kind("triangle").number
K_SMOOTH_TRIANGLE = _kind("smooth_triangle").number
K_TEST = _kind("test_shape").number  # chapter 9's test shape: no hits, normal = the point

# pattern kinds: their numbers in the pattern table (``scene.pattern_kinds``; the header of
# a generated kernel module lists them too)
P_NONE = _NO_PATTERN
P_STRIPE = _pattern_kind("stripe_pattern").number
P_GRADIENT = _pattern_kind("gradient_pattern").number
P_RING = _pattern_kind("ring_pattern").number
P_CHECKERS = _pattern_kind("checkers_pattern").number
P_TEST = _pattern_kind("test_pattern").number
P_MAP = _pattern_kind("texture_map").number  # texture mapping: a uv pattern through a mapping
P_CUBE_MAP = _pattern_kind("cube_map").number  # ... six uv patterns, one per face of a cube

# ti (texture ints) and tf (texture floats): texture patterns' records (the bonus chapter
# on texture mapping), each starting at an offset that names it. A map record in ti: the
# mapping, then where its uv patterns' records start in ti (one for a texture map; a cube
# map's six in ``cube_map``'s order: left, front, right, back, up, down)
MAP_KIND = 0  # one of the M_ values
MAP_UV = 1  # 6
NMAP = 7
M_SPHERICAL = 0
M_PLANAR = 1
M_CYLINDRICAL = 2
M_CUBE = 3
FACE_LEFT = 0  # face_from_point's faces, as a cube map's uv patterns are ordered
FACE_FRONT = 1
FACE_RIGHT = 2
FACE_BACK = 3
FACE_UP = 4
FACE_DOWN = 5
# a uv-pattern record in ti: its kind, where its floats start in tf, an image's size
UV_KIND = 0  # one of the UV_ kinds below
UV_AT = 1  # its floats in tf: checkers: width, height, a (3), b (3); align check: main,
# ul, ur, bl, br (3 each); image: the canvas's pixels, row by row from the top (3 each)
UV_WIDTH = 2  # an image's width and height in pixels
UV_HEIGHT = 3
NUV = 4
UV_CHECKERS = 0
UV_ALIGN_CHECK = 1
UV_IMAGE = 2

# items: what a ray visits, in order
ITEM_TYPE = 0
ITEM_A = 1  # primitive: its row; box: the item after its contents; csg: its first csg node;
# compact triangle: its run's row
ITEM_B = 2  # csg: one past its last csg node; box of a hierarchy's inner node: the first
# item of its second child; compact triangle: its number in ``tg``
ITEM_C = 3  # csg: its first primitive; box: the split axis + 1 of a hierarchy's inner node
# (a ray going down that axis visits the second child first), else 0
ITEM_D = 4  # csg: one past its last primitive
NITEM = 5
I_PRIM = 0
I_BOX = 1
I_CSG = 2
I_SKIP = 3  # nothing (a group whose box would not help; dropped when packing ends)
I_TRI = 4  # a compact triangle (``tg``) of a run
I_NODES = 5  # a hierarchy over compact triangles only, also as compact nodes (``bvh``):
# ITEM_A: the item after the hierarchy's items (which follow it, for the kernels that walk
# the items), ITEM_B: where its root node starts in the flat box table (``nodes``), ITEM_C:
# WIDE when the nodes are wide ones (``bvh=sah4``), else 0

# csg nodes (post-order): the left operand is primitives [START, MID), the right [MID, END)
CSG_START = 0
CSG_MID = 1
CSG_END = 2
CSG_OP = 3
NCSG = 4
OP_UNION = 0
OP_INTERSECTION = 1
OP_DIFFERENCE = 2

# balls: the world spheres outside CSG trees (WORLD_SPHERE rows whose item is I_PRIM), taken
# out of the items and tested all at once; column j of row r at balls[r * n_balls + j]
B_X = 0  # the centre
B_Y = 1
B_Z = 2
B_R2 = 3  # the radius squared
B_SHADOW = 4  # 1.0 when it casts a shadow, else 0.0
B_PRIM = 5  # its primitive row (a float; exact below 2**24 in float32)
NBALL = 6

# boxes: one row per box item (its ITEM_D): lo x, y, z, hi x, y, z
NBOX = 6
# nodes (after the boxes in the flat box table): a hierarchy over compact triangles, a
# node per row, a node's two children side by side: its box (NBOX), then two links,
# integers stored as the bits of their float slot (``bvh.node_links``, ``int_bits``):
NODE_A = 6  # an inner node: its first child's row; a leaf: its first I_TRI item
NODE_C = 7  # a leaf: how many triangles (> 0); an inner node: -1 - its split axis + 1
# (-1: no axis, the first child first; -2, -3, -4: x, y, z, the second child first for
# a ray going down that axis)
NNODE = 8
# wide nodes (``bvh=sah4``: the same hierarchy collapsed, a node adopting its children's
# children), NWIDE values a node: four children's boxes as six rows of four (lo x, lo y,
# lo z, hi x, hi y, hi z; child j at row * WIDE + j; an empty slot's box holds nothing: lo
# +inf, hi -inf), then four links as int32 (in W_LINK's value and on): a child node's row
# (>= 0), or a leaf, -1 - (its first I_TRI item * 8 + how many triangles); then nothing
WIDE = 4
W_LINK = 6 * WIDE
NWIDE = 32

# the hierarchy's builder (``bvh``, ``bvh_kernel``: its own copies, checked by the tests)
BVH_BINS = 16  # bins per axis
BVH_STACK = 256  # its stack of nodes to build
BVH_UNIT = 6  # per unit (float32): box lo x, y, z, hi x, y, z
BVH_STATS = 5  # what it reports: nodes, leaves, box items, depth, items
BVH_WORK = 7 * BVH_STACK + 3 * BVH_BINS  # its scratch: ints (pending nodes, open boxes, counts)
BVH_FWORK = 3 * BVH_BINS * 6 + 2 * BVH_BINS + 15  # ... and floats (the bins' boxes, areas ...)

# lights: one row per light, then the area lights' jitter sequences (the values of each,
# in order, from lights[n_lights * NLIGHT + LIGHT_SEQ])
LIGHT_POSITION = 0  # 3: a point light's position; an area light's centre
LIGHT_INTENSITY = 3  # 3
LIGHT_CORNER = 6  # 3: an area light (the bonus chapter on soft shadows): its corner
LIGHT_UVEC = 9  # 3: ... one cell's edge along u (the full edge / usteps)
LIGHT_VVEC = 12  # 3: ... and along v
LIGHT_USTEPS = 15  # cells along u (0: a point light)
LIGHT_VSTEPS = 16  # ... and along v
LIGHT_JITTER = 17  # 1: each cell's point placed at random (``raytracer.sampling``); 0: by
# the light's sequence
LIGHT_SEQ = 18  # where the sequence's values start, after the rows
LIGHT_SEQ_N = 19  # how many values it has
LIGHT_SEQ_AT = 20  # the value it gives next (the reference's cyclic generator's position)
NLIGHT = 21

# cam: the camera
CAM_INV = 0  # 12: rows 0-2 of the inverse view transform
CAM_HALF_WIDTH = 12
CAM_HALF_HEIGHT = 13
CAM_PIXEL_SIZE = 14
NCAM = 15

# sky: what a path that meets nothing sees (``raytracer.sky``; black without one)
SKY_HORIZON = 0  # 3: the colour at and below the horizon
SKY_ZENITH = 3  # 3: ... and straight up
NSKY = 6

# the render entry's ``integrator`` argument (``kernels_entry``)
INTEGRATOR_WHITTED = 0  # the book's
INTEGRATOR_PATH = 1  # the path integrator (chapter 21 here; kernels compiled with HAS_PATH)
INTEGRATOR_PATH_CROSSED = 2  # ... with light sampling off (area lights found by crossing)

# per-thread scratch for CSG trees, entry j of column c at sf[j * NSF + c] (floats) and
# si[j * NSI + c] (ints)
CS_T = 0  # sf: the tree's intersection list: t
CS_U = 1  # sf: ... a triangle's u
CS_V = 2  # sf: ... and v
CS_LAST_T = 3  # sf: per primitive of the tree: its latest t before the hit (n1/n2)
NSF = 4
CS_P = 0  # si: the list: the primitive
CS_L = 1  # si: the list: the index within the primitive's own list
CS_START = 2  # si: per primitive of the tree: where its entries start in the list
CS_COUNT = 3  # si: per primitive: how many of its intersections come before the hit
CS_LAST_L = 4  # si: per primitive: the index of its latest one
RAYS = 5  # si: entries 0, 1, 2 (count_rays kernels): rays traced, shadow rays, n1/n2 passes
MEMO = 6  # si: entry k: the item that last shadowed a point from light k (modulo the
# entries) on this thread (-1: none)
BV_FROM = 7  # si: the hit ray's stack of item ranges still to visit (an ordered hierarchy's
BV_TO = 8  # ... second children taken first): entry k is [BV_FROM, BV_TO)
NSI = 9
BVH_DEPTH = 64  # the deepest a hierarchy's node can be (``bvh``: the builder keeps to it)
MIN_SCRATCH = 2 * BVH_DEPTH + 2  # entries at least: the RAYS counters, the range stack

# the per-ray stack of reflected and refracted rays: origin, direction, weight, remaining;
# entry k at stack[k * STACK_WIDTH + column]
STACK_WIDTH = 8
# a thread's next camera rays (``kernels_trace.sample_rays``), after its stack: a row of
# RAY_BLOCK per coordinate (ox, oy, oz, dx, dy, dz)
RAY_BLOCK = 8
