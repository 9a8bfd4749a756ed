"""The path integrator (chapter 21 here, beyond the book; the C++ report's renderer):
Monte Carlo path tracing with the book's materials, lights and shapes.

Three ``Tracer`` steps (``raytracer.tracer`` binds these functions as its methods; the
first argument is the tracer, so a variant's override of any step is called):

- ``path_color_at(w, r, depth, roulette, bounce, throughput, light_sampling)``: the light
  carried back along ``r``, weighted by ``throughput``; recursive, as the C++ report's
  Listing 1;
- ``scatter(comps, lobe_u, fresnel_u, u1, u2)``: where a path goes from a hit, and the
  weight it takes (``Scattered``);
- ``direct_light(w, comps, weight, bounce, area)``: the book's lights seen from a diffuse
  hit (next-event estimation, or explicit light sampling);
- ``crossed_lights(w, r, weight)``: the area lights that a ray leaving a diffuse hit
  crosses (with light sampling off).

They reach the hits through the steps they share with the book's integrator
(``intersect_world``, ``prepare_computations``, ``is_shadowed``, ``schlick``), so a variant
that changes how hits are found path-traces with its own code.

**A path** starts at a camera ray with throughput white. At the hit of bounce b (the camera
ray's is bounce 0), with the material m and its computations::

    add throughput * m.emissive
    if b == depth: stop                       (only emission at the bounce cap)
    if roulette > 0 and b >= roulette:        (Russian roulette: ``russian_roulette``)
        p = min(1, max(throughput.red, .green, .blue))
        if number(b, ROULETTE) >= p: stop
        throughput = throughput / p          (each channel divided)
    choose a lobe and a new ray (``scatter``, numbers LOBE, FRESNEL, DIRECTION, DIRECTION+1)
    throughput = throughput * its weight
    if throughput is black: stop              (it can add nothing more)
    if the lobe is diffuse:
        light sampling on:  add direct_light(throughput)
        light sampling off: add direct_light(throughput) of the point lights only,
                            and crossed_lights(the new ray, throughput)
    follow the new ray as bounce b + 1

A ray that meets nothing adds ``throughput * sky_color(w.sky, direction)``
(``raytracer.sky``). The sum is kept as ``emitted + direct + the rest of the path``.

**The lobes** (``raytracer.scatter.choose_lobe``): diffuse: a cosine-weighted direction
around the normal (which faces the eye) from ``over_point``, weight ``colour * diffuse``
(colour: the pattern at ``over_point`` if any, else ``color``, as the book's ``lighting``
takes it); mirror: the book's ``reflectv`` from ``over_point``, weight white (the book's
reflections are not tinted by the surface; its share is the probability); glass: with
probability ``schlick(comps)`` the mirror's ray (named "reflect"), else the book's refracted
direction from ``under_point`` ("refract"; total internal reflection reflects), weight white.

**Direct light** at a diffuse hit, for each light k of the world in order, summed from
black: the light's point (a point light's position; an area light's ``corner + uvec * (u *
usteps) + vvec * (v * vsteps)`` with u, v its two numbers: one point spread uniformly over
the whole light, its cells and ``jitter`` not used), ``cos = dot(normalize(point -
over_point), normalv)``; if cos > 0 and ``is_shadowed(w, point, over_point)`` is false,
add ``weight * intensity * cos``. That is the book's diffuse term without 1 / pi, so the
book's lights keep their brightness under either integrator. Emissive surfaces are found
only by the paths that hit them (no ray is aimed at them).

**Without light sampling** (``RenderSettings.light_sampling`` False) no shadow ray is aimed
at an area light: the light is found by the paths that cross it. A ray leaving a diffuse
hit from ``o`` along ``d`` crosses area light k (the parallelogram ``corner + U a + V b``,
U = uvec * usteps, V = vvec * vsteps, 0 <= a, b <= 1, n = U x V, seen from both sides, and
never in a path's way) at t = (corner - o) . n / (d . n) > 0; where the point there is not
shadowed from ``o`` (``is_shadowed``) the path adds::

    weight * intensity * pi t^2 |d|^3 / |d . n|

and goes on as if the light were not there. That factor is the book's light turned into a
surface: direct light at a point is ``intensity * cos`` averaged over the light's area A,
and a cosine-weighted direction (pdf cos / pi) crosses the patch dA with probability
``cos / pi * dA cos_l / r^2`` (r = t |d|, cos_l = |d . n| / (|d| |n|), A = |n|), so the
mean of what the crossings add is the mean of what the shadow rays add: both settings
converge to the same picture, the crossings with more noise (a small light is seldom
crossed). A point light, which no path can meet, is sampled either way.

**The random numbers** are ``raytracer.sampling.path_random(seed, x, y, i, b, d)`` of the
sample being traced (``Tracer._sample``), bounce b, and dimension d:

===========  ======================================================
d            used for
===========  ======================================================
0            ROULETTE: survival
1            LOBE: which lobe
2            FRESNEL: glass reflects or refracts
3, 4         DIRECTION: a diffuse direction's u1, u2
5 + 2k, 6+2k LIGHTS: light k's point (area lights), along uvec, vvec
===========  ======================================================

A number is drawn only where it is used, but what it is never depends on what else was
drawn, so any port reproduces the picture to rounding, whatever order it traces in.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from raytracer.colors import BLACK, WHITE, Color
from raytracer.intersections import Computations, Intersection, hit, refraction_direction
from raytracer.lights import AreaLight
from raytracer.materials import surface_color
from raytracer.rays import Ray, ray
from raytracer.sampling import path_random_key, sample_key
from raytracer.scatter import DIFFUSE, GLASS, MIRROR, choose_lobe, cosine_direction
from raytracer.sky import sky_color
from raytracer.tuples import Tuple, cross, dot, magnitude, normalize
from raytracer.world import World

ROULETTE = 0
LOBE = 1
FRESNEL = 2
DIRECTION = 3  # and 4
LIGHTS = 5  # light k: LIGHTS + 2 k and LIGHTS + 2 k + 1
REFLECT = "reflect"  # glass, reflecting
REFRACT = "refract"  # glass, refracting


@dataclass(frozen=True, slots=True)
class Scattered:
    """Where a path goes from a hit: ``ray``, the next ray; ``weight``, what the path's
    throughput is multiplied by; ``lobe``: "diffuse", "mirror", "reflect" or "refract"."""

    ray: Ray
    weight: Color
    lobe: str


class PathTracer(Protocol):
    """What the path integrator asks of a tracer: the steps it shares with the book's
    integrator, its own steps, and the sample being traced."""

    _sample: tuple[int, int, int, int]

    def intersect_world(self, w: World, r: Ray) -> list[Intersection]: ...

    def prepare_computations(
        self, hit: Intersection, r: Ray, xs: Sequence[Intersection] | None = None
    ) -> Computations: ...

    def is_shadowed(self, w: World, first: Tuple, second: Tuple | None = None) -> bool: ...

    def schlick(self, comps: Computations) -> float: ...

    def path_color_at(
        self, w: World, r: Ray, depth: int = 5, roulette: int = 0, bounce: int = 0,
        throughput: Color | None = None, light_sampling: bool = True,
    ) -> Color: ...  # fmt: skip

    def scatter(
        self, comps: Computations, lobe_u: float, fresnel_u: float, u1: float, u2: float
    ) -> Scattered: ...

    def direct_light(
        self, w: World, comps: Computations, weight: Color, bounce: int, area: bool = True
    ) -> Color: ...

    def crossed_lights(self, w: World, r: Ray, weight: Color) -> Color: ...


def path_color_at(
    tracer: PathTracer, w: World, r: Ray, depth: int = 5, roulette: int = 0, bounce: int = 0,
    throughput: Color | None = None, light_sampling: bool = True,
) -> Color:  # fmt: skip
    """Chapter 21: the light that ``r`` carries back, times ``throughput``: what it meets
    emits, then it scatters and the path goes on, until bounce ``depth`` (the module
    docstring gives each step).

    w: the world (its lights and sky); r: the ray; depth: the most scatter events of a path
    (at the hit of bounce ``depth`` only emission counts); roulette: Russian roulette from
    this bounce on (0: never); bounce: this ray's (0: a camera ray); throughput: the
    product of the weights so far (None: white, a camera ray's); light_sampling: aim shadow
    rays at the area lights (True) or find them where the paths cross them (False).
    """
    throughput = WHITE if throughput is None else throughput
    xs = tracer.intersect_world(w, r)
    h = hit(xs)
    if h is None:
        return throughput * sky_color(w.sky, r.direction)
    comps = tracer.prepare_computations(h, r, xs)
    emitted = throughput * comps.object.material.emissive
    if bounce >= depth:
        return emitted
    key = sample_key(*tracer._sample)
    if roulette > 0 and bounce >= roulette:
        throughput = russian_roulette(throughput, path_random_key(key, bounce, ROULETTE))
        if _is_black(throughput):
            return emitted
    lobe_u, fresnel_u, u1, u2 = (
        path_random_key(key, bounce, d) for d in (LOBE, FRESNEL, DIRECTION, DIRECTION + 1)
    )
    scattered = tracer.scatter(comps, lobe_u, fresnel_u, u1, u2)
    weight = throughput * scattered.weight
    if _is_black(weight):
        return emitted
    if scattered.lobe == DIFFUSE:
        emitted = emitted + tracer.direct_light(w, comps, weight, bounce, light_sampling)
        if not light_sampling:
            emitted = emitted + tracer.crossed_lights(w, scattered.ray, weight)
    rest = tracer.path_color_at(
        w, scattered.ray, depth, roulette, bounce + 1, weight, light_sampling
    )
    return emitted + rest


def _is_black(c: Color) -> bool:
    return c.red == 0.0 and c.green == 0.0 and c.blue == 0.0


def russian_roulette(throughput: Color, u: float) -> Color:
    """Chapter 21: Russian roulette: a path with ``throughput`` goes on with probability p =
    min(1, its brightest channel), each channel divided by p (not multiplied by 1 / p, which
    overflows for a tiny p); it ends (black) when its number ``u`` (in [0, 1)) is p or more.
    Unbiased: on average the throughput is kept."""
    p = min(1.0, max(throughput.red, throughput.green, throughput.blue))
    if u >= p:
        return BLACK
    return Color(throughput.red / p, throughput.green / p, throughput.blue / p)


def scatter(
    tracer: PathTracer, comps: Computations, lobe_u: float, fresnel_u: float, u1: float,
    u2: float,
) -> Scattered:  # fmt: skip
    """Chapter 21: where a path goes from the hit ``comps`` and its weight, given its
    numbers: ``lobe_u`` chooses the lobe (``raytracer.scatter.choose_lobe``), ``fresnel_u``
    reflects from glass when below ``schlick(comps)``, ``u1`` and ``u2`` place a diffuse
    direction (``cosine_direction``)."""
    m = comps.object.material
    lobe = choose_lobe(m, lobe_u)
    if lobe == GLASS:
        direction = None if fresnel_u < tracer.schlick(comps) else refraction_direction(comps)
        if direction is None:  # reflected, or total internal reflection
            return Scattered(ray(comps.over_point, comps.reflectv), WHITE, REFLECT)
        return Scattered(ray(comps.under_point, direction), WHITE, REFRACT)
    if lobe == MIRROR:
        return Scattered(ray(comps.over_point, comps.reflectv), WHITE, MIRROR)
    albedo = surface_color(m, comps.object, comps.over_point) * m.diffuse
    direction = cosine_direction(comps.normalv, u1, u2)
    return Scattered(ray(comps.over_point, direction), albedo, DIFFUSE)


def direct_light(
    tracer: PathTracer, w: World, comps: Computations, weight: Color, bounce: int,
    area: bool = True,
) -> Color:  # fmt: skip
    """Chapter 21: the light of the world's lights reaching the diffuse hit ``comps``,
    times ``weight`` (the path's throughput after the bounce): one shadow ray per light,
    towards a point light or one point of an area light (the module docstring); ``area``
    False: the point lights only (light sampling off)."""
    key = sample_key(*tracer._sample)
    total = BLACK
    for k, light in enumerate(w.lights):
        if isinstance(light, AreaLight):
            if not area:
                continue
            u = path_random_key(key, bounce, LIGHTS + 2 * k)
            v = path_random_key(key, bounce, LIGHTS + 2 * k + 1)
            along_u, along_v = light.uvec * (u * light.usteps), light.vvec * (v * light.vsteps)
            target = light.corner + along_u + along_v
        else:
            target = light.position
        toward = target - comps.over_point
        if magnitude(toward) == 0.0:
            continue  # the light is on the point: no direction to it
        cosine = dot(normalize(toward), comps.normalv)
        if cosine <= 0.0 or tracer.is_shadowed(w, target, comps.over_point):
            continue
        total = total + weight * light.intensity * cosine
    return total


def crossed_lights(tracer: PathTracer, w: World, r: Ray, weight: Color) -> Color:
    """Chapter 21, light sampling off: the light of the area lights that the ray ``r``
    (leaving a diffuse hit) crosses where they are seen from its origin, times ``weight``
    (the module docstring gives the crossing and its factor)."""
    total = BLACK
    o, d = r.origin, r.direction
    for light in w.lights:
        if not isinstance(light, AreaLight):
            continue
        edge_u, edge_v = light.uvec * light.usteps, light.vvec * light.vsteps
        n = cross(edge_u, edge_v)
        facing = dot(d, n)
        if facing == 0.0:
            continue  # the ray runs along the light's plane
        t = dot(light.corner - o, n) / facing
        if t <= 0.0:
            continue
        crossing = o + d * t
        offset = crossing - light.corner
        area2 = dot(n, n)
        a = dot(cross(offset, edge_v), n) / area2
        b = dot(cross(edge_u, offset), n) / area2
        if not (0.0 <= a <= 1.0 and 0.0 <= b <= 1.0):
            continue
        if tracer.is_shadowed(w, crossing, o):
            continue
        length = magnitude(d)
        factor = math.pi * t * t * length * length * length / abs(facing)
        total = total + weight * light.intensity * factor
    return total
