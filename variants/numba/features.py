"""What a scene needs from the kernels: its feature set, found once from the packed arrays.

The feature set is the set of ``kernel_flags`` switches that are on: the shape kinds and
pattern kinds present (the texture patterns of the bonus chapter "Texture mapping" among
them, and image textures), bounding boxes (a hierarchy's or groups'), CSG, shadows (some
object casts one), reflection, refraction, Schlick (some material is both reflective
and transparent), and area lights (the bonus chapter "Rendering soft shadows"), jittered
or not; and the path integrator (chapter 21 here), which a render's settings ask for
(``with_path``), not the world.
A render compiles (or loads from the disk cache) one kernel module per feature set, so an
opaque-spheres scene runs a kernel with no refraction, Schlick, cylinder or pattern code.
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np

from scene.kinds import KINDS
from scene.pattern_kinds import PATTERN_KINDS
from variants.numba import kernel_flags
from variants.numba import layout as L
from variants.numba.packed import Packed

ALL_FLAGS: tuple[str, ...] = tuple(
    name for name in vars(kernel_flags) if name.startswith("HAS_")
)  # in the order kernel_flags lists them
KIND_NAMES = {kind.number: kind.name for kind in KINDS}
PATTERN_NAMES = {kind.number: kind.name for kind in PATTERN_KINDS}
KIND_FLAGS = {kind.number: f"HAS_{kind.name.upper()}" for kind in KINDS}
"""Each kind of the kind table's switch (``kernel_flags`` holds one for every kind)."""
PATTERN_FLAGS = {kind.number: f"HAS_{kind.name.upper()}" for kind in PATTERN_KINDS}
"""Each kind of the pattern table's switch (``kernel_flags`` holds one for every kind)."""
SHADING_FLAGS = {
    "HAS_SHADOWS": "shadows",
    "HAS_REFLECTION": "reflection",
    "HAS_REFRACTION": "refraction",
    "HAS_SCHLICK": "schlick",
    "HAS_AREA_LIGHTS": "area lights (a shadow ray per cell)",
    "HAS_JITTER": "jittered area lights",
}

STRUCTURE_FLAGS = {
    "HAS_BOXES": "bounding boxes",
    "HAS_NODES": "compact nodes (a hierarchy over triangles alone)",
    "HAS_CSG": "csg",
}


class FeatureSet(NamedTuple):
    """The switches a kernel is compiled with (names from ``kernel_flags``)."""

    flags: frozenset[str]

    @classmethod
    def everything(cls) -> FeatureSet:
        """The generic kernel: every switch on (``specialize=off``, and the book API)."""
        return cls(frozenset(ALL_FLAGS))

    @classmethod
    def from_key(cls, key: str) -> FeatureSet:
        """The set ``key`` spells (``FeatureSet.key``'s spelling); a name no switch has is
        an error naming it."""
        switches = {name.removeprefix("HAS_").lower(): name for name in ALL_FLAGS}
        words = [word for word in key.split("+") if word and word != "empty"]
        unknown = [word for word in words if word not in switches]
        if unknown:
            raise ValueError(f"no kernel feature is named {', '.join(map(repr, unknown))}")
        return cls(frozenset(switches[word] for word in words))

    @property
    def key(self) -> str:
        """A short, stable spelling: the flags that are on, without ``HAS_``."""
        on = [name.removeprefix("HAS_").lower() for name in ALL_FLAGS if name in self.flags]
        return "+".join(on) or "empty"

    def with_path(self) -> FeatureSet:
        """This set and the path integrator (``HAS_PATH``: a render with ``--integrator
        path``); a Whitted render's kernel leaves its code out."""
        return FeatureSet(self.flags | {"HAS_PATH"})

    def describe(self) -> list[str]:
        """Lines for ``explain``: the shapes, structure, patterns and shading stages."""
        kinds = [KIND_NAMES[k] for k, flag in KIND_FLAGS.items() if flag in self.flags]
        patterns = [PATTERN_NAMES[k] for k, flag in PATTERN_FLAGS.items() if flag in self.flags]
        if "HAS_UV_IMAGE" in self.flags:
            patterns.append("image textures")
        shading = [word for flag, word in SHADING_FLAGS.items() if flag in self.flags]
        structure = [
            word
            for flag, word in STRUCTURE_FLAGS.items()
            if flag in self.flags
        ]
        return [
            f"shapes: {', '.join(kinds) or 'none'}",
            f"structure: {', '.join(structure) or 'flat list'}",
            f"patterns: {', '.join(patterns) or 'none'}",
            f"shading: {', '.join(shading) or 'ambient and diffuse only'}",
        ]

    def left_out(self) -> list[str]:
        """The switches that are off (what a kernel for this set does not contain)."""
        return [
            name.removeprefix("HAS_").lower()
            for name in ALL_FLAGS
            if name not in self.flags and name != "HAS_PATTERNS"
        ]


