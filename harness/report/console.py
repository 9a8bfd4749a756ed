"""What ``rtc bench`` prints after a run: each section's lines (no plotting library needed,
so the bench never imports it)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from harness import sections


def console_table(run: Mapping[str, Any]) -> str:
    """Each section's lines, in the table's order, then how long the run took."""
    lines: list[str] = []
    for section in sections.SECTIONS:
        lines += sections.reporting(section.name).console_lines(run)
    if math.isfinite(run["seconds"]):
        lines.append(f"(the run took {run['seconds']:.0f} s)")
    return "\n".join(lines)
