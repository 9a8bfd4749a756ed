"""What the numba kernels refuse: anything they cannot compile is a ``PackError`` naming the
object (a shape, pattern, light or transform), never an approximation."""

from __future__ import annotations

from scene.kinds import KINDS
from variants.arrays import flatten as F


class PackError(ValueError):
    """Something the numba kernels cannot compile; the message names the object."""


def refusal(error: F.FlattenError) -> PackError:
    """A flattening error in the kernels' words."""
    if isinstance(error, F.UnknownShape):
        if error.changed is not None:
            return PackError(
                f"numba: cannot compile {error.where}, a {type(error.shape).__name__}: it "
                f"changes how a {error.changed.__name__} intersects or computes normals, and "
                "the kernels only know the reference's"
            )
        known = ", ".join(k.name for k in KINDS) + ", group, csg"
        return PackError(
            f"numba: cannot compile {error.where}, a {type(error.shape).__name__}: the "
            f"kernels know {known}"
        )
    return PackError(f"numba: {error}")
