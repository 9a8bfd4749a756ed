"""Shading without allocation (chapters 6, 7, 8, 10 and 11, and the soft shadows bonus
chapter): the world's intersections, the precomputed state of a hit, Phong lighting,
shadows (the fraction of each light that arrives), reflection and refraction, each writing
into a buffer its caller owns.

Each function names its naive twin in ``raytracer``; the arithmetic is the twin's, in the
same order (``w`` components included, a black colour still added as zeros), so the floats
are the same. The recursion of chapter 11 uses the scratch of ``ctx.level(remaining)``:
each level has its own intersections, computations, spawned ray and colours.

Area lights follow ``raytracer.tracer``'s contract: ``intensity_at`` and ``lighting_into``
each take the points of the light's cells from ``light_points``, which for a jittered light
of a render computes them once per sample (``ctx.sample``, set by the pixel loop; reflected
and refracted rays of the sample reuse them), for a light with fixed points returns the
ones its record computed, and otherwise takes the next values of the light's sequence.
"""

from __future__ import annotations

import math

from raytracer.sampling import light_jitters
from variants.prealloc.buffers import (
    ComputationsBuffer,
    IntersectionBuffer,
    Vec,
    hit_index,
    sort_intersections,
)
from variants.prealloc.context import TraceContext
from variants.prealloc.geometry import position_into, transform_point_into
from variants.prealloc.patterns import PatternRecord
from variants.prealloc.records import LightRecord, MaterialRecord
from variants.prealloc.shapes import (
    ShapeRecord,
    intersect_into,
    normal_at_into,
    world_to_object_into,
)


def _black(out: Vec) -> None:
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0


def intersect_world_into(ctx: TraceContext, ray: Vec, xs: IntersectionBuffer) -> None:
    """Chapter 7: ``xs`` reset to zero length, then every object's intersections, sorted
    by t (naive twin: ``raytracer.world.intersect_world``, a new list per ray)."""
    xs.count = 0
    for rec in ctx.objects:
        intersect_into(rec, ray, xs)
    sort_intersections(xs)


def pattern_at_shape_into(
    ctx: TraceContext, pattern: PatternRecord, obj: ShapeRecord | None, point: Vec, out: Vec
) -> None:
    """Chapters 10, 14: the pattern's colour on ``obj`` at a world point (naive twin:
    ``raytracer.patterns.pattern_at_shape``; with no object, chapter 6's form of
    ``lighting`` treats world space as object space)."""
    local = ctx.local_point
    if obj is not None:
        world_to_object_into(obj, point, local)
    else:
        local[0], local[1], local[2], local[3] = point[0], point[1], point[2], point[3]
    transform_point_into(pattern.inverse, local, local)
    pattern.pattern_at_into(local, out)


def light_points(ctx: TraceContext, light: LightRecord) -> list[Vec]:
    """Soft shadows: the points of an area light's cells, in cell order, for one use by
    ``intensity_at`` or ``lighting_into`` (naive twin: ``raytracer.lights.point_on_light``
    for every cell, with ``Tracer.light_for_sample``'s jitter when the light is sampled).
    A sampled light's points are this sample's (computed when the sample changes); a fixed
    light's are its record's; any other takes the next ``2 * samples`` sequence values."""
    if light.fixed:
        return light.points
    if light.sampled:
        sample = ctx.sample
        if light.points_for is not sample:
            seed, x, y, i = sample
            index = light.index if light.index is not None else 0
            light.fill_points(light_jitters(seed, x, y, i, index, light.usteps, light.vsteps))
            light.points_for = sample
        return light.points
    assert light.jitter_by is not None
    light.fill_points(light.jitter_by)
    return light.points


