"""A background-compile job for ``tests/test_harness_bench.py``: ``python -m tests.warm_probe
JOB.json``. With ``"wait"``, it waits until the file ``"wait"`` names exists (at most
``"longest"`` seconds); with ``"make"``, it writes the file ``"make"`` names. It records what
happened in ``"record"``, a line per job (the maker's before its file exists, so the order
of the lines is certain)."""

import json
import sys
import time
from pathlib import Path


def main(argv: list[str]) -> int:
    job = json.loads(Path(argv[0]).read_text())
    record = Path(job["record"])
    if "make" in job:
        # the line first, then the file: the waiting job's line can only come after this one
        note(record, f"{job['name']} made")
        Path(job["make"]).touch()
        return 0
    give_up = time.monotonic() + float(job["longest"])
    while not Path(job["wait"]).exists() and time.monotonic() < give_up:
        time.sleep(0.02)
    outcome = "released" if Path(job["wait"]).exists() else "gave up"
    note(record, f"{job['name']} {outcome}")
    return 0


def note(record: Path, line: str) -> None:
    with record.open("a", encoding="utf-8") as out:
        out.write(line + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
