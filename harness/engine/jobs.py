"""Running a measurement job in a fresh process (``harness.engine.child``) and reading its results.

The measuring process gets ``NUMBA_NRT_STATS=1`` (numba counts its allocations),
``NUMBA_NUM_THREADS`` when ``--threads`` is given, and the worker hook folder on
``PYTHONPATH`` (worker processes count their allocations, see ``harness.instruments.alloccount``).

It runs in a session of its own, so Ctrl-C in the terminal reaches ``rtc bench`` alone: the
parent then stops the child's whole process group (the child and any pool workers it
started) with SIGTERM, and says once that it was interrupted; no child prints a traceback.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import traceback
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from harness.engine.lifeline import watch_parent
from harness.instruments.alloccount import WORKER_HOOK_PATH


@dataclass
class JobOutcome:
    """What a job returned: ``result`` (the child's JSON) and where its images are."""

    folder: Path
    result: dict[str, Any]

    @property
    def ok(self) -> bool:
        return "error" not in self.result

    def image(self, name: str) -> np.ndarray:
        return np.asarray(np.load(self.folder / name))

    def discard(self) -> None:
        shutil.rmtree(self.folder, ignore_errors=True)


def child_environment(threads: int | None) -> dict[str, str]:
    env = dict(os.environ)
    env["NUMBA_NRT_STATS"] = "1"
    if threads:
        env["NUMBA_NUM_THREADS"] = str(threads)
    paths = [WORKER_HOOK_PATH, *filter(None, env.get("PYTHONPATH", "").split(os.pathsep))]
    env["PYTHONPATH"] = os.pathsep.join(paths)
    env.pop("RTC_ALLOCCOUNT_DIR", None)
    return env


STOP_SECONDS = 5.0  # how long a stopped child's group gets to exit before SIGKILL
CANNOT_WRITE = 74  # a measuring process's exit status when it cannot write (sysexits EX_IOERR)
DISK_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG, errno.EIO)
"""What a write fails with when the disk, not the job, is at fault: the bench stops."""


def disk_error(error: BaseException) -> bool:
    """Whether ``error`` is a write the disk refused (full, read-only, over quota)."""
    return isinstance(error, OSError) and error.errno in DISK_ERRORS


def write_result(folder: Path, outcome: Mapping[str, Any], name: str = "result.json") -> int:
    """A measuring process's last act: ``outcome`` written atomically as ``folder/name``;
    0, or ``CANNOT_WRITE`` with one line on stderr when the disk refuses it (the parent
    then stops the bench: ``run_in_child``)."""
    temporary = folder / f".{name}.tmp"
    try:
        temporary.write_text(json.dumps(outcome))
        os.replace(temporary, folder / name)
    except OSError as error:
        with contextlib.suppress(OSError):
            temporary.unlink(missing_ok=True)
        print(
            f"  measuring process: cannot write its result in {folder}: "
            f"{error.strerror or error}",
            file=sys.stderr,
            flush=True,
        )
        return CANNOT_WRITE
    return 0


def start_child(command: list[str], env: Mapping[str, str], **popen: Any) -> subprocess.Popen[Any]:
    """``command`` started in a new session (its own process group; see the module)."""
    return subprocess.Popen(command, env=dict(env), start_new_session=True, **popen)


def stop_group(process: subprocess.Popen[Any]) -> None:
    """Stop ``process`` and everything in its process group: SIGTERM, then SIGKILL for
    whatever is left after ``STOP_SECONDS``."""
    for how in (signal.SIGTERM, signal.SIGKILL):
        with contextlib.suppress(ProcessLookupError, PermissionError):  # gone already
            os.killpg(process.pid, how)
        try:
            process.wait(timeout=STOP_SECONDS)
            return
        except subprocess.TimeoutExpired:
            continue


def wait_child(process: subprocess.Popen[Any]) -> int:
    """``process``'s exit code; if we are interrupted meanwhile (Ctrl-C, SIGTERM), its
    process group is stopped first and the interrupt goes on."""
    try:
        return process.wait()
    except BaseException:
        stop_group(process)
        raise


def run_in_child(
    module: str, folder: Path, job: Mapping[str, Any], threads: int | None
) -> dict[str, Any] | int:
    """Write ``job`` into ``folder`` (created) and run ``python -m MODULE folder/job.json``
    in a fresh process pinned to ``threads``; its ``result.json``, or its exit code when it
    wrote none. The child's progress goes to our stderr; an interrupt stops it (and its
    process group) too."""
    folder.mkdir(parents=True)
    job_path = folder / "job.json"
    job_path.write_text(json.dumps(job))
    process = start_child([sys.executable, "-m", module, str(job_path)], child_environment(threads))
    code = wait_child(process)
    if code == CANNOT_WRITE:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(folder))  # said there
    result_path = folder / "result.json"
    if result_path.exists():
        result: dict[str, Any] = json.loads(result_path.read_text())
        if result.get("disk"):  # the job failed writing: the disk, not the variant
            raise OSError(errno.ENOSPC, str(result["disk"]), str(folder))
        return result
    return code


def run_job(folder: Path, job: Mapping[str, Any]) -> JobOutcome:
    """Run one job of ``harness.engine.child`` in ``folder`` (created)."""
    result = run_in_child("harness.engine.child", folder, job, job.get("threads"))
    if isinstance(result, int):
        result = {"variant": job["variant"], "error": f"the measuring process exited with {result}"}
    return JobOutcome(folder, result)


def job_main(run: Callable[[dict[str, Any], Path], dict[str, Any]], argv: list[str]) -> int:
    """The body of a section's measuring process (``python -m harness.MODULE JOB.json``):
    read the job, exit when the parent dies, ``run(job, folder)``, and write its result (or
    ``{"error": ..., "traceback": ...}`` when it raised: one failed point, reported in the
    run file) atomically as ``result.json`` beside the job."""
    job_path = Path(argv[0])
    job = json.loads(job_path.read_text())
    watch_parent()
    try:
        result = run(job, job_path.parent)
    except Exception as error:
        result = {"error": f"{type(error).__name__}: {error}", "traceback": traceback.format_exc()}
        if disk_error(error):
            result["disk"] = f"{getattr(error, 'strerror', None) or error}"
    return write_result(job_path.parent, result)
