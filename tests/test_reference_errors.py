"""Bad input to the reference tracer fails with a clear ValueError naming what is wrong."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import pytest

from groundwork.images import read_png, write_image
from raytracer import (
    NotInvertibleError,
    canvas,
    color,
    inverse,
    matrix,
    pixel_at,
    plane,
    scaling,
    set_pattern_transform,
    set_transform,
    sphere,
    stripe_pattern,
    translation,
    write_pixel,
)
from variants.registry import load_variant


def test_singular_set_transform_names_the_shape() -> None:
    s = sphere()
    with pytest.raises(ValueError, match=r"set_transform\(Sphere\).*not invertible") as error:
        set_transform(s, scaling(0, 1, 1))
    assert isinstance(error.value, NotInvertibleError)
    assert s.transform == matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def test_singular_set_transform_on_a_plane() -> None:
    with pytest.raises(ValueError, match=r"set_transform\(Plane\)"):
        set_transform(plane(), scaling(1, 0, 1))


def test_invertible_set_transform_is_kept() -> None:
    s = sphere()
    set_transform(s, translation(1, 2, 3))
    assert s.transform == translation(1, 2, 3)


def test_singular_pattern_transform() -> None:
    p = stripe_pattern(color(1, 1, 1), color(0, 0, 0))
    with pytest.raises(ValueError, match=r"set_pattern_transform\(StripePattern\)"):
        set_pattern_transform(p, scaling(1, 1, 0))


@pytest.mark.parametrize("variant", ["naive", "cached", "robust"])
def test_a_singular_transform_assigned_directly_is_named_when_used(variant: str) -> None:
    """The book's ``s.transform ← m`` does not check; the first use names the shape."""
    api = load_variant_api(variant)
    s = api["sphere"]()
    s.transform = api["scaling"](1, 0, 1)
    r = api["ray"](api["point"](0, 0, -5), api["vector"](0, 0, 1))
    with pytest.raises(NotInvertibleError, match=r"^Sphere: its transform is not invertible"):
        api["intersect"](s, r)
    with pytest.raises(NotInvertibleError, match=r"^Sphere: its transform is not invertible"):
        api["normal_at"](s, api["point"](0, 0, -1))


@pytest.mark.parametrize("variant", ["naive", "cached"])
def test_a_camera_looking_along_its_up_vector_is_named(variant: str) -> None:
    api = load_variant_api(variant)
    view = api["view_transform"](api["point"](0, 5, 0), api["point"](0, 0, 0),
                                 api["vector"](0, 1, 0))  # fmt: skip
    c = dataclasses.replace(api["camera"](4, 3, 1.0), transform=view)
    with pytest.raises(NotInvertibleError, match=r"^camera: .*'up' across the line"):
        api["ray_for_pixel"](c, 1, 1)


def load_variant_api(name: str) -> Mapping[str, Any]:
    return load_variant(name).api


def test_inverse_of_a_singular_matrix_says_determinant_0() -> None:
    singular = matrix([[-4, 2, -2, -3], [9, 6, 2, 6], [0, -5, 1, -5], [0, 0, 0, 0]])
    with pytest.raises(NotInvertibleError, match="determinant 0"):
        inverse(singular)


def test_matrix_must_be_square() -> None:
    with pytest.raises(ValueError, match="square"):
        matrix([[1, 2, 3], [4, 5, 6]])


@pytest.mark.parametrize("size", [(0, 10), (10, -1), (16385, 1), (2.5, 3)])
def test_absurd_canvas_size_names_the_size(size: tuple[float, float]) -> None:
    width, height = size
    with pytest.raises(ValueError, match=rf"canvas\({width!r}, {height!r}\)"):
        canvas(width, height)  # type: ignore[arg-type]


def test_largest_canvas_side_is_allowed() -> None:
    assert canvas(16384, 1).width == 16384


@pytest.mark.parametrize("xy", [(10, 0), (0, 20), (-1, 0), (3, -1)])
def test_pixel_outside_the_canvas(xy: tuple[int, int]) -> None:
    c = canvas(10, 20)
    x, y = xy
    with pytest.raises(ValueError, match=rf"pixel \({x}, {y}\) is outside the 10x20 canvas"):
        write_pixel(c, x, y, color(1, 0, 0))
    with pytest.raises(ValueError, match=rf"pixel_at: pixel \({x}, {y}\).*10x20"):
        pixel_at(c, x, y)


def test_pixel_on_the_edge_is_inside() -> None:
    c = canvas(10, 20)
    write_pixel(c, 9, 19, color(1, 0, 0))
    assert pixel_at(c, 9, 19) == color(1, 0, 0)


@pytest.mark.parametrize("name", ["out.jpg", "out", "out.png.txt"])
def test_bad_image_extension(tmp_path, name: str) -> None:
    target = tmp_path / name
    with pytest.raises(ValueError, match="unknown image extension"):
        write_image(canvas(2, 2), target)
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []  # no temporary file left behind


def test_png_and_ppm_are_written(tmp_path) -> None:
    c = canvas(3, 2)
    write_pixel(c, 0, 0, color(1, 0, 0))
    write_pixel(c, 2, 1, color(0, 0.5, 1.5))
    write_image(c, tmp_path / "out.png")
    assert read_png(tmp_path / "out.png") == (3, 2, bytes([255, 0, 0] + [0] * 12 + [0, 128, 255]))
    write_image(c, tmp_path / "out.PPM")
    assert (tmp_path / "out.PPM").read_text().startswith("P3\n3 2\n255\n255 0 0 ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.PPM", "out.png"]


def test_png_uses_the_canvas_own_rgb8(tmp_path) -> None:
    class Flat:
        width, height = 2, 1

        def to_rgb8(self) -> bytes:
            return bytes([1, 2, 3, 4, 5, 6])

    write_image(Flat(), tmp_path / "flat.png")
    assert read_png(tmp_path / "flat.png") == (2, 1, bytes([1, 2, 3, 4, 5, 6]))
