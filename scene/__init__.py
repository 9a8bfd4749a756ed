"""The book's YAML scene format read into a description every tracer starts from:
``load_scene(path, variant.api, variant=variant.name)`` gives a ``Scene`` (the camera, the
lights, one resolved ``ShapeSpec`` per shape added, each OBJ model's triangles as arrays);
``Variant.world_for(scene)`` makes the variant's own world of it. The format itself, key by
key: ``docs/scene-format.md``.

Values the book's functions take but no surface has are refused: a negative color or light
component, a negative ambient, diffuse or specular, shininess or refractive-index of 0 or
less, reflective or transparency outside 0 to 1, a cylinder's or cone's min above its max, a
torus radius of 0 or less, a transform that cannot be inverted in floating point (a scale of
1e-200, not only of 0). Every mistake is one ``SceneError``: ``file:line: what is wrong,
what was expected``.

Modules: ``reader`` (YAML with lines), ``composer`` (YAML's composer with the ``limits``),
``transforms``, ``colors``, ``materials``, ``textures`` (map patterns),
``images`` (image files), ``kinds`` (the table of leaf shapes), ``shapes`` (a shape's
entry), ``fir_branch``, ``obj_mesh`` and ``obj_scan`` (OBJ models as arrays), ``build``
(the book's shapes from a description), ``loader`` (the top level).
"""

from scene.errors import SceneError
from scene.loader import Scene, load_scene, load_scene_text

__all__ = ["Scene", "SceneError", "load_scene", "load_scene_text"]
