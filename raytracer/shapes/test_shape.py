"""The test shape (chapter 9): records the ray it was asked to intersect."""

from __future__ import annotations

from dataclasses import dataclass, field

from raytracer.bounds import BoundingBox
from raytracer.rays import Ray
from raytracer.shapes.shape import Intersection, Shape
from raytracer.tuples import Tuple, point, vector


@dataclass(slots=True, eq=True)
class TestShape(Shape):
    """Chapter 9: a shape for testing the abstract ``Shape``.

    saved_ray: the last object-space ray ``local_intersect`` received (not compared).
    """

    __test__ = False  # not a pytest test class, despite the name

    saved_ray: Ray | None = field(default=None, compare=False)

    def local_intersect(self, local_ray: Ray) -> list[Intersection]:
        """Chapter 9: remember the ray; no intersections."""
        self.saved_ray = local_ray
        return []

    def local_normal_at(self, local_point: Tuple, hit: Intersection | None = None) -> Tuple:
        """Chapter 9: the object-space point as a vector."""
        return vector(local_point.x, local_point.y, local_point.z)

    def local_bounds(self) -> BoundingBox:
        """The bonus chapter 'Bounding boxes and hierarchies': the unit cube's box, from
        (-1, -1, -1) to (1, 1, 1)."""
        return BoundingBox(point(-1, -1, -1), point(1, 1, 1))


def test_shape() -> TestShape:
    """Chapter 9: a new test shape."""
    return TestShape()


test_shape.__test__ = False  # type: ignore[attr-defined]  # not a pytest test function
