"""Interchangeable tracers: the reference (`naive`) and the optimized variants.

Every variant is found through the ``rtc.variants`` entry-point group (see ``registry``),
named by the grammar ``NAME``, ``NAME[opt=value,flag]``, ``NAME[...]:INNER`` or ``all``,
takes and returns the reference's value types at its API boundary, and overrides only what
it changes.

A variant is a module or package of its own (``naive``, ``cached``, ``prealloc``,
``robust``, ``numba``, ``wavefront``, ``pooled``, ``dask_cluster``) and imports no other
but ``cached``, which ``prealloc`` and ``robust`` build on. What several share stands below
them: ``arrays`` (the array tracers' scene walk, table rows and canvas), ``jobs`` and
``wrapper`` (what the wrappers share), ``registry`` (names, factories, errors) and ``stubs``
(a learner's tracer's). The import contracts in ``pyproject.toml`` keep it so.
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
