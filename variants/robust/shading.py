"""The robust variant's tracer (chapters 7, 8 and 11): offsets that scale with the scene.

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
  a surface does not flicker in and out of that surface's shadow), and ``lighting`` lets a
  light exactly on the lit point (a cone's tip) add nothing but the ambient;
- ``prepare_computations`` crosses coincident surfaces together when it works out n1 and
  n2 (nested glass sharing a surface is entered and left as one medium);
- ``refracted_color`` and ``schlick`` compute sin(theta_t) as ``n1/n2 * sin(theta_i)``
  (never ``inf * 0`` for very high indices) and the refracted direction from the tangential
  part of the eye vector (no cancellation);
- everything else (``shade_hit``, ``color_at``, ``reflected_color``, the render loop) is
  the reference ``Tracer``'s, which calls these through ``self``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from raytracer.colors import BLACK, Color
from raytracer.intersections import Computations, Intersection, computations_at
from raytracer.lights import AreaLight, Light
from raytracer.materials import Material
from raytracer.materials import lighting as phong
from raytracer.rays import Ray, position
from raytracer.shapes.shape import Shape
from raytracer.space import Placed, world_to_object
from raytracer.tolerance import epsilon
from raytracer.tracer import Tracer, light_and_point
from raytracer.tuples import Tuple, dot, magnitude
from raytracer.world import World

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


class RobustTracer(Tracer):
    """The reference's pipeline with this module's lighting, prepare_computations, is_shadowed,
    schlick and refracted_color; every other step is the reference's and calls these."""

    def prepare_computations(
        self, hit: Intersection, r: Ray, xs: Sequence[Intersection] | None = None
    ) -> Computations:
        """Chapters 7, 8, 11: the reference's computations with the scaled offset and
        coincident surfaces crossed together."""
        point = position(r, hit.t)
        normalv, stretch = normal_and_stretch(hit.object, point, hit)
        n1, n2 = refractive_indices(hit, [hit] if xs is None else xs)
        offset = surface_offset(r, hit.t, stretch)
        return computations_at(hit, r, point, normalv, offset, n1, n2)

    def lighting(
        self,
        material: Material,
        object: Placed | None,
        light: Light,
        point: Tuple,
        eyev: Tuple,
        normalv: Tuple,
        in_shadow: bool | float = False,
        ambient: bool = True,
    ) -> Color:
        """Chapter 6: the reference's Phong colour, but a point light exactly on the lit point
        (a cone's tip, which has no normal to step off along), or so near that the distance
        underflows, lights only the ambient: the reference divides by the zero distance."""
        if not isinstance(light, AreaLight) and magnitude(light.position - point) == 0.0:
            in_shadow = True
        return phong(material, object, light, point, eyev, normalv, in_shadow, ambient)

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool:
        """Chapter 8: something that casts shadows lies between a point and a light (not
        counting what touches the light itself, within 2**-30 of the distance); the
        reference's two forms, ``(w, point)`` and ``(w, light_position, point)``."""
        light_position, point = light_and_point(w, first, second, "is_shadowed")
        v = light_position - point
        distance = math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z)
        if distance == 0.0:
            return False
        r = Ray(point, Tuple(v.x / distance, v.y / distance, v.z / distance, 0.0))
        limit = distance * SHADOW_MARGIN
        return any(0 <= i.t < limit and i.object.casts_shadow for i in self.intersect_world(w, r))

    def schlick(self, comps: Computations) -> float:
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

    def refracted_color(self, w: World, comps: Computations, remaining: int = 5) -> Color:
        """Chapter 11: the color seen through the surface; black under total internal
        reflection.

        sin(theta_t) = n1/n2 sin(theta_i) is computed from sin(theta_i) (so a very high
        ratio times a zero sine is 0, not inf * 0), and the direction as n1/n2 times the
        tangential part of the eye vector, minus cos(theta_t) along the normal.
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
        return self.color_at(w, Ray(comps.under_point, direction), remaining - 1) * transparency
