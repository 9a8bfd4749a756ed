"""Materials and the Phong reflection model (chapter 6), with shadows (chapter 8), patterns
(chapter 10), and reflection and refraction properties (chapter 11).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

from raytracer.colors import BLACK, WHITE, Color
from raytracer.lights import PointLight
from raytracer.patterns import Pattern, pattern_at_shape
from raytracer.tuples import Tuple, dot, normalize, reflect

if TYPE_CHECKING:
    from raytracer.shapes.shape import Shape


@dataclass(frozen=True, slots=True)
class Material:
    """How a surface looks.

    color: the surface color (ignored when ``pattern`` is set);
    ambient, diffuse, specular: the Phong model's weights, usually 0 to 1;
    shininess: the size of the specular highlight (higher is smaller and tighter);
    reflective: 0 (matte) to 1 (mirror); transparency: 0 (opaque) to 1;
    refractive_index: 1 for vacuum/air, 1.5 for glass, 1.333 for water;
    pattern: a pattern giving the color at each point, or None.
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


def lighting(
    material: Material,
    object: Shape | None,
    light: PointLight,
    point: Tuple,
    eyev: Tuple,
    normalv: Tuple,
    in_shadow: bool = False,
    ambient: bool = True,
) -> Color:
    """Chapters 6, 8 and 10: the Phong color of one point lit by one light.

    material: the surface's material; object: the shape (for its pattern's object space);
    light: the light; point: the world-space point being lit; eyev: towards the eye;
    normalv: the surface normal; in_shadow: True when the light is blocked (ambient only);
    ambient: False leaves the ambient term out (a world's second and later lights: the
    ambient light is counted once, with the first).
    """
    if material.pattern is not None:
        if object is None:  # the chapter 6 form had no object: treat world space as object space
            surface = material.pattern.local_pattern_at(material.pattern.inverse_transform * point)
        else:
            surface = pattern_at_shape(material.pattern, object, point)
    else:
        surface = material.color
    effective_color = surface * light.intensity
    ambient_part = effective_color * material.ambient if ambient else BLACK
    if in_shadow:
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
    return ambient_part + diffuse + specular
