"""A progress bar for a scene that is slow to load (a large file, many shapes, big OBJ models).

The bar (tqdm, on stderr) appears only once a load has taken ``DELAY`` seconds, so a small
scene prints nothing; it goes through the load's phases: reading the YAML (characters),
building the shapes, and dividing the groups (the bonus chapter). It is cleared when the
load ends.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import Any, TextIO

DELAY = 1.0  # seconds before a bar appears


def open_bar(total: int, done: int, label: str, unit: str, stream: TextIO, **more: Any) -> Any:
    """A tqdm bar on ``stream`` drawn at once with ``done`` of ``total`` (0: unknown), cleared
    when it is closed; ``rtc render``'s and ``rtc kata``'s bars are drawn by it too."""
    from tqdm import tqdm

    return tqdm(
        total=max(total, done) or None, initial=done, desc=label, unit=unit, file=stream,
        leave=False, dynamic_ncols=True, **more,
    )  # fmt: skip


class LoadProgress:
    """The phases of one load, drawn as a tqdm bar once the load is slow.

    enabled: draw at all (default: when stderr is a terminal, as ``rtc render``'s bar);
    stream: where (default stderr); delay: seconds of loading before the bar appears; clock:
    a monotonic clock in seconds (tests pass their own).
    """

    def __init__(
        self,
        label: str,
        *,
        enabled: bool | None = None,
        stream: TextIO | None = None,
        delay: float | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.label = label
        self.delay = DELAY if delay is None else delay
        self.clock = clock
        self.start = clock()
        self.phase_name = ""
        self.total = 0
        self.done = 0
        self.unit = "it"
        self.bar: Any = None
        self.shown = False  # whether a bar was ever drawn (for tests)

    def phase(self, name: str, total: int, unit: str = "it") -> None:
        """Start a phase of ``total`` steps (the bar, if drawn, restarts at 0)."""
        self.phase_name, self.total, self.done, self.unit = name, max(total, 0), 0, unit
        if self.bar is not None:
            self.bar.reset(total=self.total or None)
            self.bar.unit = unit
            self.bar.set_description_str(f"{self.label}: {name}", refresh=False)
            self.bar.refresh()

    def advance(self, steps: int = 1) -> None:
        """``steps`` more steps of the current phase done."""
        self.update(self.done + steps)

    def update(self, done: int) -> None:
        """The current phase has ``done`` steps done (a total exceeded grows the total)."""
        self.done = done
        if not self.enabled:
            return
        if self.bar is None:
            if self.clock() - self.start < self.delay:
                return
            self._open()
        if done > self.total:
            self.total = done
            self.bar.total = done
        self.bar.update(done - self.bar.n)

    def _open(self) -> None:
        self.bar = open_bar(
            self.total, self.done, f"{self.label}: {self.phase_name}", self.unit, self.stream,
            unit_scale=True,
        )  # fmt: skip
        self.shown = True

    def close(self) -> None:
        """Clear the bar (if one was drawn)."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None
