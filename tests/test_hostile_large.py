"""Hostile input, fourth round (issue 37): input far larger than ours is refused in one line,
before it is walked.

- ``rtc report`` over a run file of more than 100,000 rows (17 MB): it cost about 15 ms a
  row (25 minutes); now the file is skipped with one line naming it and its count, and the
  other runs are reported (``harness.engine.results.MAX_ROWS``).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from harness.engine.results import MAX_ROWS
from harness.report.build import load_history

ROOT = Path(__file__).resolve().parent.parent
HUGE = "bench-20250102T000000000Z-bbbbbb.json"


@pytest.mark.parametrize("key", ["rows", "series"])
def test_a_run_of_more_than_100000_rows_is_skipped_in_one_line(tmp_path: Path, key: str) -> None:
    runs = tmp_path / "results" / "runs"
    runs.mkdir(parents=True)
    good = sorted((ROOT / "results" / "runs").glob("bench-*.json"))[0]  # a committed run
    shutil.copy(good, runs / good.name)
    data = json.loads(good.read_text(encoding="utf-8"))
    data["rtc"]["stem"] = HUGE.removesuffix(".json")
    one = {"section": "table", "name": "naive", "status": "skipped"}  # about 17 MB in all
    data["rtc"][key] = [dict(one, name=f"naive-{i}") for i in range(100_001)]
    (runs / HUGE).write_text(json.dumps(data), encoding="utf-8")
    assert MAX_ROWS < 100_001
    kept, problems = load_history(tmp_path / "results")  # what rtc report reads
    assert [run["stem"] for run in kept] == [good.stem]
    assert problems == [
        f"{runs / HUGE}: {key}: 100,001 of them, more than a run of this project holds "
        f"({MAX_ROWS:,})"
    ]
