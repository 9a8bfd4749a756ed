"""The stability suite: every case, the variants to run them on, and the run itself.

``all`` is every available variant with its default options, plus each option set it
advertises (``Variant.bench_configs``) that changes its arithmetic (``float32``,
``fastmath``), plus ``robust``: loaded from the registry once its entry point exists, from
its factory until then.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from harness.engine.plan import bench_configs, split_names
from harness.stability import (
    cases_degenerate,
    cases_path,
    cases_rays,
    cases_refraction,
    cases_scale,
    cases_torus,
    cases_transforms,
)
from harness.stability.model import Case, Outcome, Probe, crashed
from variants.registry import Variant, VariantError, load_variant, parse_variant_name, registry
from variants.robust import variant as robust_variant

CASES: list[Case] = [
    *cases_scale.CASES,
    *cases_rays.CASES,
    *cases_torus.CASES,
    *cases_transforms.CASES,
    *cases_refraction.CASES,
    *cases_degenerate.CASES,
    *cases_path.CASES,
]
ARITHMETIC_OPTIONS = ("float32", "fastmath")
ROBUST = "robust"


@dataclass(frozen=True)
class Cell:
    """One case run on one variant."""

    case: str
    variant: str
    outcome: Outcome
    seconds: float


def _robust_directly() -> Variant:
    """``robust`` from its factory (until pyproject registers its entry point)."""
    return robust_variant()


def load(name: str) -> Variant:
    """A variant by name (the registry's grammar); ``robust`` works before it is registered.
    A ``VariantError`` for anything else the registry does not know."""
    try:
        return load_variant(name)
    except VariantError:
        if name.strip() == ROBUST and ROBUST not in {entry.name for entry in registry()}:
            return _robust_directly()
        raise


def arithmetic_configs(variant: Variant) -> list[str]:
    """The option sets ``variant`` advertises that change its arithmetic."""
    return [
        name
        for name in bench_configs(variant)
        if any(key in ARITHMETIC_OPTIONS for key, _ in parse_variant_name(name).options)
    ]


def select_variants(text: str) -> tuple[list[Variant], dict[str, str]]:
    """The variants named by ``text`` (comma-separated names, ``all``), each once, and the
    unavailable ones ``all`` skipped -> why. A ``VariantError`` for a bad name."""
    chosen: dict[str, Variant] = {}
    unavailable: dict[str, str] = {}
    for token in split_names(text):
        if token != "all":
            variant = load(token)
            chosen.setdefault(variant.name, variant)
            continue
        entries = registry()
        for entry in entries:
            if entry.variant is None:
                unavailable[entry.name] = entry.reason
                continue
            chosen.setdefault(entry.variant.name, entry.variant)
            for config in arithmetic_configs(entry.variant):
                extra = load_variant(config)
                chosen.setdefault(extra.name, extra)
        if ROBUST not in {entry.name for entry in entries}:
            chosen.setdefault(ROBUST, _robust_directly())
    if not chosen:
        raise VariantError(f"no variant named in {text!r}")
    return list(chosen.values()), unavailable


def select_cases(text: str | None) -> list[Case]:
    """The cases whose id starts with one of the comma-separated prefixes (all for None);
    a ``ValueError`` naming the prefixes that match nothing."""
    if not text:
        return list(CASES)
    prefixes = [p.strip() for p in text.split(",") if p.strip()]
    unmatched = [p for p in prefixes if not any(c.id.startswith(p) for c in CASES)]
    if unmatched or not prefixes:
        groups = sorted({c.group for c in CASES})
        raise ValueError(
            f"no stability case starts with {', '.join(map(repr, unmatched)) or repr(text)}; "
            f"the groups are {', '.join(groups)} (or a full id such as scale/1e-6)"
        )
    return [c for c in CASES if any(c.id.startswith(p) for p in prefixes)]


def run_case(case: Case, probe: Probe) -> Cell:
    """One case on one variant; an exception the case did not catch is a crash."""
    started = time.perf_counter()
    with warnings.catch_warnings():
        # float32 packing overflows (index 1e200) are measured by the case, not printed
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            outcome = case.check(probe)
        except Exception as error:  # a crash is a result, never the suite's end
            outcome = crashed(error)
    return Cell(case.id, probe.variant.name, outcome, time.perf_counter() - started)


def run_suite(
    variants: Sequence[Variant],
    cases: Sequence[Case],
    size: tuple[int, int],
    log: Callable[[str], object] | None = None,
) -> list[Cell]:
    """Every case on every variant, variant by variant; renders at ``size``."""
    cells: list[Cell] = []
    for variant in variants:
        probe = Probe(variant, size)
        started = time.perf_counter()
        for case in cases:
            cells.append(run_case(case, probe))
        if log is not None:
            log(f"{variant.name}: {len(cases)} cases in {time.perf_counter() - started:.1f} s")
    return cells
