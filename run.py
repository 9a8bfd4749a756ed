#!/usr/bin/env python3
"""Set up the project in ./.venv if needed, then run one of its jobs.

    python3 run.py bench   # the optimizations step by step, quickly: results/local/README.md
    python3 run.py bench --full      # every section (minutes); --publish: the committed results/
    python3 run.py test    # every feature for every variant, the unit tests (on every core),
                           # ruff, the import contracts (lint-imports) and mypy
    python3 run.py test --thorough   # the same, deeper (docs/contributing.md)
    python3 run.py rtc ARGS...   # any rtc command inside the environment
    python3 run.py upgrade       # newer dependencies: rewrite constraints.txt (see below)

Needs only Python 3.11 or newer. The environment is (re)built when pyproject.toml,
constraints.txt or the C extension's sources (setup.py, harness/instruments/_alloccount.c) change.
Every package is installed at the version constraints.txt pins, so that a new release of a
dependency (hypothesis, numba, pytest ...) changes nothing until it is asked for: `upgrade`
installs the newest versions pyproject.toml allows into a scratch environment and writes
them to constraints.txt; the next `test` reinstalls .venv from it.
"""

from __future__ import annotations

import hashlib
import os
import queue
import subprocess
import sys
import tempfile
import threading
import time
import tomllib
import venv
from collections import deque
from pathlib import Path
from typing import IO

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
STAMP = VENV / "installed-from.sha256"
CONSTRAINTS = ROOT / "constraints.txt"
# a change reinstalls
BUILD_INPUTS = (
    "pyproject.toml", "constraints.txt", "setup.py", "harness/instruments/_alloccount.c",
)
STATUS_EVERY = 5.0  # seconds: while pip works, its latest line is shown at most this often
SILENT_EVERY = 10.0  # seconds between two lines saying that a quiet step (mypy) still runs


def _wanted_stamp() -> str:
    digest = hashlib.sha256()
    for name in BUILD_INPUTS:
        path = ROOT / name
        digest.update(path.read_bytes() if path.exists() else b"")
    return digest.hexdigest()