OPTION_FEATURES = "RTC_NUMBA_OPTION_FEATURES"
"""The generic kernel of float32 and fast math with fewer features: where a render that
runs the generic kernel (``specialize=off``, ``RTC_NUMBA_SPECIALIZE=off``) computes in
float32 or with fast math and its scene needs only the features this names
(``FeatureSet.key``'s spelling), its kernel holds those alone. The test suite sets it to
what its float32 and fast-math scenes use (tests/conftest.py); unset, every feature."""


def generic(needed: FeatureSet, approximate: bool) -> FeatureSet:
    """The features of the generic kernel that renders a scene needing ``needed``: every
    one, or for an ``approximate`` precision (float32, fast math) the set that
    ``RTC_NUMBA_OPTION_FEATURES`` names where it holds ``needed``."""
    narrowed = os.environ.get(OPTION_FEATURES) if approximate else None
    if narrowed:
        try:
            chosen = FeatureSet.from_key(narrowed)
        except ValueError as error:
            from variants.registry import RenderError  # the render's one-line failure

            raise RenderError(f"{OPTION_FEATURES}={narrowed!r}: {error}") from None
        if needed.flags <= chosen.flags:
            return chosen
    return FeatureSet.everything()


def analyse(packed: Packed) -> FeatureSet:
    """The feature set a packed world needs (the test shape is never rendered)."""
    flags: set[str] = set()
    # sets of the columns' values, not np.unique: that imports numpy.ma (~15 ms of a render)
    kinds = set(packed.pi[:, L.KIND].tolist()) if len(packed.pi) else set()
    flags.update(KIND_FLAGS[k] for k in kinds if k != L.K_TEST)
    patterns = set(packed.pi[:, L.PATTERN].tolist()) if len(packed.pi) else set()
    flags.update(PATTERN_FLAGS[p] for p in patterns if p != L.P_NONE)
    if patterns - {L.P_NONE}:
        flags.add("HAS_PATTERNS")
    types = set(packed.items[:, L.ITEM_TYPE].tolist()) if len(packed.items) else set()
    if L.I_BOX in types:
        flags.add("HAS_BOXES")
    if L.I_NODES in types:
        flags.add("HAS_NODES")
    if L.I_CSG in types:
        flags.add("HAS_CSG")
    if len(packed.pi) and packed.pi[:, L.CASTS_SHADOW].any():
        flags.add("HAS_SHADOWS")
    reflective = packed.pf[:, L.REFLECTIVE] != 0
    transparent = packed.pf[:, L.TRANSPARENCY] != 0
    if reflective.any():
        flags.add("HAS_REFLECTION")
    if transparent.any():
        flags.add("HAS_REFRACTION")
    both = (packed.pf[:, L.REFLECTIVE] > 0) & (packed.pf[:, L.TRANSPARENCY] > 0)
    if both.any():
        flags.add("HAS_SCHLICK")
    if L.UV_IMAGE in packed.textures.uv_kinds:
        flags.add("HAS_UV_IMAGE")
    area = packed.lights[:, L.LIGHT_USTEPS] > 0 if len(packed.lights) else np.zeros(0, bool)
    if area.any():
        flags.add("HAS_AREA_LIGHTS")
        if (packed.lights[area, L.LIGHT_JITTER] != 0).any():
            flags.add("HAS_JITTER")
    return FeatureSet(frozenset(flags))
