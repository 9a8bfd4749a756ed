"""Progress on stderr for a long job: a render's rows (``rtc render``), the kata's scenarios
(``rtc kata``), a scene that is slow to load (``LoadProgress``).

Nothing is shown for a job that ends within ``DELAY`` seconds. After that, as work is done:

- ``bar`` (the default when stderr is a terminal): a tqdm bar, done/total, time spent and
  left, cleared when the job ends;
- ``lines`` (the default otherwise: a pipe, a log file, CI): a plain line at once and then
  at most one every ``EVERY`` seconds, ``rtc render: 40/100 rows, 12 s so far, about 18 s
  left``, which a log keeps readable (a bar would write a carriage return per update);
- ``none``: nothing.

The display moves when the job reports work done, never from a thread of its own: a job
that is held, stopped or killed prints nothing more, and a step that takes longer than
``EVERY`` seconds shows when it ends.

``advice``: asked, once the delay has passed, with the job's estimated total seconds (time
so far scaled by the share done) until it returns a line to show; that line is shown once,
above the bar (``rtc render``'s "this will take long" line).

``LoadProgress``: a scene's load (a large file, many shapes, big OBJ models) goes through
phases: reading the YAML (characters), building the shapes, and dividing the groups (the
bonus chapter). Its bar appears only once the load has taken ``DELAY`` seconds, so a small
scene prints nothing, and is cleared when the load ends.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from typing import Any, TextIO

DELAY = 1.0  # seconds of work before anything is shown
EVERY = 10.0  # seconds between two plain lines
MODES = ("auto", "bar", "lines", "none")


def duration(seconds: float) -> str:
    """``seconds`` for a person: ``8 s``, ``3 min 35 s``, ``2 h 05 min``."""
    whole = max(0, round(seconds))
    if whole < 60:
        return f"{whole} s"
    if whole < 3600:
        return f"{whole // 60} min {whole % 60:02d} s"
    return f"{whole // 3600} h {whole % 3600 // 60:02d} min"


def open_bar(total: int, done: int, label: str, unit: str, stream: TextIO, **more: Any) -> Any:
    """A tqdm bar on ``stream`` drawn at once with ``done`` of ``total`` (0: unknown), cleared
    when it is closed: every bar of the project (a render's, the kata's, a load's)."""
    # deferred: saves ~25 ms (tqdm) of every command that draws no bar
    from tqdm import tqdm

    return tqdm(
        total=max(total, done) or None, initial=done, desc=label, unit=unit, file=stream,
        leave=False, dynamic_ncols=True, **more,
    )  # fmt: skip


def _is_terminal(stream: TextIO) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


class Progress:
    """The progress of one job of ``total`` steps (``unit``: what a step is, singular),
    labelled ``label`` (the command: ``rtc render``).

    Call it (or ``advance``) with the number of steps just done. mode: one of ``MODES``
    (``auto``: ``bar`` on a terminal, else ``lines``); stream: where (default stderr);
    delay, every: seconds (``DELAY``, ``EVERY``); clock: a monotonic clock in seconds (tests
    pass their own); advice: see the module's docstring.
    """

    def __init__(
        self,
        label: str,
        total: int,
        unit: str,
        *,
        mode: str = "auto",
        stream: TextIO | None = None,
        delay: float = DELAY,
        every: float = EVERY,
        clock: Callable[[], float] = time.monotonic,
        advice: Callable[[float], str | None] | None = None,
    ) -> None:
        if mode not in MODES:
            raise ValueError(f"progress mode {mode!r}: expected one of {', '.join(MODES)}")
        self.stream = stream if stream is not None else sys.stderr
        if mode == "auto":
            mode = "bar" if _is_terminal(self.stream) else "lines"
        self.mode = mode
        self.label = label
        self.total = max(total, 0)
        self.unit = unit
        self.delay = delay
        self.every = every
        self.clock = clock
        self.advice = advice
        self.start = clock()
        self.done = 0
        self.bar: Any = None
        self.last_line: float | None = None  # the clock when the last plain line was written
        self.lines = 0  # plain lines written
        self.advised: str | None = None  # the advice line, once shown
        self.shown = False  # whether a bar or a line was ever shown

    def __call__(self, steps: int) -> None:
        self.advance(steps)

    def set_total(self, total: int) -> None:
        """The job turned out to have ``total`` steps (``rtc kata`` learns it once pytest
        has collected the scenarios): its time, and the delay, count from now."""
        self.total = max(total, 0)
        self.start = self.clock()
        if self.bar is not None:
            self.bar.total = self.total
            self.bar.refresh()

    def exclude(self, seconds: float) -> None:
        """Leave ``seconds`` just spent out of the job's time (numba's one-time compile):
        the estimates are the work's alone."""
        self.start += seconds

    def elapsed(self) -> float:
        return self.clock() - self.start

    def estimate(self) -> float | None:
        """The job's estimated total seconds, from the share done so far; None before any
        step is done."""
        if self.done <= 0 or self.total <= 0:
            return None
        return self.elapsed() * max(self.total, self.done) / self.done

    def advance(self, steps: int = 1) -> None:
        """``steps`` more steps done: show what is due."""
        self.done += steps
        if self.mode == "none":
            return
        elapsed = self.elapsed()
        if elapsed < self.delay and not self.shown:
            return
        self._advise()
        if self.mode == "bar":
            if self.bar is None:
                self._open()
            else:
                self.bar.update(self.done - self.bar.n)
            return
        now = self.clock()
        if self.last_line is None or now - self.last_line >= self.every:
            self.write(self.line())
            self.last_line = now
            self.lines += 1
            self.shown = True

    def line(self) -> str:
        """The plain line: ``rtc render: 40/100 rows, 12 s so far, about 18 s left``."""
        units = self.unit + ("" if self.total == 1 else "s")
        text = f"{self.label}: {self.done}/{self.total} {units}, {duration(self.elapsed())} so far"
        estimate = self.estimate()
        if estimate is not None and self.done < self.total:
            text += f", about {duration(estimate - self.elapsed())} left"
        return text

    def _advise(self) -> None:
        if self.advice is None or self.advised is not None:
            return
        estimate = self.estimate()
        if estimate is None:
            return
        said = self.advice(estimate)
        if said:
            self.advised = said
            self.write(said)

    def write(self, text: str) -> None:
        """One line on the stream, above the bar if one is drawn."""
        if self.bar is not None:
            self.bar.write(text, file=self.stream)
        else:
            print(text, file=self.stream, flush=True)

    def _open(self) -> None:
        self.bar = open_bar(self.total, self.done, self.label, self.unit, self.stream)
        self.shown = True

    def close(self) -> None:
        """Clear the bar (if one is drawn); a plain line stays."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None


class Ticker:
    """For a step that reports no progress of its own (numba compiling a kernel): ``say``
    is called with the seconds so far every ``every`` seconds, from a thread of its own,
    until ``stop``, so that a log does not fall silent. ``wait(seconds)`` waits for the stop
    or the time, True once stopped (``threading.Event.wait``; tests pass their own)."""

    def __init__(
        self,
        say: Callable[[float], object],
        every: float = EVERY,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.say = say
        self.every = every
        self.clock = clock
        self.stopped = threading.Event()
        self.wait: Callable[[float], bool] = self.stopped.wait
        self.thread: threading.Thread | None = None

    def start(self) -> Ticker:
        self.thread = threading.Thread(target=self.run, name="rtc-ticker", daemon=True)
        self.thread.start()
        return self

    def run(self) -> None:
        began = self.clock()
        while not self.wait(self.every):
            self.say(self.clock() - began)

    def stop(self) -> None:
        self.stopped.set()
        if self.thread is not None and self.thread is not threading.current_thread():
            self.thread.join()
            self.thread = None


def compile_ticker(say: Callable[[str], object], every: float = EVERY) -> Callable[..., None]:
    """An ``on_compile`` listener (``compiled.library``) that says ``still compiling, N s so
    far`` every ``every`` seconds while a compile runs (the compile's own start and end
    lines are the caller's)."""
    running: list[Ticker] = []

    def listener(what: str, seconds: float | None) -> None:
        if seconds is None:
            running.append(
                Ticker(
                    lambda spent: say(f"still compiling, {duration(spent)} so far"), every
                ).start()
            )
        elif running:
            running.pop().stop()

    return listener


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