def lighting_into(
    ctx: TraceContext,
    m: MaterialRecord,
    obj: ShapeRecord | None,
    light: LightRecord,
    point: Vec,
    eyev: Vec,
    normalv: Vec,
    intensity: float,
    out: Vec,
    ambient: bool = True,
) -> None:
    """Chapters 6, 8, 10 and soft shadows: the Phong colour of one point, written into
    ``out`` (naive twin: ``raytracer.materials.lighting``). intensity: the fraction of the
    light that arrives (0.0: in shadow, 1.0: the book's unshadowed point); ambient: False
    for a world's later lights."""
    if m.pattern is not None:
        surface = ctx.surface
        pattern_at_shape_into(ctx, m.pattern, obj, point, surface)
    else:
        surface = m.color
    ir, ig, ib = light.intensity
    er, eg, eb = surface[0] * ir, surface[1] * ig, surface[2] * ib  # effective_color
    k = m.ambient
    ar, ag, ab = (er * k, eg * k, eb * k) if ambient else (0.0, 0.0, 0.0)
    if light.area:
        effective, ambient_part = (er, eg, eb), (ar, ag, ab)
        _area_lighting_into(ctx, m, light, effective, ambient_part, point, eyev, normalv,
                            intensity, out)  # fmt: skip
        return
    if intensity == 0.0:
        out[0], out[1], out[2] = ar, ag, ab
        return
    px, py, pz, pw = point
    lx, ly, lz, lw = light.position
    lx, ly, lz, lw = lx - px, ly - py, lz - pz, lw - pw
    length = math.sqrt(lx * lx + ly * ly + lz * lz + lw * lw)
    lx, ly, lz, lw = lx / length, ly / length, lz / length, lw / length  # lightv
    nx, ny, nz, nw = normalv
    light_dot_normal = lx * nx + ly * ny + lz * nz + lw * nw
    if light_dot_normal < 0:
        out[0], out[1], out[2] = ar, ag, ab  # the light is on the other side
        return
    diffuse = m.diffuse
    dr = er * diffuse * light_dot_normal
    dg = eg * diffuse * light_dot_normal
    db = eb * diffuse * light_dot_normal
    # reflectv = reflect(-lightv, normalv)
    vx, vy, vz, vw = -lx, -ly, -lz, -lw
    d = vx * nx + vy * ny + vz * nz + vw * nw
    rx, ry, rz, rw = vx - nx * 2 * d, vy - ny * 2 * d, vz - nz * 2 * d, vw - nw * 2 * d
    ex, ey, ez, ew = eyev
    reflect_dot_eye = rx * ex + ry * ey + rz * ez + rw * ew
    if reflect_dot_eye <= 0:
        sr = sg = sb = 0.0  # black: the reflection points away from the eye
    else:
        factor = reflect_dot_eye**m.shininess
        specular = m.specular
        sr, sg, sb = ir * specular * factor, ig * specular * factor, ib * specular * factor
    if intensity != 1.0:  # part of the light arrives
        dr, dg, db = dr * intensity, dg * intensity, db * intensity
        sr, sg, sb = sr * intensity, sg * intensity, sb * intensity
    out[0] = ar + dr + sr
    out[1] = ag + dg + sg
    out[2] = ab + db + sb


