"""A failing test is one failure in the gate's report, whatever its traceback holds
(``tests/tracebacks.py``): a traceback entry with no line number (which pytest itself cannot
format: an INTERNALERROR that ends the session, or under pytest-xdist a lost worker) and a
report whose formatting raises, each next to a passing test, in one process and on a worker."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from holding import HANG_SECONDS

TESTS = Path(__file__).resolve().parent

LINELESS = """
import sys, types

def test_lineless():
    error = AssertionError("a failure with a frame of no line")
    # an instruction offset past the code's end: no line, as where Python 3.11 has none
    raise error.with_traceback(types.TracebackType(None, sys._getframe(), 10**6, -1))

def test_passes():
    assert 1 + 1 == 2
"""

UNFORMATTABLE = """
import pytest

class Unformattable(pytest.Item):
    def runtest(self):
        raise AssertionError("a failure of its own")

    def repr_failure(self, excinfo):
        raise RuntimeError("its report cannot be formatted")

class Cases(pytest.File):
    def collect(self):
        yield Unformattable.from_parent(self, name="unformattable")

def pytest_collect_file(parent, file_path):
    if file_path.suffix == ".case":
        return Cases.from_parent(parent, path=file_path)
"""


@pytest.mark.parametrize("workers", [[], ["-n", "1"]], ids=["one process", "on a worker"])
def test_a_failure_pytest_cannot_format_is_one_failure(tmp_path: Path, workers: list[str]) -> None:
    (tmp_path / "test_lineless.py").write_text(LINELESS, encoding="utf-8")
    (tmp_path / "conftest.py").write_text(UNFORMATTABLE, encoding="utf-8")
    (tmp_path / "one.case").write_text("", encoding="utf-8")
    environment = {**os.environ, "PYTHONPATH": str(TESTS)}
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "tracebacks", "-p", "no:cacheprovider", "-rf",
         *workers],
        cwd=tmp_path, capture_output=True, text=True, env=environment, timeout=HANG_SECONDS,
    )  # fmt: skip
    out = done.stdout + done.stderr
    assert "INTERNALERROR" not in out, out
    assert done.returncode == 1, out
    assert "2 failed, 1 passed" in out, out
    assert "AssertionError: a failure with a frame of no line" in out, out
    assert "FAILED one.case::unformattable - AssertionError: a failure of its own" in out, out
    assert "pytest could not format this failure's traceback" in out, out
