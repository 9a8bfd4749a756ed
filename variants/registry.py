"""The variant registry: variants are discovered through the ``rtc.variants`` entry points.

An entry point names a zero-argument factory that returns a ``Variant``. A factory whose
optional dependency is missing raises ``ImportError`` (or ``Unavailable``); the registry then
reports that variant as unavailable, with the reason, and the others still load.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from typing import Any

GROUP = "rtc.variants"


class Unavailable(Exception):
    """Raised by a variant factory that cannot run here; the message says why."""


@dataclass(frozen=True)
class Variant:
    """A tracer that answers the book's API.

    name: what ``--variant`` calls it.
    summary: one line for ``rtc variants``.
    api: the book's names (see ``raytracer.api.BOOK_API``) mapped to callables and constants.
    overrides: the book names whose implementation differs from the reference's.
    base: the variant this one builds on, if any.
    """

    name: str
    summary: str
    api: Mapping[str, Any] = field(repr=False)
    overrides: frozenset[str] = frozenset()
    base: str | None = None


@dataclass(frozen=True)
class VariantEntry:
    """One registry entry: a variant, or the reason it is not available."""

    name: str
    variant: Variant | None
    reason: str = ""

    @property
    def available(self) -> bool:
        return self.variant is not None


def _entry_points() -> dict[str, Any]:
    found = {ep.name: ep for ep in entry_points().select(group=GROUP)}
    return dict(sorted(found.items(), key=lambda item: (item[0] != "naive", item[0])))


def variant_names() -> list[str]:
    """Every registered variant name, ``naive`` first, available or not."""
    return list(_entry_points())


def _load_entry(name: str, ep: Any) -> VariantEntry:
    try:
        factory: Callable[[], Variant] = ep.load()
        return VariantEntry(name, factory())
    except (ImportError, Unavailable) as error:
        return VariantEntry(name, None, f"{type(error).__name__}: {error}")


def registry() -> list[VariantEntry]:
    """Load every registered variant; broken ones are reported, not raised."""
    return [_load_entry(name, ep) for name, ep in _entry_points().items()]


def available_variants() -> list[Variant]:
    return [entry.variant for entry in registry() if entry.variant is not None]


def load_variant(name: str) -> Variant:
    """The variant called ``name``; a clear error if it is unknown or unavailable."""
    eps = _entry_points()
    if name not in eps:
        known = ", ".join(eps) or "none"
        raise LookupError(f"unknown variant {name!r}; registered variants: {known}")
    entry = _load_entry(name, eps[name])
    if entry.variant is None:
        raise LookupError(f"variant {name!r} is not available here: {entry.reason}")
    return entry.variant
