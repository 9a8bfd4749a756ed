"""The robust variant's shading (chapters 7, 8 and 11): offsets that scale with the scene.

The book moves a hit point off its surface by a fixed ``EPSILON`` (0.0001) before casting
shadow, reflected and refracted rays. That is too much for a scene a millionth the size (the
offset is larger than the objects) and too little for one a million times larger or far from
the origin (smaller than the rounding error of the hit point: shadow acne). Here the offset is

    max(epsilon / stretch, ERROR_FACTOR * u * (|origin| + |t| |direction|))

- ``epsilon / stretch``: the offset in *object* space is ``epsilon`` (the book's, or
  ``RenderSettings.epsilon``), as the book's unit shapes have it; ``stretch`` is how much
  the transforms from object to world space shorten a unit step along the surface normal
  (the length of the inverse transpose times the unit object normal, through every parent).
  A unit sphere keeps the book's 0.0001; the same sphere scaled by 1e6 gets 100.
- the second term bounds the floating-point error of ``origin + t * direction`` (``u`` is
  the unit roundoff 2**-53, max-norms), so that the offset never drowns in rounding, even
  far from the origin.

Also here:

- ``is_shadowed`` ignores blockers within a relative 2**-30 of the light (a light lying on
  a surface does not flicker in and out of that surface's shadow);
- ``prepare_computations`` crosses coincident surfaces together when it works out n1 and
  n2 (nested glass sharing a surface is entered and left as one medium);
- ``refracted_color`` and ``schlick`` compute sin(theta_t) as ``n1/n2 * sin(theta_i)``
  (never ``inf * 0`` for very high indices) and the refracted direction from the tangential
  part of the eye vector (no cancellation);
- ``render`` is the reference's loop, tracing with these functions.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from raytracer.camera import Camera, RenderSettings, pixel_color, ray_for_pixel
from raytracer.canvas import Canvas, canvas, write_pixel
from raytracer.colors import BLACK, Color
from raytracer.intersections import Computations, Intersection, hit
from raytracer.materials import lighting
from raytracer.rays import Ray, position
from raytracer.shapes.shape import Shape
from raytracer.shapes.space import world_to_object
from raytracer.tolerance import epsilon, using_epsilon
from raytracer.tuples import Tuple, dot, reflect
from raytracer.world import World, intersect_world

UNIT_ROUNDOFF = 2.0**-53
ERROR_FACTOR = 2.0**10  # generous: the bound covers transforms and the solver, not just p = o + td
SHADOW_MARGIN = 1.0 - 2.0**-30  # a blocker must be nearer than this fraction of the light
COINCIDENT = 2.0**-40  # intersections this close (relative) are one boundary


def normal_and_stretch(
    shape: Shape, world_point: Tuple, hit: Intersection | None
) -> tuple[Tuple, float]:
    """Chapters 6 and 14: the world normal at ``world_point`` (as the reference computes it),
    and how much the transforms shorten a unit object-space step along it (``stretch``: 1 for
    rigid transforms, 1/s for a uniform scale by s). A zero normal (a cone's tip) has
    stretch 1."""
    local_point = world_to_object(shape, world_point)
    n = shape.local_normal_at(local_point, hit)
    length = math.sqrt(n.x * n.x + n.y * n.y + n.z * n.z)
    if length == 0.0:
        return Tuple(0.0, 0.0, 0.0, 0.0), 1.0
    stretch = 1.0 / length
    node: Shape | None = shape
    while node is not None:
        m = node.inverse_transpose * n
        size = math.sqrt(m.x * m.x + m.y * m.y + m.z * m.z)
        if size == 0.0 or not math.isfinite(size):
            return Tuple(0.0, 0.0, 0.0, 0.0), 1.0
        stretch *= size
        n = Tuple(m.x / size, m.y / size, m.z / size, 0.0)
        node = node.parent
    return n, stretch


def surface_offset(ray: Ray, t: float, stretch: float) -> float:
    """How far to move a hit off its surface (see the module docstring)."""
    o, d = ray.origin, ray.direction
    reach = max(abs(o.x), abs(o.y), abs(o.z)) + abs(t) * max(abs(d.x), abs(d.y), abs(d.z))
    return max(epsilon() / stretch, ERROR_FACTOR * UNIT_ROUNDOFF * reach)


def _same(i: Intersection, target: Intersection) -> bool:
    return i is target or (i.t == target.t and i.object is target.object)


def refractive_indices(hit: Intersection, xs: Sequence[Intersection]) -> tuple[float, float]:
    """Chapter 11's n1 and n2, with coincident surfaces crossed together: intersections at
    the same distance (within a relative 2**-40) are one boundary, so two glass spheres with
    the same transform are entered, and left, as one medium (the one listed last) instead
    of being entered as one and left as the other."""
    n1 = n2 = 1.0
    containers: list[Shape] = []
    start = 0
    while start < len(xs):
        t0 = xs[start].t
        end = start + 1
        while end < len(xs) and abs(xs[end].t - t0) <= COINCIDENT * abs(t0):
            end += 1
        boundary = xs[start:end]
        crosses_hit = any(_same(i, hit) for i in boundary)
        if crosses_hit:
            n1 = containers[-1].material.refractive_index if containers else 1.0
        for i in boundary:  # by identity: two equal spheres are still two
            inside = next((k for k, obj in enumerate(containers) if obj is i.object), None)
            if inside is None:
                containers.append(i.object)
            else:
                del containers[inside]
        if crosses_hit:
            n2 = containers[-1].material.refractive_index if containers else 1.0
            break
        start = end
    return n1, n2


def prepare_computations(
    hit: Intersection, ray: Ray, xs: Sequence[Intersection] | None = None
) -> Computations:
    """Chapters 7, 8, 11: the reference's computations with the scaled offset."""
    point = position(ray, hit.t)
    eyev = -ray.direction
    normalv, stretch = normal_and_stretch(hit.object, point, hit)
    inside = dot(normalv, eyev) < 0
    if inside:
        normalv = -normalv
    offset = normalv * surface_offset(ray, hit.t, stretch)
    n1, n2 = refractive_indices(hit, [hit] if xs is None else xs)
    return Computations(
        t=hit.t,
        object=hit.object,
        point=point,
        eyev=eyev,
        normalv=normalv,
        inside=inside,
        over_point=point + offset,
        under_point=point - offset,
        reflectv=reflect(ray.direction, normalv),
        n1=n1,
        n2=n2,
    )


def is_shadowed(w: World, point: Tuple) -> bool:
    """Chapter 8: something that casts shadows lies between ``point`` and the light (not
    counting what touches the light itself, within 2**-30 of the distance)."""
    if w.light is None:
        raise ValueError("is_shadowed: the world has no light source")
    v = w.light.position - point
    distance = math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z)
    if distance == 0.0:
        return False
    r = Ray(point, Tuple(v.x / distance, v.y / distance, v.z / distance, 0.0))
    limit = distance * SHADOW_MARGIN
    return any(0 <= i.t < limit and i.object.casts_shadow for i in intersect_world(w, r))


