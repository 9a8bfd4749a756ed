"""Which integrator a variant renders with (``RenderSettings.integrator``): every variant
built on the reference ``Tracer`` renders with both, the book's Whitted integrator and the
path integrator (chapter 21 here, beyond the book: ``raytracer.path``), since the path steps
reach the hits through the steps the variant keeps or overrides; numba's kernels and
wavefront's passes have path integrators of their own (``variants.numba.kernels_path``,
``variants.wavefront.paths``). A variant with a render loop of its own and no path
integrator in it says so in one line (``whitted_only``), instead of rendering the book's
picture in its place.
"""

from __future__ import annotations

from raytracer.camera import WHITTED, RenderSettings
from variants.registry import RenderError


class IntegratorNotPorted(RenderError, ValueError):
    """A render asked a variant for an integrator its render loop does not have; the
    message names the variant (``rtc render`` reports it in one line)."""


def whitted_only(variant: str, settings: RenderSettings) -> None:
    """Raise ``IntegratorNotPorted`` unless ``settings`` ask for the book's integrator:
    ``variant``'s render loop has no other."""
    if settings.integrator != WHITTED:
        raise IntegratorNotPorted(
            f"{variant} has no {settings.integrator} integrator yet (its render loop is the "
            f"book's Whitted tracer): render with --integrator {WHITTED}, or path-trace with "
            "numba, wavefront or a Python variant (naive, cached, robust, prealloc, pooled or "
            "dask over them)"
        )
