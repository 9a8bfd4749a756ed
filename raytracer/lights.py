"""Light sources: chapter 6's point light, and the area light of the bonus chapter
"Rendering soft shadows" (chapter 18 here).

An area light is a parallelogram (``corner``, and the edges ``usteps * uvec`` and
``vsteps * vvec``) cut into ``usteps`` x ``vsteps`` cells. Each cell stands for one point
of light, ``point_on_light(light, u, v)``: the corner of cell (u, v) plus a fraction of the
cell's edges that the light's ``jitter_by`` sequence gives (two values per point, u's
then v's; ``sequence(0.5)``, the default, is every cell's centre). Shading with it
(``raytracer.materials.lighting``, ``raytracer.tracer.Tracer.intensity_at``) walks the
cells v outer, u inner, so the sequence's values go to the cells in that order.

The sequence is the book's: a cyclic generator, the one mutable object inside the
otherwise immutable light. A sequence of several values makes a render depend on the order
in which rays are traced; scenes use ``jitter`` instead (``AreaLight.jitter``): the tracer
gives each pixel sample and light its own reproducible sequence (``Tracer.light_for_sample``,
``raytracer.sampling.light_jitter``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from raytracer.colors import Color
from raytracer.sampling import MAX_LIGHT_STEPS
from raytracer.tuples import Tuple


@dataclass(frozen=True, slots=True)
class PointLight:
    """A light with no size: ``position`` (a point) and ``intensity`` (its color)."""

    position: Tuple
    intensity: Color


def point_light(position: Tuple, intensity: Color) -> PointLight:
    """Chapter 6: a point light at ``position`` shining with ``intensity``."""
    return PointLight(position, intensity)


class CyclicSequence:
    """The soft shadows chapter's ``sequence``: ``next(gen)`` gives its values in order,
    starting over after the last.

    ``values`` never changes; only the position of the next value does. Two sequences are
    equal when their values are (wherever each stands), so that two lights built alike
    compare equal; a sequence hashes by its values too. It pickles (a pool's workers get
    their own copy, standing where the original stood).
    """

    __slots__ = ("_next", "values")

    def __init__(self, values: Iterable[float]) -> None:
        numbers = tuple(values)
        if not numbers:
            raise ValueError("sequence: give at least one value, e.g. sequence(0.5)")
        for value in numbers:
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"sequence: {value!r} is not a number")
            if not math.isfinite(value):
                raise ValueError(f"sequence: {value!r} is not a finite number")
        self.values: tuple[float, ...] = numbers
        self._next = 0

    def __next__(self) -> float:
        value = self.values[self._next]
        self._next = (self._next + 1) % len(self.values)
        return value

    def __iter__(self) -> Iterator[float]:
        return self

    @property
    def position(self) -> int:
        """The index in ``values`` of the value ``next`` gives next."""
        return self._next

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, CyclicSequence):
            return NotImplemented
        return self.values == other.values

    def __hash__(self) -> int:
        return hash(self.values)

    def __repr__(self) -> str:
        return f"sequence({', '.join(repr(v) for v in self.values)})"


def sequence(*values: float) -> CyclicSequence:
    """Soft shadows: a cyclic sequence of ``values`` (``next(gen)`` gives them in turn,
    forever), the chapter's deterministic stand-in for random numbers."""
    return CyclicSequence(values)


def next_(gen: Iterator[float]) -> float:
    """Soft shadows: the book's ``next(gen)``, the next value of a sequence."""
    return next(gen)


def _centre_jitter() -> CyclicSequence:
    return CyclicSequence((0.5,))


