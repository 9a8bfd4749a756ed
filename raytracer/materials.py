"""Materials and the Phong reflection model (chapter 6), with shadows (chapter 8), patterns
(chapter 10), reflection and refraction properties (chapter 11), and area lights (the bonus
chapter "Rendering soft shadows", 18 here).

``lighting``'s seventh argument is the book's ``in_shadow`` (True: the light is blocked)
or, since the soft shadows chapter, ``intensity``: the fraction of the light that reaches
the point (``Tracer.intensity_at``). The arithmetic, which every variant reproduces:

- effective = surface color * light.intensity; ambient = effective * material.ambient
  (black when ``ambient`` is False);
- a point light: intensity 0 gives ``ambient``; otherwise, with lightv towards the light,
  ``diffuse = effective * diffuse * (lightv . normalv)`` (black, and no specular, when
  that dot product is negative) and ``specular = light.intensity * specular * (reflectv .
  eyev) ** shininess`` (black when that dot product is not positive); each multiplied by
  the intensity unless it is 1; the result ``ambient + diffuse + specular``;
- an area light: the same diffuse and specular for every cell (v outer, u inner; lightv
  towards ``point_on_light(light, u, v)``), summed separately from black, and the result
  ``ambient + diffuse_sum * (intensity / samples) + specular_sum * (intensity /
  samples)``. Every cell is walked whatever the intensity, so ``lighting`` takes exactly
  ``2 * samples`` values from the light's ``jitter_by``. A 1x1 light at a point shades
  exactly as a point light there.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

from raytracer.colors import BLACK, WHITE, Color
from raytracer.lights import AreaLight, Light, point_on_light
from raytracer.patterns import Pattern, pattern_at_shape
from raytracer.space import Placed
from raytracer.tuples import Tuple, dot, normalize, reflect


@dataclass(frozen=True, slots=True)
class Material:
    """How a surface looks.

    color: the surface color (ignored when ``pattern`` is set);
    ambient, diffuse, specular: the Phong model's weights, usually 0 to 1;
    shininess: the size of the specular highlight (higher is smaller and tighter);
    reflective: 0 (matte) to 1 (mirror); transparency: 0 (opaque) to 1;
    refractive_index: 1 for vacuum/air, 1.5 for glass, 1.333 for water;
    pattern: a pattern giving the color at each point, or None;
    emissive: the light the surface gives off (chapter 21 here, beyond the book: the path
    integrator adds it; the book's Whitted integrator ignores it), black by default.
    """

    color: Color = WHITE
    ambient: float = 0.1
    diffuse: float = 0.9
    specular: float = 0.9
    shininess: float = 200.0
    reflective: float = 0.0
    transparency: float = 0.0
    refractive_index: float = 1.0
    pattern: Pattern | None = None
    emissive: Color = BLACK


def material(**overrides: Any) -> Material:
    """Chapter 6: the default material, with any properties given replaced.

    overrides: property values by name, e.g. ``material(diffuse=0.7, specular=0.2)``.
    """
    known = [f.name for f in fields(Material)]
    unknown = sorted(set(overrides) - set(known))
    if unknown:
        raise ValueError(
            f"material: unknown propert{'y' if len(unknown) == 1 else 'ies'} "
            f"{', '.join(unknown)}; a material has {', '.join(known)}"
        )
    return Material(**overrides)


def light_fraction(in_shadow: bool | float) -> float:
    """``lighting``'s seventh argument as the fraction of the light that arrives: the
    book's ``in_shadow`` (True: 0.0, False: 1.0) or a number from 0 to 1 (the soft shadows
    chapter's ``intensity``)."""
    if isinstance(in_shadow, bool):
        return 0.0 if in_shadow else 1.0
    if isinstance(in_shadow, int | float) and 0 <= in_shadow <= 1:
        return float(in_shadow)
    raise ValueError(
        "lighting: in_shadow must be true or false, or the light's intensity a number from "
        f"0 to 1, got {in_shadow!r}"
    )


def surface_color(material: Material, object: Placed | None, point: Tuple) -> Color:
    """Chapters 6 and 10: the colour of the surface at the world-space ``point``: its
    pattern's there (in ``object``'s pattern space; with no object, world space is taken as
    object space, the chapter 6 form), else the material's ``color``."""
    if material.pattern is None:
        return material.color
    if object is None:
        return material.pattern.local_pattern_at(material.pattern.inverse_transform * point)
    return pattern_at_shape(material.pattern, object, point)


def lighting(
    material: Material,
    object: Placed | None,
    light: Light,
    point: Tuple,
    eyev: Tuple,
    normalv: Tuple,
    in_shadow: bool | float = False,
    ambient: bool = True,
) -> Color:
    """Chapters 6, 8 and 10, and soft shadows: the Phong color of one point lit by one
    light (the module docstring gives the arithmetic).

    material: the surface's material; object: the shape (for its pattern's object space);
    light: a point light or an area light; point: the world-space point being lit; eyev:
    towards the eye; normalv: the surface normal; in_shadow: True when the light is blocked
    (ambient only), False when not, or the fraction of the light that arrives (0 to 1,
    ``intensity_at``); ambient: False leaves the ambient term out (a world's second and
    later lights: the ambient light is counted once, with the first).
    """
    intensity = light_fraction(in_shadow)
    effective_color = surface_color(material, object, point) * light.intensity
    ambient_part = effective_color * material.ambient if ambient else BLACK
    if isinstance(light, AreaLight):
        return _area_lighting(
            material, light, effective_color, ambient_part, point, eyev, normalv, intensity
        )
    if intensity == 0.0:
        return ambient_part
    lightv = normalize(light.position - point)
    light_dot_normal = dot(lightv, normalv)
    if light_dot_normal < 0:
        return ambient_part  # the light is on the other side of the surface
    diffuse = effective_color * material.diffuse * light_dot_normal
    reflectv = reflect(-lightv, normalv)
    reflect_dot_eye = dot(reflectv, eyev)
    if reflect_dot_eye <= 0:
        specular = BLACK  # the reflection points away from the eye
    else:
        factor = reflect_dot_eye**material.shininess
        specular = light.intensity * material.specular * factor
    if intensity != 1.0:  # part of the light arrives (1.0: the book's unshadowed point)
        diffuse = diffuse * intensity
        specular = specular * intensity
    return ambient_part + diffuse + specular


def _area_lighting(
    material: Material,
    light: AreaLight,
    effective_color: Color,
    ambient_part: Color,
    point: Tuple,
    eyev: Tuple,
    normalv: Tuple,
    intensity: float,
) -> Color:
    """Soft shadows: ``lighting`` with an area light: diffuse and specular averaged over
    its cells (each towards its own ``point_on_light``), times ``intensity``."""
    diffuse_sum = BLACK
    specular_sum = BLACK
    for v in range(light.vsteps):
        for u in range(light.usteps):
            lightv = normalize(point_on_light(light, u, v) - point)
            light_dot_normal = dot(lightv, normalv)
            if light_dot_normal < 0:
                continue  # this cell is on the other side of the surface
            diffuse_sum = diffuse_sum + effective_color * material.diffuse * light_dot_normal
            reflect_dot_eye = dot(reflect(-lightv, normalv), eyev)
            if reflect_dot_eye > 0:
                factor = reflect_dot_eye**material.shininess
                specular_sum = specular_sum + light.intensity * material.specular * factor
    weight = intensity / light.samples
    return ambient_part + diffuse_sum * weight + specular_sum * weight
