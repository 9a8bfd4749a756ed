"""A variant for the fault tests: ``held``, naive's tracer held at its first region until the
test lets it go, so that "a render still running" is a certainty, not a race with the clock.

Not a test module and not on the suite's path: ``tests/holding.py`` copies it into a private
site folder with an entry point, for the processes a test starts (``rtc render``, ``rtc
bench``, its measuring process, a pool's workers), as an installed plugin would be.

``RTC_TEST_HOLD`` names a folder. A process's first ``render_region`` writes
``reached-PID`` there, then waits until the file ``release`` exists; every later region is
traced at once. Without ``RTC_TEST_HOLD`` it is naive.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from raytracer.tracer import Tracer
from variants.registry import Variant, check_options, reject_inner, tracer_variant

NAME = "held"
HOLD_VARIABLE = "RTC_TEST_HOLD"
RELEASE = "release"
REACHED_PREFIX = "reached-"
POLL_SECONDS = 0.01


class HeldTracer(Tracer):
    """The reference's tracer, waiting at its first region for the test's release."""

    def __init__(self) -> None:
        super().__init__()
        self.waited = False

    def render_region(self, c: Any, w: Any, settings: Any, region: Any) -> Sequence[float]:
        folder = os.environ.get(HOLD_VARIABLE)
        if folder and not self.waited:
            self.waited = True
            hold = Path(folder)
            (hold / f"{REACHED_PREFIX}{os.getpid()}").touch()
            while not (hold / RELEASE).exists():
                time.sleep(POLL_SECONDS)
        return super().render_region(c, w, settings, region)


def variant(inner: Variant | None = None, **options: str) -> Variant:
    reject_inner(NAME, inner)
    check_options(NAME, options)
    return tracer_variant(
        NAME, "naive, held at its first region until the test releases it", HeldTracer()
    )
