"""Transformation matrices (chapter 4) and the view transformation (chapter 7)."""

from __future__ import annotations

import math

from raytracer.matrices import Matrix, matrix
from raytracer.tuples import Tuple, cross, normalize


def translation(x: float, y: float, z: float) -> Matrix:
    """Chapter 4: move points by (x, y, z); vectors are unaffected."""
    return matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


def scaling(x: float, y: float, z: float) -> Matrix:
    """Chapter 4: scale by x, y and z along the axes (a negative factor reflects)."""
    return matrix([[x, 0, 0, 0], [0, y, 0, 0], [0, 0, z, 0], [0, 0, 0, 1]])


def rotation_x(radians: float) -> Matrix:
    """Chapter 4: rotate around the x axis (left-handed: clockwise looking down +x)."""
    c, s = math.cos(radians), math.sin(radians)
    return matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rotation_y(radians: float) -> Matrix:
    """Chapter 4: rotate around the y axis."""
    c, s = math.cos(radians), math.sin(radians)
    return matrix([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def rotation_z(radians: float) -> Matrix:
    """Chapter 4: rotate around the z axis."""
    c, s = math.cos(radians), math.sin(radians)
    return matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def shearing(xy: float, xz: float, yx: float, yz: float, zx: float, zy: float) -> Matrix:
    """Chapter 4: shear; ``xy`` moves x in proportion to y, and so on."""
    return matrix([[1, xy, xz, 0], [yx, 1, yz, 0], [zx, zy, 1, 0], [0, 0, 0, 1]])


def view_transform(from_: Tuple, to: Tuple, up: Tuple) -> Matrix:
    """Chapter 7: the transformation that puts the eye at ``from_`` looking at ``to``.

    from_: the eye's position (the book's ``from``); to: the point looked at;
    up: roughly which way is up (need not be exactly perpendicular, nor normalized).
    As in the book, ``left`` is not normalized again.
    """
    forward = normalize(to - from_)
    left = cross(forward, normalize(up))
    true_up = cross(left, forward)
    orientation = matrix(
        [
            [left.x, left.y, left.z, 0],
            [true_up.x, true_up.y, true_up.z, 0],
            [-forward.x, -forward.y, -forward.z, 0],
            [0, 0, 0, 1],
        ]
    )
    return orientation * translation(-from_.x, -from_.y, -from_.z)
