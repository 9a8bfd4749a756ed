"""What the array tracers (``numba``, ``wavefront``) share, below both: neither imports the
other.

- ``flatten``: a scene as they see it, every leaf with its transform composed through its
  groups (chapter 14), an OBJ model's triangles as arrays; ``mesh_kernel`` is its compiled
  pass over a model's triangles;
- ``rows``: the reference's values (transforms, tuples, colours) as table rows;
- ``canvas``: the array-backed canvas they render into (chapter 2), and the ``Tracer`` steps
  that make and fill one.
"""
