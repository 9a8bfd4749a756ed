"""The kinds of pattern (chapter 10, and the bonus chapter "Texture mapping"): one table,
one row per kind, as ``scene.kinds`` is for shapes.

Each row says what a kind is, not how a tracer colors it: its name (the book's factory),
the reference's class, the scene format's ``type:`` for it, and whether it holds two colours
``a`` and ``b`` (a texture pattern holds uv patterns instead; chapter 10's test pattern,
none). Its number is its place in the
table plus one: 0 is no pattern. The packers of the compiled and vectorized tracers, the
kernel specialization and ``--explain`` read their lists of pattern kinds from here; a
tracer's own code for coloring a kind stays in that tracer, in one place per kind.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from raytracer.api import BOOK_API
from raytracer.patterns import (
    CheckersPattern,
    GradientPattern,
    Pattern,
    RingPattern,
    StripePattern,
    TestPattern,
)
from raytracer.textures.maps import CubeMap, TextureMap
from scene.kinds import unchanged

PATTERN_METHODS = ("local_pattern_at",)
"""What a subclass of a reference pattern must inherit unchanged to count as its kind."""

NO_PATTERN = 0
"""The number a tracer stores for a material without a pattern."""


class PatternKind(NamedTuple):
    """One kind of pattern.

    name: the book's factory (``stripe_pattern()``); reference: the reference's class; key:
    the scene format's ``type:`` (None: not written by type; the texture patterns are
    ``type: map``, ``scene.textures``); two_colors: it colors with its ``a`` and ``b``;
    texture: a texture pattern of the bonus chapter (uv patterns through a mapping, or one
    per face of a cube).
    """

    name: str
    reference: type[Pattern]
    key: str | None = None
    two_colors: bool = True
    texture: bool = False

    @property
    def chapter(self) -> int:
        """Where the book introduces it (its factory's chapter, ``raytracer.api``)."""
        return BOOK_API[self.name]

    @property
    def number(self) -> int:
        """Its place in ``PATTERN_KINDS`` plus one: the number tracers store in their
        tables (0: no pattern)."""
        return PATTERN_KINDS.index(self) + 1


PATTERN_KINDS: tuple[PatternKind, ...] = (
    PatternKind("stripe_pattern", StripePattern, "stripes"),
    PatternKind("gradient_pattern", GradientPattern, "gradient"),
    PatternKind("ring_pattern", RingPattern, "rings"),
    PatternKind("checkers_pattern", CheckersPattern, "checkers"),
    PatternKind("test_pattern", TestPattern, two_colors=False),
    PatternKind("texture_map", TextureMap, two_colors=False, texture=True),
    PatternKind("cube_map", CubeMap, two_colors=False, texture=True),
)
"""Every pattern kind, in the order tracers number them (from 1)."""

BY_NAME: dict[str, PatternKind] = {kind.name: kind for kind in PATTERN_KINDS}
PLAIN: tuple[PatternKind, ...] = tuple(kind for kind in PATTERN_KINDS if not kind.texture)
"""The kinds of chapter 10 (no texture patterns)."""


def pattern_kind(name: str) -> PatternKind:
    """The pattern kind called ``name`` (``KeyError`` for any other)."""
    return BY_NAME[name]


def reference_pattern_kind(
    pattern: object, kinds: Sequence[PatternKind] = PATTERN_KINDS
) -> PatternKind | None:
    """The kind of ``pattern`` among ``kinds``: a reference pattern, or a subclass that
    keeps how it colors (``local_pattern_at``); None for any other pattern."""
    for kind in kinds:
        if isinstance(pattern, kind.reference):
            return kind if unchanged(type(pattern), kind.reference, PATTERN_METHODS) else None
    return None


def names(kinds: Sequence[PatternKind]) -> str:
    """``stripe_pattern, gradient_pattern, ...``: for the 'known: ...' part of an error."""
    return ", ".join(k.name for k in kinds)