def _area_lighting_into(
    ctx: TraceContext,
    m: MaterialRecord,
    light: LightRecord,
    effective: tuple[float, float, float],
    ambient_part: tuple[float, float, float],
    point: Vec,
    eyev: Vec,
    normalv: Vec,
    intensity: float,
    out: Vec,
) -> None:
    """Soft shadows: the ambient term plus an area light's diffuse and specular terms, each
    summed over its cells from zero (each cell towards its own point) and times
    ``intensity / samples``, written into ``out`` (naive twin:
    ``raytracer.materials._area_lighting``)."""
    er, eg, eb = effective
    ir, ig, ib = light.intensity
    diffuse, specular, shininess = m.diffuse, m.specular, m.shininess
    px, py, pz, pw = point
    nx, ny, nz, nw = normalv
    ex, ey, ez, ew = eyev
    dr = dg = db = 0.0  # the diffuse sum
    sr = sg = sb = 0.0  # the specular sum
    for cell in light_points(ctx, light):
        lx, ly, lz, lw = cell[0] - px, cell[1] - py, cell[2] - pz, cell[3] - pw
        length = math.sqrt(lx * lx + ly * ly + lz * lz + lw * lw)
        lx, ly, lz, lw = lx / length, ly / length, lz / length, lw / length  # lightv
        light_dot_normal = lx * nx + ly * ny + lz * nz + lw * nw
        if light_dot_normal < 0:
            continue  # this cell is on the other side
        dr = dr + er * diffuse * light_dot_normal
        dg = dg + eg * diffuse * light_dot_normal
        db = db + eb * diffuse * light_dot_normal
        vx, vy, vz, vw = -lx, -ly, -lz, -lw
        d = vx * nx + vy * ny + vz * nz + vw * nw
        rx, ry, rz, rw = vx - nx * 2 * d, vy - ny * 2 * d, vz - nz * 2 * d, vw - nw * 2 * d
        reflect_dot_eye = rx * ex + ry * ey + rz * ez + rw * ew
        if reflect_dot_eye > 0:
            factor = reflect_dot_eye**shininess
            sr = sr + ir * specular * factor
            sg = sg + ig * specular * factor
            sb = sb + ib * specular * factor
    weight = intensity / light.samples
    ar, ag, ab = ambient_part
    out[0] = ar + dr * weight + sr * weight
    out[1] = ag + dg * weight + sg * weight
    out[2] = ab + db * weight + sb * weight


def is_shadowed(ctx: TraceContext, light_position: Vec, point: Vec) -> bool:
    """Chapter 8: True when a shadow-casting object lies between ``point`` and the light
    at ``light_position`` (naive twin: ``Tracer.is_shadowed``; here the shadow ray and its
    intersection list are the context's, reused)."""
    px, py, pz, pw = point
    lx, ly, lz, lw = light_position
    vx, vy, vz, vw = lx - px, ly - py, lz - pz, lw - pw
    distance = math.sqrt(vx * vx + vy * vy + vz * vz + vw * vw)
    ray = ctx.shadow_ray
    ray[0], ray[1], ray[2], ray[3] = px, py, pz, pw
    ray[4], ray[5], ray[6], ray[7] = vx / distance, vy / distance, vz / distance, vw / distance
    xs = ctx.shadow_xs
    intersect_world_into(ctx, ray, xs)
    ts, objects = xs.ts, xs.objects
    best = -1  # hit() of the shadow-casting intersections
    for i in range(xs.count):
        t = ts[i]
        if objects[i].casts_shadow and t >= 0 and (best < 0 or t < ts[best]):
            best = i
    return best >= 0 and ts[best] < distance


def intensity_at(ctx: TraceContext, light: LightRecord, point: Vec) -> float:
    """Soft shadows: the fraction of ``light`` that reaches ``point``: 1.0 or 0.0 for a
    point light, the fraction of unshadowed cells for an area light (naive twin:
    ``Tracer.intensity_at``)."""
    if not light.area:
        return 0.0 if is_shadowed(ctx, light.position, point) else 1.0
    total = 0.0
    for cell in light_points(ctx, light):
        if not is_shadowed(ctx, cell, point):
            total += 1.0
    return total / light.samples


def refractive_indices_into(
    ctx: TraceContext, xs: IntersectionBuffer, hit_in_xs: int, comps: ComputationsBuffer
) -> None:
    """Chapter 11: ``comps.n1``/``n2`` from the objects the ray is inside of at the hit
    (naive twin: ``raytracer.intersections._refractive_indices``). ``hit_in_xs``: the
    hit's index in ``xs`` (-1: not there; then an entry with its t and object matches)."""
    hit_t, hit_obj = comps.t, comps.object
    containers = ctx.containers
    containers.count = 0
    items = containers.items
    n1 = n2 = 1.0
    ts, objects = xs.ts, xs.objects
    for i in range(xs.count):
        obj = objects[i]
        is_hit = i == hit_in_xs or (ts[i] == hit_t and obj is hit_obj)
        if is_hit:
            count = containers.count
            n1 = items[count - 1].material.refractive_index if count else 1.0
        containers.toggle(obj)
        if is_hit:
            count = containers.count
            n2 = items[count - 1].material.refractive_index if count else 1.0
            break
    comps.n1 = n1
    comps.n2 = n2


