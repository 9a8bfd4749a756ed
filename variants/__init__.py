"""Interchangeable tracers: the reference (`naive`) and the optimized variants.

Every variant is found through the ``rtc.variants`` entry-point group (see ``registry``),
named by the grammar ``NAME``, ``NAME[opt=value,flag]``, ``NAME[...]:INNER`` or ``all``,
takes and returns the reference's value types at its API boundary, and overrides only what
it changes.
"""

from variants.registry import (
    Unavailable,
    Variant,
    VariantError,
    available_variants,
    load_variant,
    variant_names,
)

__all__ = [
    "Unavailable",
    "Variant",
    "VariantError",
    "available_variants",
    "load_variant",
    "variant_names",
]