def _requirements() -> str:
    """What the install brings, from pyproject.toml: the dependencies' names, then the
    development tools'."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]

    def names(requirements: list[str]) -> str:
        return ", ".join(
            requirement.split(";")[0].split("[")[0].split(">")[0].split("=")[0].split("<")[0]
            .strip()
            for requirement in requirements
        )  # fmt: skip

    extras = project.get("optional-dependencies", {})
    dev = extras.get("dev", []) + extras.get("anchors", [])
    return f"{names(project['dependencies'])}; for the tests: {names(dev)}"


def _shorten(line: str, width: int = 110) -> str:
    return line if len(line) <= width else line[: width - 3] + "..."


def _relay(stream: IO[str], lines: queue.Queue[str | None]) -> None:
    for line in stream:
        lines.put(line.rstrip())
    lines.put(None)


def _pip(*args: str, python: Path = BIN / "python") -> None:
    """``pip ARGS`` in .venv (or ``python``'s environment), alive on screen: its warnings
    and errors as they come, its latest line every ``STATUS_EVERY`` seconds (a long download
    or unpacking included), how many packages it installed, and its last lines if it fails
    (SystemExit)."""
    command = [str(python), "-m", "pip", *args, "--disable-pip-version-check"]
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace"
    )
    assert process.stdout is not None
    lines: queue.Queue[str | None] = queue.Queue()
    threading.Thread(target=_relay, args=(process.stdout, lines), daemon=True).start()
    kept: deque[str] = deque(maxlen=40)
    start = shown = time.monotonic()
    latest = ""
    while True:
        try:
            line = lines.get(timeout=1.0)
        except queue.Empty:
            line = ""
        if line is None:
            break
        if line.strip():
            kept.append(line)
            latest = line.strip()
            if latest.startswith(("ERROR", "WARNING", "error:", "warning:")):
                print(f"run.py: pip: {latest}", flush=True)
            elif latest.startswith("Successfully installed"):
                count = len(latest.split()) - 2
                print(f"run.py: pip installed {count} package{'s' * (count != 1)}", flush=True)
                latest = ""
        now = time.monotonic()
        if latest and now - shown >= STATUS_EVERY:
            print(f"run.py: pip [{now - start:3.0f} s]: {_shorten(latest)}", flush=True)
            shown = now
    if process.wait() != 0:
        print("\n".join(["run.py: pip failed; its last lines:", *kept]), file=sys.stderr)
        raise SystemExit(process.returncode)


class _Ticker:
    """While a quiet step runs (venv's own pip install), a line saying so every
    ``STATUS_EVERY`` seconds: progress on the screen from the first second."""

    def __init__(self, what: str) -> None:
        self.what = what
        self.done = threading.Event()
        self.start = time.monotonic()

    def _tick(self) -> None:
        while not self.done.wait(STATUS_EVERY):
            print(f"run.py: {self.what}, {time.monotonic() - self.start:.0f} s so far", flush=True)

    def __enter__(self) -> None:
        threading.Thread(target=self._tick, daemon=True).start()

    def __exit__(self, *exc: object) -> None:
        self.done.set()


def ensure_environment() -> None:
    """Create .venv and install the project (editable, with dev tools and the anchors a
    benchmark sets beside its rows) unless already current."""
    if STAMP.exists() and STAMP.read_text().strip() == _wanted_stamp():
        return
    if not (BIN / "python").exists():
        print("run.py: creating .venv (Python's venv, with pip)", flush=True)
        with _Ticker("still creating .venv (installing pip into it)"):
            venv.EnvBuilder(with_pip=True).create(VENV)
    pinned = ["--constraint", str(CONSTRAINTS)] if CONSTRAINTS.exists() else []
    print("run.py: updating pip in .venv", flush=True)
    _pip("install", "--upgrade", "pip", *pinned)
    print(
        "run.py: installing the project (editable: your edits count at once) into .venv, "
        f"with what it needs: {_requirements()}, at the versions constraints.txt pins "
        "(a few minutes the first time)",
        flush=True,
    )
    # --no-compile: Python compiles each module when first imported, only those used, instead
    # of pip compiling every file of every package before anything runs (a minute or more)
    _pip("install", "--no-compile", *pinned, "-e", f"{ROOT}[dev,anchors]")
    STAMP.write_text(_wanted_stamp())


CONSTRAINTS_HEADER = """\
# The version of every package the project installs (run.py installs with --constraint):
# a new release changes nothing until `python3 run.py upgrade` rewrites this file from the
# newest versions pyproject.toml allows. Commit it once the gate passes with it.
"""


def upgrade() -> int:
    """Install the newest dependencies pyproject.toml allows into a scratch environment and
    write their versions to constraints.txt (the next job reinstalls .venv from it)."""
    with tempfile.TemporaryDirectory(prefix="rtc-upgrade-") as folder:
        print(f"run.py: a scratch environment in {folder}: the newest versions", flush=True)
        venv.EnvBuilder(with_pip=True).create(folder)
        python = Path(folder) / BIN.name / "python"
        _pip("install", "--upgrade", "pip", python=python)
        project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
        extras = project["optional-dependencies"]
        wanted = project["dependencies"] + extras["dev"] + extras["anchors"]
        _pip("install", *wanted, python=python)  # what the project needs, not the project
        frozen = subprocess.run(
            [str(python), "-m", "pip", "freeze", "--all", "--disable-pip-version-check"],
            capture_output=True, text=True, check=True,
        ).stdout.splitlines()  # fmt: skip
    pins = sorted((line for line in frozen if line.strip()), key=str.lower)
    CONSTRAINTS.write_text(CONSTRAINTS_HEADER + "\n".join(pins) + "\n", encoding="utf-8")
    print(f"run.py: wrote {len(pins)} versions to constraints.txt; git diff shows what changed")
    return 0


def _run(*argv: str, silent: str | None = None) -> int:
    """Run ``argv`` in the project's folder; its exit status. ``silent``: what the command
    does, for one that prints nothing until it ends (mypy): while it runs, a line says so
    every ``SILENT_EVERY`` seconds."""
    print("run.py: $", " ".join(argv), flush=True)
    with subprocess.Popen(list(argv), cwd=ROOT) as process:  # Ctrl-C: as subprocess.run
        start = time.monotonic()
        while True:
            try:
                return process.wait(timeout=None if silent is None else SILENT_EVERY)
            except subprocess.TimeoutExpired:
                print(f"run.py: {silent}, {time.monotonic() - start:.0f} s so far", flush=True)


def bench(extra: list[str]) -> int:
    """``rtc bench`` (quick unless ``--full`` is given) then ``rtc report``; ``--publish``
    (the committed results) goes to both."""
    mode = [] if "--full" in extra else ["--quick"]
    code = _run(str(BIN / "rtc"), "bench", *mode, *extra)
    if code == 0:
        code = _run(str(BIN / "rtc"), "report", *(["--publish"] if "--publish" in extra else []))
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
    """The suite on every core (pytest-xdist), then ruff, the import contracts (lint-imports,
    pyproject.toml's ``[tool.importlinter]``) and mypy. The tests marked
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
        [str(BIN / "lint-imports"), "--no-cache"],
    ]
    for argv in steps:
        worst = max(worst, _run(*argv))
    mypy = "mypy is still checking the types (it reports at the end)"
    return max(worst, _run(str(BIN / "mypy"), silent=mypy))


def main(argv: list[str]) -> int:
    if not argv or argv[0] not in {"bench", "test", "rtc", "upgrade"}:
        print(__doc__)
        return 2
    if argv[0] == "upgrade":
        return upgrade()
    ensure_environment()
    job, extra = argv[0], argv[1:]
    if job == "bench":
        return bench(extra)
    if job == "test":
        return test(extra)
    return _run(str(BIN / "rtc"), *extra)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
