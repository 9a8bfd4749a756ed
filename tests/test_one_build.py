"""A compiled library is built once, however many processes need it at the same time (the
gate's test workers, a bench's children): ``compiled.library.one_builder``, a lock per
library in the kernel folder. The test holds the lock itself until both processes are
waiting for it (``/proc/locks``), so that they certainly meet; then one builds and the
other loads what it built. The book API's entry points take such a lock (one each) on their
first call in a process (``variants.numba.specialize``)."""

from __future__ import annotations

import dataclasses
import fcntl
import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
from holding import HANG_SECONDS
from test_hostile import TINY

from compiled import compile_log, library
from variants.numba import specialize

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
LOAD = (  # the recipe's fields as JSON in argv[1]
    "import json, sys\n"
    "import numpy as np\n"
    "from compiled import library\n"
    "compiled = library.load(library.Recipe(**json.loads(sys.argv[1])))\n"
    "src, dst = np.arange(4.0), np.zeros(4)\n"
    "compiled.function(4, src, dst, 2.0)\n"
    "print(compiled.origin.split()[:2], dst.tolist())\n"
)


def waiting_for(lock: Path) -> int:
    """How many processes wait for the ``flock`` on ``lock`` (``/proc/locks``: a waiter's
    line has ``->``)."""
    inode = f":{os.stat(lock).st_ino} "
    with open("/proc/locks", encoding="utf-8") as locks:
        return sum(1 for line in locks if "->" in line and inode in line + " ")


@pytest.mark.skipif(not Path("/proc/locks").exists(), reason="needs Linux's /proc/locks")
def test_two_processes_that_need_a_library_build_it_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder, log = tmp_path / "kernels", tmp_path / "compiles.jsonl"
    folder.mkdir(mode=0o700)
    monkeypatch.setenv("RTC_NUMBA_KERNELS", str(folder))
    path = TINY.path()
    lock = folder / f".{path.stem}.lock"
    environment = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(TESTS), str(ROOT)]),
        "RTC_COMPILE_LOG": str(log),
    }
    with library.one_builder(path, "the test kernel"):
        children = [
            subprocess.Popen(
                [sys.executable, "-c", LOAD, json.dumps(dataclasses.asdict(TINY))],
                cwd=ROOT,
                env=environment,
                text=True,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
            )
            for _ in range(2)
        ]
        give_up = time.monotonic() + HANG_SECONDS
        while waiting_for(lock) < 2:
            assert all(child.poll() is None for child in children), "a process ended early"
            assert time.monotonic() < give_up, "hang guard: the processes never reached the lock"
            time.sleep(0.05)
    outputs = [child.communicate(timeout=HANG_SECONDS) for child in children]
    for child, (out, err) in zip(children, outputs, strict=True):
        assert child.returncode == 0, err
        assert out.strip() == "['shared', 'library'] [0.25, 2.25, 4.25, 6.25]", (out, err)
    lines = [json.loads(line) for line in log.read_text(encoding="utf-8").splitlines()]
    builds = [line for line in lines if line["kind"] == "library"]
    assert [line["what"] for line in builds] == ["the test kernel"], lines
    assert {line["pid"] for line in lines} == {child.pid for child in children}, lines


def test_an_entry_point_s_first_call_holds_the_lock_and_later_ones_do_not(
    tmp_path: Path,
) -> None:
    module = tmp_path / "rtc_numba_example.py"
    lock = tmp_path / ".rtc_numba_example.api_example.lock"  # one lock per entry point
    held: list[bool] = []

    def locked() -> bool:
        fd = os.open(lock, os.O_RDWR)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        finally:
            os.close(fd)
        return False

    def api_example(x: int) -> int:
        held.append(locked())
        return 2 * x

    calls = specialize._locked_first_call(_Dispatcher(api_example), module)
    assert [calls(1), calls(2), calls(3)] == [2, 4, 6]
    assert held == [True, False, False]


class _Dispatcher:
    """A stand-in for a numba dispatcher: its ``py_func``, called."""

    def __init__(self, function: Any) -> None:
        self.py_func = function

    def __call__(self, *arguments: Any) -> Any:
        return self.py_func(*arguments)


def test_the_compile_log_says_whether_a_repeated_compile_was_in_one_folder() -> None:
    def line(pid: int, folder: str | None) -> dict[str, Any]:
        found = {"kind": "library", "what": "k", "wall": 2.0, "cpu": 1.0, "start": 0.0,
                 "pid": pid, "test": "t"}  # fmt: skip
        return found if folder is None else {**found, "folder": folder}

    def again(*lines: dict[str, Any]) -> list[str]:
        return [text for text in compile_log.summary(list(lines)) if "again," in text]

    assert again(line(1, "/a"), line(2, "/a")) == ["  again, in one kernel folder: 2x k"]
    assert again(line(1, "/a"), line(2, "/b")) == ["  again, in 2 kernel folders: 2x k"]
    assert again(line(1, None), line(2, "/a")) == ["  again, kernel folder not logged: 2x k"]
    assert again(line(1, "/a")) == []