def prepare_computations_into(
    ctx: TraceContext,
    hits: IntersectionBuffer,
    h: int,
    ray: Vec,
    xs: IntersectionBuffer,
    hit_in_xs: int,
    comps: ComputationsBuffer,
) -> None:
    """Chapters 7, 8, 11: the state shading needs for entry ``h`` of ``hits``, written into
    ``comps`` (naive twin: ``raytracer.intersections.prepare_computations``).

    xs: all intersections along the ray (for n1/n2); hit_in_xs: the hit's index in xs, or
    -1 if it is not one of them (when ``hits`` is not ``xs``).
    """
    t = hits.ts[h]
    rec = hits.objects[h]
    comps.t = t
    comps.object = rec
    comps.u = hits.us[h]
    comps.v = hits.vs[h]
    point = comps.point
    position_into(ray, t, point)
    dx, dy, dz, dw = ray[4], ray[5], ray[6], ray[7]
    ex, ey, ez, ew = -dx, -dy, -dz, -dw
    eyev = comps.eyev
    eyev[0], eyev[1], eyev[2], eyev[3] = ex, ey, ez, ew
    normalv = comps.normalv
    normal_at_into(rec, point, comps.u, comps.v, normalv)
    nx, ny, nz, nw = normalv
    inside = nx * ex + ny * ey + nz * ez + nw * ew < 0
    if inside:
        nx, ny, nz, nw = -nx, -ny, -nz, -nw
        normalv[0], normalv[1], normalv[2], normalv[3] = nx, ny, nz, nw
    comps.inside = inside
    eps = ctx.eps
    ox, oy, oz, ow = nx * eps, ny * eps, nz * eps, nw * eps  # offset
    px, py, pz, pw = point
    over, under = comps.over_point, comps.under_point
    over[0], over[1], over[2], over[3] = px + ox, py + oy, pz + oz, pw + ow
    under[0], under[1], under[2], under[3] = px - ox, py - oy, pz - oz, pw - ow
    # reflectv = reflect(ray.direction, normalv)
    d = dx * nx + dy * ny + dz * nz + dw * nw
    r = comps.reflectv
    r[0], r[1], r[2], r[3] = dx - nx * 2 * d, dy - ny * 2 * d, dz - nz * 2 * d, dw - nw * 2 * d
    refractive_indices_into(ctx, xs, hit_in_xs, comps)


def schlick(comps: ComputationsBuffer) -> float:
    """Chapter 11: Schlick's reflectance at the hit (naive twin:
    ``raytracer.intersections.schlick``)."""
    e, n = comps.eyev, comps.normalv
    cos = e[0] * n[0] + e[1] * n[1] + e[2] * n[2] + e[3] * n[3]
    n1, n2 = comps.n1, comps.n2
    if n1 > n2:
        ratio = n1 / n2
        sin2_t = ratio * ratio * (1.0 - cos * cos)
        if sin2_t > 1.0:
            return 1.0  # total internal reflection
        cos = math.sqrt(1.0 - sin2_t)
    r0 = ((n1 - n2) / (n1 + n2)) ** 2
    return r0 + (1 - r0) * (1 - cos) ** 5


