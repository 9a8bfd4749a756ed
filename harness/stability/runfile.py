"""Stability run files: ``results/runs/stability-<UTC time>-<random>.json``, one per ``rtc
stability``, written atomically and never replaced (``harness.engine.results``'s writer), beside the
bench runs (whose names start with ``bench-``, so neither history sees the other).

The file holds one JSON object ``{"rtc": {...}}``: ``schema_version``, ``kind``
("stability"), ``stem``, ``started``, ``seconds``, ``machine``, ``settings`` (size, cases),
``variants``, ``unavailable``, ``cases`` (id, title, measure, tolerance, unit) and ``results``
(case, variant, verdict, error, tolerance, detail, note, seconds).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

from groundwork.files import read_text
from harness.engine.results import (
    MAX_RUN_FILE_BYTES,
    ResultFileError,
    new_stem,
    runs_dir,
    write_new_file,
)
from harness.stability.model import Case, Verdict
from harness.stability.suite import Cell

SCHEMA_VERSION = 1
KIND = "stability"
PREFIX = "stability-"


def _number(value: float | None) -> float | None:
    """JSON has no NaN or infinity: those become None."""
    return value if value is not None and math.isfinite(value) else None


def document(
    cells: Sequence[Cell],
    cases: Sequence[Case],
    variants: Sequence[str],
    unavailable: dict[str, str],
    settings: dict[str, Any],
    machine: dict[str, Any],
    started: datetime,
    seconds: float,
) -> dict[str, Any]:
    """The run file's content (see the module docstring)."""
    return {
        "rtc": {
            "schema_version": SCHEMA_VERSION,
            "kind": KIND,
            "started": started.isoformat(),
            "seconds": seconds,
            "machine": machine,
            "settings": settings,
            "variants": list(variants),
            "unavailable": dict(unavailable),
            "cases": [
                {
                    "id": c.id,
                    "title": c.title,
                    "measure": c.measure,
                    "tolerance": c.tolerance,
                    "unit": c.unit,
                }
                for c in cases
            ],
            "results": [
                {
                    "case": cell.case,
                    "variant": cell.variant,
                    "verdict": cell.outcome.verdict.value,
                    "error": _number(cell.outcome.error),
                    "tolerance": _number(cell.outcome.tolerance),
                    "detail": cell.outcome.detail,
                    "note": cell.outcome.note,
                    "seconds": round(cell.seconds, 4),
                }
                for cell in cells
            ],
        }
    }


def write_run(results: Path, data: dict[str, Any]) -> Path:
    """Write ``data`` as a new run file under ``results/runs``; returns its path."""
    folder = runs_dir(results)
    folder.mkdir(parents=True, exist_ok=True)
    while True:
        stem = new_stem(prefix=PREFIX)
        path = folder / f"{stem}.json"
        if not path.exists():
            break
    data["rtc"]["stem"] = stem
    write_new_file(path, json.dumps(data, indent=1) + "\n")
    return path


def list_runs(results: Path) -> list[Path]:
    """Every stability run file, oldest first (their names sort by time)."""
    folder = runs_dir(results)
    return sorted(folder.glob(f"{PREFIX}*.json")) if folder.is_dir() else []


def load_run(path: Path) -> dict[str, Any]:
    """A stability run's ``rtc`` section; ``ResultFileError`` naming the file if unreadable."""
    try:
        data = json.loads(read_text(path, MAX_RUN_FILE_BYTES))
    except OSError as error:  # a named pipe, a device, a file too large ...
        raise ResultFileError(
            f"{path}: cannot read the stability result: {error.strerror or error}"
        ) from None
    except (ValueError, RecursionError) as error:  # JSON's, UTF-8's, a huge integer
        raise ResultFileError(f"{path}: cannot read the stability result: {error}") from None
    rtc = data.get("rtc") if isinstance(data, dict) else None
    if not isinstance(rtc, dict) or rtc.get("kind") != KIND:
        raise ResultFileError(f"{path}: not an rtc stability result (no 'rtc' of kind {KIND!r})")
    version = rtc.get("schema_version")
    if version != SCHEMA_VERSION:
        raise ResultFileError(
            f"{path}: stability schema version {version!r}; this harness reads {SCHEMA_VERSION}"
        )
    verdicts = {v.value for v in Verdict}
    for row in rtc.get("results", []):
        if row.get("verdict") not in verdicts:
            raise ResultFileError(f"{path}: unknown verdict {row.get('verdict')!r}")
    rtc.setdefault("stem", path.stem)
    return rtc


def is_partial(run: dict[str, Any]) -> bool:
    """Whether ``run`` covered only some cases (``--cases``) or variants (``--variants``)."""
    settings = run.get("settings") or {}
    return bool(settings.get("cases")) or settings.get("variants", "all") != "all"


def latest_run(results: Path) -> tuple[dict[str, Any] | None, list[str]]:
    """The newest readable stability run over every case and variant, else the newest
    readable one (a run over a few cases never replaces the whole table), or None; and a
    message per unreadable one."""
    problems: list[str] = []
    fallback = None
    for path in reversed(list_runs(results)):
        try:
            run = load_run(path)
        except ResultFileError as error:
            problems.append(str(error))
            continue
        if not is_partial(run):
            return run, problems
        fallback = fallback or run
    return fallback, problems
