"""Builds the one optional C extension, ``harness.instruments._alloccount`` (exact allocation
counts).

Everything else is configured in pyproject.toml. The extension is optional: without a C
compiler (or without NumPy's headers) ``pip install`` still succeeds and the harness falls
back to tracemalloc-based figures, saying so in its tables.
"""

from __future__ import annotations

from setuptools import Extension, setup


def _numpy_options() -> dict[str, list]:
    """Count NumPy array buffers too (NEP 49 handler) when NumPy's headers are available."""
    try:
        import numpy
    except ImportError:
        return {}
    return {"include_dirs": [numpy.get_include()], "define_macros": [("RTC_WITH_NUMPY", "1")]}


setup(
    ext_modules=[
        Extension(
            "harness.instruments._alloccount",
            ["harness/instruments/_alloccount.c"],
            optional=True,
            **_numpy_options(),
        )
    ]
)
