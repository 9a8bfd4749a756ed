"""The book's YAML scene description format: a camera, a light and shapes, built through any
variant's API: ``load_scene(path, variant.api, variant=variant.name)``.

The format, as this loader reads it (top level: a list of items, read in order):

- ``- add: camera`` (width, height, field-of-view, from, to, up): exactly one;
  ``- add: light`` (at, intensity): any number, each one shading on its own (ambient once);
  ``- add: area_light`` (corner, uvec, usteps, vvec, vsteps, intensity, and jitter: true
  for random points in the cells; uvec and vvec are the full edges): the soft shadows
  chapter's light, also any number. None of either renders black with a warning.
- ``- add: sphere | plane | cube | cylinder | cone | group | obj | csg`` with ``transform``,
  ``material``, ``shadow`` (false: casts no shadow); ``min``, ``max``, ``closed``
  (cylinders, cones); ``children`` (groups); ``file`` (obj: relative to the scene file);
  ``operation``, ``left``, ``right`` (csg).
- ``- define: NAME`` with ``value:`` a material mapping, a transform list or a shape, and
  ``extend: OTHER`` (materials: OTHER's properties, then these; transforms: OTHER's, then
  these). A name is usable only below its definition.
- ``- add: NAME`` adds a new copy of a defined shape; its own keys replace the definition's,
  except ``transform``, which applies after the definition's.
- A transform list is applied entry by entry: ``[A, B]`` is ``B * A``.
- A material or ``shadow: false`` on a group, OBJ model or CSG applies to every shape inside
  it that does not set its own.
- A material's ``pattern:`` is ``type: stripes | gradient | rings | checkers`` with
  ``colors`` (two), or ``type: map`` (the bonus chapter "Texture mapping") with ``mapping:
  spherical | planar | cylindrical`` and a ``uv_pattern`` (``checkers`` with width, height,
  colors; ``align_check`` with colors main, ul, ur, bl, br; ``image`` with a ``file``, PPM
  or PNG, relative to the scene file), or ``mapping: cube`` with a UV pattern for each of
  ``left front right back up down``; every pattern takes a ``transform``.

Values the book's functions take but no surface has are refused: a negative color or light
component, a negative ambient, diffuse or specular, shininess or refractive-index of 0 or
less, reflective or transparency outside 0 to 1, a cylinder's or cone's min above its max, a
transform that cannot be inverted in floating point (a scale of 1e-200, not only of 0).

Limits (``limits``), checked while the file is read: groups and CSGs nested at most 100 deep
(``RTC_SCENE_MAX_DEPTH``), at most 5,000,000 shapes in the world, every copy a YAML alias or
a defined shape makes and every OBJ triangle counted (``RTC_SCENE_MAX_SHAPES``). A load that
takes more than a second shows a progress bar on stderr when stderr is a terminal.

Every mistake in a scene file is one ``SceneError``: ``file:line: what is wrong, what was
expected``. Modules: ``reader`` (YAML with lines), ``composer`` (YAML's composer with the
limits), ``limits``, ``progress``, ``transforms``, ``materials``, ``textures`` (map patterns),
``images`` (image files), ``shapes``, ``loader`` (the top level).
"""

from scene.errors import SceneError
from scene.loader import Scene, load_scene, load_scene_text

__all__ = ["Scene", "SceneError", "load_scene", "load_scene_text"]
