"""What the numba kernels refuse: anything they cannot compile is a ``PackError`` naming the
object (a shape, pattern, light or transform), never an approximation."""


class PackError(ValueError):
    """Something the numba kernels cannot compile; the message names the object."""
