#!/usr/bin/env python3
"""Set up the project in ./.venv if needed, then run one of its jobs.

    python3 run.py bench   # quick benchmark of the reference scene, writes results/README.md
    python3 run.py test    # every feature for every variant, the unit tests (on every core),
                           # ruff and mypy
    python3 run.py rtc ARGS...   # any rtc command inside the environment

Needs only Python 3.11 or newer. The environment is (re)built when pyproject.toml or the
C extension's sources (setup.py, harness/_alloccount.c) change.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
STAMP = VENV / "installed-from.sha256"
BUILD_INPUTS = ("pyproject.toml", "setup.py", "harness/_alloccount.c")  # a change reinstalls


def _wanted_stamp() -> str:
    digest = hashlib.sha256()
    for name in BUILD_INPUTS:
        path = ROOT / name
        digest.update(path.read_bytes() if path.exists() else b"")
    return digest.hexdigest()


def ensure_environment() -> None:
    """Create .venv and install the project (editable, with dev tools) unless already current."""
    if STAMP.exists() and STAMP.read_text().strip() == _wanted_stamp():
        return
    if not (BIN / "python").exists():
        print("run.py: creating .venv", flush=True)
        venv.EnvBuilder(with_pip=True).create(VENV)
    print("run.py: installing the project and its dependencies into .venv", flush=True)
    subprocess.run(
        [str(BIN / "python"), "-m", "pip", "install", "--quiet", "--upgrade", "pip"], check=True
    )
    subprocess.run(
        [str(BIN / "python"), "-m", "pip", "install", "--quiet", "-e", f"{ROOT}[dev]"], check=True
    )
    STAMP.write_text(_wanted_stamp())


def _run(*argv: str) -> int:
    print("run.py: $", " ".join(argv), flush=True)
    return subprocess.run(list(argv), cwd=ROOT).returncode


def bench(extra: list[str]) -> int:
    code = _run(str(BIN / "rtc"), "bench", "--quick", *extra)
    if code == 0:
        code = _run(str(BIN / "rtc"), "report")
    return code


NO_TESTS_SELECTED = 5  # pytest's exit status when no test matched


def _marks_serial_tests() -> bool:
    """Whether a test module marks a test ``serial`` (a text search, which saves collecting
    the suite twice when none does: a mark it missed would only run in parallel, never be
    left out)."""
    return any(
        "mark.serial" in path.read_text(encoding="utf-8") for path in (ROOT / "tests").rglob("*.py")
    )


def test(extra: list[str]) -> int:
    """The suite on every core (pytest-xdist), then ruff and mypy. The tests marked
    ``serial`` (they cannot share the machine; none is, today) run first, alone, in one
    process; then the others on a worker process per core, ``worksteal`` handing a worker
    that is done tests from another's queue. ``extra`` goes to both passes."""
    pytest = [str(BIN / "python"), "-m", "pytest", "--variant", "all"]
    parallel = [*pytest, "--numprocesses", "auto", "--dist", "worksteal"]
    worst = 0
    if _marks_serial_tests():
        worst = _run(*pytest, "-m", "serial", "-p", "no:xdist", *extra)
        if worst == NO_TESTS_SELECTED:  # none among those ``extra`` picks
            worst = 0
        parallel += ["-m", "not serial"]
    steps = [
        [*parallel, *extra],
        [str(BIN / "ruff"), "check", "."],
        [str(BIN / "mypy")],
    ]
    for argv in steps:
        worst = max(worst, _run(*argv))
    return worst


def main(argv: list[str]) -> int:
    if not argv or argv[0] not in {"bench", "test", "rtc"}:
        print(__doc__)
        return 2
    ensure_environment()
    job, extra = argv[0], argv[1:]
    if job == "bench":
        return bench(extra)
    if job == "test":
        return test(extra)
    return _run(str(BIN / "rtc"), *extra)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