@dataclass(frozen=True, slots=True)
class AreaLight:
    """Soft shadows: a light spread over a parallelogram of ``usteps`` x ``vsteps`` cells.

    corner: a point, one corner of the light; uvec, vvec: one cell's edges (vectors; the
    light's full edges are ``uvec * usteps`` and ``vvec * vsteps``); usteps, vsteps: whole
    numbers of cells, 1 or more; intensity: its color (the whole light's: each cell gives
    ``1 / samples`` of it); position: its centre (``corner + full_uvec / 2 +
    full_vvec / 2``, as ``area_light`` computes it); jitter_by: where in its cell each
    point goes (``sequence``, two values per point); jitter: True for the random per-sample
    jitter of scene files (``Tracer.light_for_sample`` gives each pixel sample its own
    ``jitter_by``); False: ``jitter_by`` as it is.

    Build one with ``area_light``. The light is a value (``light.jitter_by ← ...`` makes a
    new light); its ``jitter_by`` is the one mutable part, as in the book.
    """

    corner: Tuple
    uvec: Tuple
    usteps: int
    vvec: Tuple
    vsteps: int
    intensity: Color
    position: Tuple
    jitter_by: CyclicSequence = field(default_factory=_centre_jitter)
    jitter: bool = False

    def __post_init__(self) -> None:
        for name in ("usteps", "vsteps"):
            steps = getattr(self, name)
            if isinstance(steps, bool) or not isinstance(steps, int):
                raise ValueError(f"area_light: {name} must be a whole number, got {steps!r}")
            if not 1 <= steps <= MAX_LIGHT_STEPS:
                raise ValueError(f"area_light: {name} must be 1 to {MAX_LIGHT_STEPS}, got {steps}")
        if not isinstance(self.jitter_by, CyclicSequence):
            raise ValueError(
                "area_light: jitter_by must be a sequence(...), got "
                f"{type(self.jitter_by).__name__}"
            )
        if not isinstance(self.jitter, bool):
            raise ValueError(f"area_light: jitter must be true or false, got {self.jitter!r}")

    @property
    def samples(self) -> int:
        """How many cells (points of light) it has: ``usteps * vsteps``."""
        return self.usteps * self.vsteps


Light = PointLight | AreaLight
"""What a world's ``lights`` hold."""


def _whole_steps(value: float, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"area_light: {name} must be a whole number, got {value!r}")
    if isinstance(value, float) and not value.is_integer():
        raise ValueError(f"area_light: {name} must be a whole number, got {value}")
    steps = int(value)
    if not 1 <= steps <= MAX_LIGHT_STEPS:
        raise ValueError(f"area_light: {name} must be 1 to {MAX_LIGHT_STEPS}, got {value}")
    return steps


def _edge(v: Tuple, name: str) -> Tuple:
    if v.w != 0:
        raise ValueError(f"area_light: {name} must be a vector (w = 0), got w = {v.w}")
    length = math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z)
    if not length > 0 or not math.isfinite(length):
        raise ValueError(
            f"area_light: {name} must be a vector of finite, non-zero length, got "
            f"({v.x}, {v.y}, {v.z})"
        )
    return v


def area_light(
    corner: Tuple,
    full_uvec: Tuple,
    usteps: int,
    full_vvec: Tuple,
    vsteps: int,
    intensity: Color,
) -> AreaLight:
    """Soft shadows: a light over the parallelogram from ``corner`` along ``full_uvec``
    (cut into ``usteps`` cells) and ``full_vvec`` (``vsteps`` cells), shining with
    ``intensity``; every cell is sampled at its centre (``jitter_by`` = ``sequence(0.5)``).

    Raises ``ValueError`` for a step count that is not a whole number from 1, or an edge
    that is not a vector of non-zero length.
    """
    usteps = _whole_steps(usteps, "usteps")
    vsteps = _whole_steps(vsteps, "vsteps")
    if corner.w != 1:
        raise ValueError(f"area_light: the corner must be a point (w = 1), got w = {corner.w}")
    full_uvec = _edge(full_uvec, "full_uvec")
    full_vvec = _edge(full_vvec, "full_vvec")
    centre = corner + full_uvec / 2 + full_vvec / 2
    return AreaLight(
        corner, full_uvec / usteps, usteps, full_vvec / vsteps, vsteps, intensity, centre
    )


def point_on_light(light: AreaLight, u: int, v: int) -> Tuple:
    """Soft shadows: the point of cell (u, v): ``corner + uvec * (u + next(jitter_by)) +
    vvec * (v + next(jitter_by))`` (two values of the sequence, u's first)."""
    return (
        light.corner
        + light.uvec * (u + next(light.jitter_by))
        + light.vvec * (v + next(light.jitter_by))
    )


def describe_lights(lights: Iterable[Light]) -> str:
    """The lights for ``rtc render --explain``: how many, and each area light's cells."""
    found = list(lights)
    text = f"{len(found)} light{'' if len(found) == 1 else 's'}"
    areas = [light for light in found if isinstance(light, AreaLight)]
    if areas:
        each = ", ".join(
            f"{a.usteps}x{a.vsteps} = {a.samples} cells{' jittered' if a.jitter else ''}"
            for a in areas
        )
        text += (
            f" ({len(areas)} area light{'' if len(areas) == 1 else 's'}: {each}; "
            "a shadow ray per cell at every shaded point)"
        )
    return text