def schlick(comps: Computations) -> float:
    """Chapter 11: Schlick's reflectance; 1 under total internal reflection."""
    cos = dot(comps.eyev, comps.normalv)
    n1, n2 = comps.n1, comps.n2
    if n1 > n2:
        sin_t = n1 / n2 * math.sqrt(max(0.0, 1.0 - cos * cos))
        if sin_t > 1.0:
            return 1.0
        cos = math.sqrt(1.0 - sin_t * sin_t)
    r0 = ((n1 - n2) / (n1 + n2)) ** 2
    return r0 + (1 - r0) * (1 - cos) ** 5


def shade_hit(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapters 7, 8, 11: the reference's shade_hit, with this variant's functions."""
    if w.light is None:
        raise ValueError("shade_hit: the world has no light source")
    shadowed = is_shadowed(w, comps.over_point)
    m = comps.object.material
    surface = lighting(
        m, comps.object, w.light, comps.over_point, comps.eyev, comps.normalv, shadowed
    )
    reflected = reflected_color(w, comps, remaining)
    refracted = refracted_color(w, comps, remaining)
    if m.reflective > 0 and m.transparency > 0:
        reflectance = schlick(comps)
        return surface + reflected * reflectance + refracted * (1 - reflectance)
    return surface + reflected + refracted


def color_at(w: World, r: Ray, remaining: int = 5) -> Color:
    """Chapter 7: the color seen along ``r`` (black when it hits nothing)."""
    xs = intersect_world(w, r)
    h = hit(xs)
    if h is None:
        return BLACK
    return shade_hit(w, prepare_computations(h, r, xs), remaining)


def reflected_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: the reflected color, scaled by the material's reflectivity."""
    reflective = comps.object.material.reflective
    if reflective == 0 or remaining <= 0:
        return BLACK
    return color_at(w, Ray(comps.over_point, comps.reflectv), remaining - 1) * reflective


def refracted_color(w: World, comps: Computations, remaining: int = 5) -> Color:
    """Chapter 11: the color seen through the surface; black under total internal reflection.

    sin(theta_t) = n1/n2 sin(theta_i) is computed from sin(theta_i) (so a very high ratio
    times a zero sine is 0, not inf * 0), and the direction as n1/n2 times the tangential
    part of the eye vector, minus cos(theta_t) along the normal.
    """
    transparency = comps.object.material.transparency
    if transparency == 0 or remaining <= 0:
        return BLACK
    n_ratio = comps.n1 / comps.n2
    eyev, normalv = comps.eyev, comps.normalv
    cos_i = dot(eyev, normalv)
    sin_t = n_ratio * math.sqrt(max(0.0, 1.0 - cos_i * cos_i))
    if sin_t > 1.0:
        return BLACK  # total internal reflection
    cos_t = math.sqrt(1.0 - sin_t * sin_t)
    tangential = normalv * cos_i - eyev  # -sin(theta_i) along the surface
    direction = tangential * n_ratio - normalv * cos_t
    return color_at(w, Ray(comps.under_point, direction), remaining - 1) * transparency


@dataclass(frozen=True)
class _Tracer:
    camera: Camera
    world: World
    settings: RenderSettings

    def pixel(self, x: int, y: int) -> Color:
        """The reference's ``pixel_color``, tracing with this variant's ``color_at``."""
        return pixel_color(self.camera, self.world, x, y, self.settings, ray_for_pixel, color_at)


def render(
    c: Camera,
    w: World,
    settings: RenderSettings | None = None,
    progress: Callable[[int], object] | None = None,
) -> Canvas:
    """Chapter 7: render ``w`` as seen by ``c``, row by row (the reference's loop)."""
    tracer = _Tracer(c, w, settings if settings is not None else RenderSettings())
    image = canvas(c.hsize, c.vsize)
    with using_epsilon(tracer.settings.epsilon):
        for y in range(c.vsize):
            for x in range(c.hsize):
                write_pixel(image, x, y, tracer.pixel(x, y))
            if progress is not None:
                progress(1)
    return image
