"""The chapter progress (``rtc bench --sections kata``): ``rtc kata --variant all --json``
in a fresh process, kept as the run's ``kata``; ``harness.sections.kata.report`` reports it."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from harness.engine.bench import Bench

SECTION = "kata"


def measure(bench: Bench) -> None:
    """Its progress (``groundwork.progress``: a bar on a terminal, else a line every few seconds)
    goes to our stderr."""
    bench.log(f"{SECTION}: rtc kata --variant all --json")
    try:
        done = subprocess.run(
            [sys.executable, "-m", "rtc.cli", "kata", "--variant", "all", "--json"],
            stdout=subprocess.PIPE,
            text=True,
            timeout=1800,
        )
        data = json.loads(done.stdout)
    except (subprocess.TimeoutExpired, json.JSONDecodeError, OSError) as error:
        bench.notes.append(f"chapter progress unavailable: {type(error).__name__}: {error}")
        return
    bench.kata = {
        "ok": data.get("ok"),
        "variants": data.get("variants"),
        "summary": data.get("summary", []),
        "errors": data.get("errors", []),
    }
