"""The reused buffers of the ``prealloc`` variant (chapters 5, 7 and 11 without allocation).

Points and vectors are 4-float lists ``[x, y, z, w]``, colours 3-float lists ``[r, g, b]``,
rays 8-float lists ``[ox, oy, oz, ow, dx, dy, dz, dw]``, matrices flat 16-float lists (row by
row). They are made once per render context and overwritten in place; a function that
produces one writes it into a buffer its caller owns (``..._into(..., out)``), the Go
write-up's ``TransformRayPtr`` style.

The intersection list keeps the Go slice's trick: ``count`` says how many entries are live,
and resetting it to zero empties the list while its storage is kept for the next ray.
"""

from __future__ import annotations

from typing import Any

from raytracer.colors import Color
from raytracer.tuples import Tuple
from variants.prealloc.errors import PreallocUnsupported

Vec = list[float]  # a point or a vector [x, y, z, w], a colour [r, g, b], a ray, a matrix


def new_tuple() -> Vec:
    """A point/vector buffer ``[x, y, z, w]`` (naive twin: ``raytracer.tuples.Tuple``)."""
    return [0.0, 0.0, 0.0, 0.0]


def new_color() -> Vec:
    """A colour buffer ``[red, green, blue]`` (naive twin: ``raytracer.colors.Color``)."""
    return [0.0, 0.0, 0.0]


def new_ray() -> Vec:
    """A ray buffer ``[ox, oy, oz, ow, dx, dy, dz, dw]`` (naive twin: ``raytracer.rays.Ray``)."""
    return [0.0] * 8


def color_buffer(c: Color, owner: str) -> Vec:
    """A ``Color`` as ``[r, g, b]``; ``owner`` names where it came from, for the error."""
    if not isinstance(c, Color):
        raise PreallocUnsupported(
            f"prealloc: {owner} must be a color, got {type(c).__name__} (nested patterns are "
            "not supported)"
        )
    return [float(c.red), float(c.green), float(c.blue)]


def tuple_buffer(t: Tuple) -> Vec:
    """A ``Tuple`` as ``[x, y, z, w]``."""
    return [float(t.x), float(t.y), float(t.z), float(t.w)]


class IntersectionBuffer:
    """Chapter 5's intersection list, reused: entry ``i < count`` is the intersection at
    ``ts[i]`` with ``objects[i]`` (a shape record), and ``us[i]``/``vs[i]`` for smooth
    triangles (None otherwise). Naive twin: a new ``list[Intersection]`` per ray.
    """

    __slots__ = ("count", "objects", "ts", "us", "vs")

    def __init__(self) -> None:
        self.count = 0
        self.ts: list[float] = []
        self.objects: list[Any] = []
        self.us: list[float | None] = []
        self.vs: list[float | None] = []


def add_intersection(
    xs: IntersectionBuffer, t: float, obj: Any, u: float | None = None, v: float | None = None
) -> None:
    """Append one entry, reusing the storage of earlier rays (naive twin:
    ``xs.append(Intersection(t, obj, u, v))``)."""
    n = xs.count
    if n < len(xs.ts):
        xs.ts[n] = t
        xs.objects[n] = obj
        xs.us[n] = u
        xs.vs[n] = v
    else:
        xs.ts.append(t)
        xs.objects.append(obj)
        xs.us.append(u)
        xs.vs.append(v)
    xs.count = n + 1


def sort_intersections(xs: IntersectionBuffer, start: int = 0) -> None:
    """Chapter 5's ``intersections(*xs)`` in place: sort entries ``start..count`` by t.

    A stable insertion sort (equal t keep their order, as ``sorted`` does), which moves no
    entry that is already in place and allocates nothing. Naive twin:
    ``raytracer.intersections.intersections``.
    """
    ts, objects, us, vs = xs.ts, xs.objects, xs.us, xs.vs
    for i in range(start + 1, xs.count):
        t = ts[i]
        j = i - 1
        if not ts[j] > t:
            continue
        obj, u, v = objects[i], us[i], vs[i]
        while j >= start and ts[j] > t:
            ts[j + 1] = ts[j]
            objects[j + 1] = objects[j]
            us[j + 1] = us[j]
            vs[j + 1] = vs[j]
            j -= 1
        ts[j + 1] = t
        objects[j + 1] = obj
        us[j + 1] = u
        vs[j + 1] = v


def hit_index(xs: IntersectionBuffer) -> int:
    """Chapter 5's ``hit(xs)``: the index of the lowest non-negative t (the first of equal
    ones), or -1 when there is none. Naive twin: ``raytracer.intersections.hit``."""
    ts = xs.ts
    best = -1
    for i in range(xs.count):
        t = ts[i]
        if t >= 0 and (best < 0 or t < ts[best]):
            best = i
    return best


class ComputationsBuffer:
    """Chapters 7, 8, 11: what shading needs about one hit, overwritten for every hit.

    Naive twin: ``raytracer.intersections.Computations`` (a new frozen value per hit).
    ``object`` is a shape record; ``u``/``v`` come from the hit (smooth triangles).
    """

    __slots__ = (
        "eyev",
        "inside",
        "n1",
        "n2",
        "normalv",
        "object",
        "over_point",
        "point",
        "reflectv",
        "t",
        "u",
        "under_point",
        "v",
    )

    def __init__(self) -> None:
        self.t = 0.0
        self.object: Any = None
        self.u: float | None = None
        self.v: float | None = None
        self.point = new_tuple()
        self.eyev = new_tuple()
        self.normalv = new_tuple()
        self.inside = False
        self.over_point = new_tuple()
        self.under_point = new_tuple()
        self.reflectv = new_tuple()
        self.n1 = 1.0
        self.n2 = 1.0


class DepthScratch:
    """The scratch of one recursion level (one value of ``remaining``, chapter 11): its
    intersections, its hit's computations, the ray it spawns, its three colours, and one
    light's share of the surface colour (a world's second and later lights)."""

    __slots__ = ("comps", "lit", "ray", "reflected", "refracted", "surface", "xs")

    def __init__(self) -> None:
        self.xs = IntersectionBuffer()
        self.comps = ComputationsBuffer()
        self.ray = new_ray()
        self.surface = new_color()
        self.reflected = new_color()
        self.refracted = new_color()
        self.lit = new_color()


class ShapeStack:
    """Chapter 11's ``containers`` list, reused: ``items[:count]`` are the shape records
    the ray is inside of, in the order it entered them."""

    __slots__ = ("count", "items")

    def __init__(self) -> None:
        self.count = 0
        self.items: list[Any] = []

    def toggle(self, obj: Any) -> None:
        """Remove ``obj`` (by identity) if present, else push it (naive twin: the
        ``del containers[index]`` / ``containers.append`` of ``_refractive_indices``)."""
        items = self.items
        n = self.count
        for k in range(n):
            if items[k] is obj:
                for m in range(k, n - 1):
                    items[m] = items[m + 1]
                self.count = n - 1
                return
        if n < len(items):
            items[n] = obj
        else:
            items.append(obj)
        self.count = n + 1
