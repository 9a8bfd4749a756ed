"""Which run the report shows for a section: a run over part of the variants never replaces a
fuller one.

``rtc bench --variants mine,naive`` (a learner's check of their own tracer) measures the
ladder and the table of two variants. Shown as the newest ladder, it would make the
report's Summary "fastest: naive" and the README's figures an empty list. So each section
comes from the newest *whole* run that measured it (``partial`` is None: every variant the
bench offers, ``--variants all``), and a newer partial run is added after it as a table of
its own rows (``harness.report.build``), never in its place. Where only partial runs measured
a section, the newest of them is shown, and says so.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness import sections

Run = Mapping[str, Any]


def partial(run: Run) -> str | None:
    """What ``run`` left out, in words (``--variants naive,mine``), or None for a whole run
    (the runs made before this was recorded count as whole)."""
    asked = (run.get("settings") or {}).get("variants_asked")
    if asked is None or asked == "all":
        return None
    return f"--variants {asked}"


def shown(name: str, runs: Sequence[Run]) -> Run | None:
    """The run whose section ``name`` the report shows (see the module)."""
    newest = sections.reporting(name).newest
    whole = [run for run in runs if partial(run) is None]
    return newest(whole) or newest(runs)


def newer_partial(name: str, runs: Sequence[Run]) -> Run | None:
    """The newest partial run that measured section ``name`` after the run shown, if any
    (the report adds its rows after the section)."""
    chosen = shown(name, runs)
    if chosen is None or partial(chosen) is not None:
        return None
    after = [run for run in runs if str(run.get("started", "")) > str(chosen.get("started", ""))]
    found = sections.reporting(name).newest([run for run in after if partial(run) is not None])
    return found
