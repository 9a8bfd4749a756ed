"""Real roots of quadratics, cubics and quartics in closed form, as a learner writes them for
the torus (chapter 20 here, beyond the book): the quadratic formula, Cardano's method for
the cubic (the trigonometric form when it has three real roots), and Ferrari's method for
the quartic (a root of its resolvent cubic splits it into two quadratics), in the form
learners take from the graphics literature: a quantity within ``EQN_EPS`` (an absolute 1e-9)
of zero counts as zero. Naive on purpose: near a double root the answer can be far off, a
pair of real roots can be lost or made up, and the fixed tolerance means something else at
every scale; ``variants.robust`` polishes the roots, and ``rtc stability`` measures both
against an exact oracle.

Each function takes the coefficients from the highest power down and returns the real
roots in increasing order (a double root once).
"""

from __future__ import annotations

import math

THIRD = 1.0 / 3.0
EQN_EPS = 1e-9  # within this of zero is zero


def is_zero(x: float) -> bool:
    return -EQN_EPS < x < EQN_EPS


def cube_root(x: float) -> float:
    """The real cube root, sign kept."""
    return math.copysign(abs(x) ** THIRD, x)


def solve_quadratic(a: float, b: float, c: float) -> list[float]:
    """a x² + b x + c = 0 (a != 0)."""
    p = b / (2 * a)
    q = c / a
    discriminant = p * p - q
    if is_zero(discriminant):
        return [-p]
    if discriminant < 0:
        return []
    root = math.sqrt(discriminant)
    return [-root - p, root - p]


def solve_cubic(a: float, b: float, c: float, d: float) -> list[float]:
    """a x³ + b x² + c x + d = 0 (a != 0): Cardano's method on the depressed cubic
    y³ + 3 p y + 2 q = 0, x = y - b / 3a."""
    big_a, big_b, big_c = b / a, c / a, d / a
    square_a = big_a * big_a
    p = THIRD * (-THIRD * square_a + big_b)
    q = 0.5 * (2.0 / 27.0 * big_a * square_a - THIRD * big_a * big_b + big_c)
    cube_p = p * p * p
    discriminant = q * q + cube_p
    if is_zero(discriminant):
        if is_zero(q):  # a triple root
            roots = [0.0]
        else:  # a single and a double root
            u = cube_root(-q)
            roots = [2 * u, -u]
    elif discriminant < 0:  # three real roots: the trigonometric form
        phi = THIRD * math.acos(max(-1.0, min(1.0, -q / math.sqrt(-cube_p))))
        t = 2 * math.sqrt(-p)
        roots = [
            t * math.cos(phi),
            -t * math.cos(phi + math.pi / 3),
            -t * math.cos(phi - math.pi / 3),
        ]
    else:  # one real root
        root = math.sqrt(discriminant)
        roots = [cube_root(root - q) - cube_root(root + q)]
    shift = THIRD * big_a
    return sorted(r - shift for r in roots)


def solve_quartic(a: float, b: float, c: float, d: float, e: float) -> list[float]:
    """a x⁴ + b x³ + c x² + d x + e = 0 (a != 0): Ferrari's method on the depressed quartic
    y⁴ + p y² + q y + r = 0, x = y - b / 4a: with z a root of the resolvent cubic
    z³ - p/2 z² - r z + (r p / 2 - q² / 8) = 0, it is (y² ± v y + z ∓ u)(...) with
    u = √(z² - r) and v = √(2 z - p)."""
    big_a, big_b, big_c, big_d = b / a, c / a, d / a, e / a
    square_a = big_a * big_a
    p = -3.0 / 8.0 * square_a + big_b
    q = 1.0 / 8.0 * square_a * big_a - 0.5 * big_a * big_b + big_c
    r = (
        -3.0 / 256.0 * square_a * square_a + 1.0 / 16.0 * square_a * big_b
        - 0.25 * big_a * big_c + big_d
    )  # fmt: skip
    if is_zero(r):  # y (y³ + p y + q) = 0
        roots = [0.0, *solve_cubic(1.0, 0.0, p, q)]
    else:
        # the largest root: then 2 z - p >= 0 whenever the quartic has real roots
        z = solve_cubic(1.0, -0.5 * p, -r, 0.5 * r * p - 1.0 / 8.0 * q * q)[-1]
        u = z * z - r
        v = 2 * z - p
        if (u < 0 and not is_zero(u)) or (v < 0 and not is_zero(v)):
            return []
        u = 0.0 if is_zero(u) else math.sqrt(u)
        v = 0.0 if is_zero(v) else math.sqrt(v)
        first = solve_quadratic(1.0, -v if q < 0 else v, z - u)
        second = solve_quadratic(1.0, v if q < 0 else -v, z + u)
        roots = first + second
    shift = 0.25 * big_a
    return sorted(r_ - shift for r_ in roots)
