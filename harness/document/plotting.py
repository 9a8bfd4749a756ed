"""What every plot of the report shares: matplotlib with its Agg backend (no display), a
figure written as a PNG atomically, and the caption naming the machine a run measured on."""

from __future__ import annotations

import io
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import matplotlib

from groundwork.files import write_atomically

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure

__all__ = ["caption", "plt", "save"]


def save(figure: Figure, path: Path) -> Path:
    """Write ``figure`` as a PNG atomically."""
    buffer = io.BytesIO()
    try:
        figure.savefig(buffer, format="png", dpi=110, bbox_inches="tight")
    finally:
        plt.close(figure)
    return write_atomically(path, buffer.getvalue())


def caption(run: Mapping[str, Any]) -> str:
    """The machine a run measured on, for a plot's title."""
    m = run["machine"]
    return f"{m['cpu_model']}, {m['cores_available']} cores, Python {m['python']}"