def shade_hit_into(ctx: TraceContext, comps: ComputationsBuffer, remaining: int, out: Vec) -> None:
    """Chapters 7, 8, 11: the colour at a hit, written into ``out`` (naive twin:
    ``raytracer.world.shade_hit``)."""
    rec = comps.object
    m = rec.material
    level = ctx.level(remaining)
    surface, reflected, refracted = level.surface, level.reflected, level.refracted
    point, eyev, normalv = comps.over_point, comps.eyev, comps.normalv
    lights = ctx.lights
    if not lights:
        _black(surface)
    for k, light in enumerate(lights):  # the ambient term once, with the first light
        intensity = intensity_at(ctx, light, point)
        if k == 0:
            lighting_into(ctx, m, rec, light, point, eyev, normalv, intensity, surface)
            continue
        lit = level.lit
        lighting_into(ctx, m, rec, light, point, eyev, normalv, intensity, lit, False)
        surface[0], surface[1], surface[2] = (
            surface[0] + lit[0], surface[1] + lit[1], surface[2] + lit[2]
        )  # fmt: skip
    reflected_color_into(ctx, comps, remaining, reflected)
    refracted_color_into(ctx, comps, remaining, refracted)
    if m.reflective > 0 and m.transparency > 0:
        reflectance = schlick(comps)
        rest = 1 - reflectance
        out[0] = surface[0] + reflected[0] * reflectance + refracted[0] * rest
        out[1] = surface[1] + reflected[1] * reflectance + refracted[1] * rest
        out[2] = surface[2] + reflected[2] * reflectance + refracted[2] * rest
    else:
        out[0] = surface[0] + reflected[0] + refracted[0]
        out[1] = surface[1] + reflected[1] + refracted[1]
        out[2] = surface[2] + reflected[2] + refracted[2]


def color_at_into(ctx: TraceContext, ray: Vec, remaining: int, out: Vec) -> None:
    """Chapter 7: the colour seen along ``ray`` (black for no hit), written into ``out``
    (naive twin: ``raytracer.world.color_at``)."""
    level = ctx.level(remaining)
    xs = level.xs
    intersect_world_into(ctx, ray, xs)
    h = hit_index(xs)
    if h < 0:
        _black(out)
        return
    comps = level.comps
    prepare_computations_into(ctx, xs, h, ray, xs, h, comps)
    shade_hit_into(ctx, comps, remaining, out)


def reflected_color_into(
    ctx: TraceContext, comps: ComputationsBuffer, remaining: int, out: Vec
) -> None:
    """Chapter 11: the reflected colour, written into ``out`` (naive twin:
    ``raytracer.world.reflected_color``); the reflected ray is this level's buffer."""
    reflective = comps.object.material.reflective
    if reflective == 0 or remaining <= 0:
        _black(out)
        return
    ray = ctx.level(remaining).ray
    p, r = comps.over_point, comps.reflectv
    ray[0], ray[1], ray[2], ray[3] = p[0], p[1], p[2], p[3]
    ray[4], ray[5], ray[6], ray[7] = r[0], r[1], r[2], r[3]
    color_at_into(ctx, ray, remaining - 1, out)
    out[0] = out[0] * reflective
    out[1] = out[1] * reflective
    out[2] = out[2] * reflective


def refracted_color_into(
    ctx: TraceContext, comps: ComputationsBuffer, remaining: int, out: Vec
) -> None:
    """Chapter 11: the refracted colour (Snell's law), written into ``out`` (naive twin:
    ``raytracer.world.refracted_color``); the refracted ray is this level's buffer."""
    transparency = comps.object.material.transparency
    if transparency == 0 or remaining <= 0:
        _black(out)
        return
    n_ratio = comps.n1 / comps.n2
    e, n = comps.eyev, comps.normalv
    cos_i = e[0] * n[0] + e[1] * n[1] + e[2] * n[2] + e[3] * n[3]
    sin2_t = n_ratio * n_ratio * (1 - cos_i * cos_i)
    if sin2_t > 1:
        _black(out)  # total internal reflection
        return
    cos_t = math.sqrt(1.0 - sin2_t)
    k = n_ratio * cos_i - cos_t
    ray = ctx.level(remaining).ray
    p = comps.under_point
    ray[0], ray[1], ray[2], ray[3] = p[0], p[1], p[2], p[3]
    ray[4] = n[0] * k - e[0] * n_ratio
    ray[5] = n[1] * k - e[1] * n_ratio
    ray[6] = n[2] * k - e[2] * n_ratio
    ray[7] = n[3] * k - e[3] * n_ratio
    color_at_into(ctx, ray, remaining - 1, out)
    out[0] = out[0] * transparency
    out[1] = out[1] * transparency
    out[2] = out[2] * transparency
