"""Faults leave one line and nothing behind (issue 19): Ctrl-C during ``rtc bench`` and
``rtc render``, a killed parent of a pooled render, a stopped pool worker (found by its
missing heartbeat), and two benches sharing the machine (noted in the run file and the
report). The signals are sent to real processes, as a terminal would."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections import deque
from collections.abc import Iterator
from multiprocessing import Pipe
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from harness import sharing
from harness.results import list_runs, load_run
from variants.pooled import HEARTBEAT_SECONDS, RenderWorkerError, _Pool, _Worker

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "harness" / "scenes" / "reference.yml"
BENCH = ["bench", "--scene", "default-world", "--variants", "naive", "--sections", "table",
         "--budget", "0"]  # fmt: skip


def start(*argv: str, locks: Path | None = None) -> subprocess.Popen[str]:
    """``python -m rtc.cli ARGV`` in a session of its own, as a terminal runs a command: a
    signal to its group (``os.killpg``) is what Ctrl-C sends. ``locks``: the benches'
    machine-wide lock folder (so that benches other tests run meanwhile stay unseen)."""
    env = dict(os.environ)
    if locks is not None:
        env["RTC_BENCH_LOCK_DIR"] = str(locks)
    return subprocess.Popen(
        [sys.executable, "-m", "rtc.cli", *argv], cwd=ROOT, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, start_new_session=True, env=env,
    )  # fmt: skip


def children(pid: int) -> list[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(p) for p in text.split()]


def workers_of(pid: int) -> list[int]:
    """The pool workers (multiprocessing's spawned processes) among ``pid``'s children."""
    found = []
    for child in children(pid):
        try:
            if b"spawn_main" in Path(f"/proc/{child}/cmdline").read_bytes():
                found.append(child)
        except OSError:
            continue
    return found


def wait_for(test: Any, seconds: float, what: str) -> Any:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        found = test()
        if found:
            return found
        time.sleep(0.05)
    raise AssertionError(f"waited {seconds} s for {what}")


def beating(pids: list[int]) -> bool:
    """Whether every worker in ``pids`` has started its heartbeat thread (its first beat is
    sent just before: the parent has heard from it, so its startup allowance is over)."""
    try:
        return all(len(os.listdir(f"/proc/{pid}/task")) >= 2 for pid in pids)
    except OSError:
        return False


def gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return True
    return state == "Z"  # a zombie has exited; only its parent's wait is missing


def no_traceback(text: str) -> None:
    for word in ("Traceback", "KeyboardInterrupt", "BrokenPipeError", "Error:"):
        assert word not in text, text


@pytest.fixture
def stop_leftovers() -> Iterator[list[subprocess.Popen[str]]]:
    """Processes a test started; whatever is still running afterwards is killed."""
    started: list[subprocess.Popen[str]] = []
    yield started
    for process in started:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


# ------------------------------------------------------------------ Ctrl-C


def test_ctrl_c_during_rtc_bench_is_one_line_and_leaves_no_run(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    bench = start(*BENCH, "--size", "40x30", "--repeat", "50", "--results-dir", str(tmp_path))
    stop_leftovers.append(bench)

    def measuring_process() -> list[int]:
        return [c for c in children(bench.pid)
                if b"harness.child" in Path(f"/proc/{c}/cmdline").read_bytes()]  # fmt: skip

    measuring = wait_for(measuring_process, 60, "the measuring process")
    time.sleep(0.5)  # into its renders
    os.killpg(bench.pid, signal.SIGINT)
    out, err = bench.communicate(timeout=30)
    assert bench.returncode == 130
    no_traceback(err)
    assert err.splitlines()[-1] == "rtc bench: interrupted"
    assert all(line.startswith(("rtc bench [", "  [naive]")) for line in err.splitlines()[:-1])
    assert out == "" and list_runs(tmp_path) == []
    assert [p.name for p in (tmp_path / "runs").iterdir()] == []  # staging and lock removed
    wait_for(lambda: all(gone(pid) for pid in measuring), 10, "the measuring process to end")


def test_a_measuring_process_sent_sigint_itself_exits_quietly(tmp_path: Path) -> None:
    job = {
        "variant": "naive", "scene": {"name": "default-world", "path": None}, "depth": 5,
        "seed": 0, "epsilon": None, "threads": None,
        "tasks": [{"kind": "row", "size": [40, 30], "samples": 1, "repeat": 50,
                   "budget": None, "compare_size": None}],
    }  # fmt: skip
    (tmp_path / "job.json").write_text(json.dumps(job))
    child = subprocess.Popen(
        [sys.executable, "-m", "harness.child", str(tmp_path / "job.json")], cwd=ROOT,
        stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    time.sleep(2.0)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=30)
    assert child.returncode == 130
    no_traceback(err)
    assert not (tmp_path / "result.json").exists()


@pytest.mark.parametrize("variant", ["naive", "pooled[workers=2]:cached"])
def test_ctrl_c_during_rtc_render_is_one_line_and_writes_no_image(
    variant: str, tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    output = tmp_path / "out.png"
    render = start("render", str(REFERENCE), "--variant", variant, "--size", "64x48",
                   "-o", str(output))  # fmt: skip
    stop_leftovers.append(render)
    assert render.stdout is not None
    assert render.stdout.readline().startswith("rendering ")  # it is rendering
    if variant.startswith("pooled"):  # at once: while the workers' interpreters start
        pool = wait_for(lambda: workers_of(render.pid), 30, "the workers")
    os.killpg(render.pid, signal.SIGINT)
    out, err = render.communicate(timeout=30)
    assert render.returncode == 130
    assert err == "rtc render: interrupted\n"
    assert out == "" and not output.exists()
    if variant.startswith("pooled"):
        wait_for(lambda: all(gone(pid) for pid in pool), 5, "the workers to end")


# ------------------------------------------------------------------ a pooled render's faults


def test_killing_the_parent_of_a_pooled_render_leaves_no_traceback(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    render = start("render", str(REFERENCE), "--variant", "pooled[workers=2]:cached",
                   "--size", "64x48", "-o", str(tmp_path / "out.png"))  # fmt: skip
    stop_leftovers.append(render)
    pool = wait_for(lambda: len(workers_of(render.pid)) == 2 and workers_of(render.pid), 30,
                    "two workers")  # fmt: skip
    time.sleep(0.5)  # the workers are tracing
    render.kill()
    killed = time.monotonic()
    assert render.stderr is not None
    err = render.stderr.read()  # to its end: every worker (which shares it) has exited
    waited = time.monotonic() - killed
    render.wait()
    no_traceback(err)
    assert err == ""
    assert waited < 3, f"the workers outlived their parent by {waited:.1f} s"
    wait_for(lambda: all(gone(pid) for pid in pool), 5, "the workers to end")
    assert not (tmp_path / "out.png").exists()


def test_a_stopped_worker_fails_the_render_within_its_timeout(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    """The heartbeat: a SIGSTOPped worker sends nothing; the render fails within the
    ``timeout`` (1 s here; 10 s by default) plus one check interval, naming the worker."""
    output = tmp_path / "out.png"
    render = start("render", str(REFERENCE), "--variant", "pooled[workers=2,timeout=1]:cached",
                   "--size", "64x48", "-o", str(output))  # fmt: skip
    stop_leftovers.append(render)
    pool = wait_for(lambda: len(workers_of(render.pid)) == 2 and workers_of(render.pid), 30,
                    "two workers")  # fmt: skip
    wait_for(lambda: beating(pool), 30, "the workers' heartbeats")
    time.sleep(0.2)
    os.kill(pool[0], signal.SIGSTOP)
    stopped = time.monotonic()
    out, err = render.communicate(timeout=30)
    detected = time.monotonic() - stopped
    assert render.returncode == 2
    (line,) = err.splitlines()
    assert line.startswith(
        "rtc render: pooled[timeout=1,workers=2]:cached could not render "
        f"{REFERENCE}: pooled render: worker 0 (pid {pool[0]}) sent no heartbeat for "
    )
    assert "(the limit is 1 s: pooled[timeout=T])" in line
    assert "it is stopped (a SIGSTOP, Ctrl-Z or a debugger)" in line
    assert line.endswith("jobs were done; no image is returned")
    # silence is counted from the last beat, up to one beat interval before the stop
    assert 1.0 - 2 * HEARTBEAT_SECONDS <= detected < 3.0, f"detected after {detected:.2f} s"
    assert not output.exists() and "rendered in" not in out
    wait_for(lambda: all(gone(pid) for pid in pool), 5, "the workers (the stopped one too)")


def test_a_ctrl_c_while_a_worker_starts_is_held_back_not_lost() -> None:
    from variants.pooled import sigint_blocked

    reached = []
    with pytest.raises(KeyboardInterrupt):
        with sigint_blocked():
            os.kill(os.getpid(), signal.SIGINT)  # a worker started now inherits the block
            blocked = signal.pthread_sigmask(signal.SIG_BLOCK, set())
            if threading.active_count() == 1:  # no other thread can take it: it waits
                time.sleep(0.05)
                reached.append(signal.SIGINT in blocked)
        time.sleep(0.05)  # delivered by now, to our own handler
    assert reached in ([], [True])


def _worker(conn: Any, *, heard_ago: float, held: int = 1) -> _Worker:
    process = SimpleNamespace(pid=os.getpid())  # a running process: ours
    worker = _Worker(0, process, conn, deque(range(held)), time.monotonic() - heard_ago)
    worker.talked = True
    return worker


def test_the_heartbeat_check_blames_silence_not_unread_messages() -> None:
    pool = _Pool.__new__(_Pool)  # no processes: only the check
    pool.timeout = 1.0
    jobs = [(0, 0, 4, 1)]
    ours, theirs = Pipe()
    try:
        pool._check_heard(_worker(ours, heard_ago=0.5), jobs, 1)  # within the limit
        theirs.send(("beat", -1, None))  # said something we have not read yet (we were busy)
        pool._check_heard(_worker(ours, heard_ago=30.0), jobs, 1)
        ours.recv()
        with pytest.raises(RenderWorkerError) as error:
            pool._check_heard(_worker(ours, heard_ago=30.0), jobs, 1)
        message = str(error.value)
        assert f"worker 0 (pid {os.getpid()}) sent no heartbeat for 30" in message
        assert "while holding job 0 (line 0)" in message
        assert "it is frozen or starved of CPU; 0 of 1 jobs were done" in message
        quiet = _worker(ours, heard_ago=30.0)
        quiet.talked = False  # before its first word: the startup allowance
        pool._check_heard(quiet, jobs, 1)
    finally:
        ours.close()
        theirs.close()


# ------------------------------------------------------------------ two benches at once


def test_two_benches_at_once_each_note_the_other_and_the_report_shows_it(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    locks = tmp_path / "machine-locks"
    first = start(*BENCH, "--size", "8x6", "--repeat", "60", "--results-dir", str(tmp_path),
                  locks=locks)  # fmt: skip
    stop_leftovers.append(first)
    lock = tmp_path / "runs" / f".bench-{first.pid}.lock"
    wait_for(lock.exists, 30, "the first bench's lock file")
    second = start(*BENCH, "--size", "8x6", "--repeat", "1", "--results-dir", str(tmp_path),
                   locks=locks)  # fmt: skip
    stop_leftovers.append(second)
    for bench in (first, second):
        _, err = bench.communicate(timeout=120)
        assert bench.returncode == 0, err
        assert "rtc bench [" in err and "the machine was shared: another `rtc bench`" in err
    runs = [load_run(path)["rtc"] for path in list_runs(tmp_path)]
    assert len(runs) == 2
    for run, other in zip(runs, (second, first), strict=True):
        load = run["load"]
        assert [o["pid"] for o in load["other_benches"]] == [other.pid]
        assert len(load["start"]) == len(load["end"]) == 3 and load["peak"] >= load["start"][0]
        assert load["cores"] >= 1 and 0 < load["cpu_share"] < 64
        assert run["shared"].startswith(
            f"another `rtc bench` ran at the same time: pid {other.pid}"
        )
    assert list((tmp_path / "runs").glob(".bench-*")) == list(locks.iterdir()) == []  # released
    report = subprocess.run([sys.executable, "-m", "rtc.cli", "report", "--results-dir",
                             str(tmp_path)], cwd=ROOT, capture_output=True, text=True)  # fmt: skip
    assert report.returncode == 0 and report.stderr == ""
    readme = (tmp_path / "README.md").read_text(encoding="utf-8")
    assert (
        f"**Shared machine:** another `rtc bench` ran at the same time: pid {first.pid}" in readme
    )


def test_the_note_follows_the_load_and_the_other_benches() -> None:
    quiet = {"cores": 2, "start": [1.5, 1, 1], "end": [1.9, 1, 1], "peak": 2.0,
             "cpu_share": 0.97, "other_benches": []}  # fmt: skip
    assert sharing.shared_note(quiet) is None  # at most the cores the run used: its own load
    busy = {**quiet, "peak": 3.42, "end": [3.1, 2, 1]}
    note = sharing.shared_note(busy)
    assert note == (
        "the 1-minute load average reached 3.42 with 2 cores in use by this run (1.50 at the "
        "start, 3.10 at the end); the run's processes got 0.97 cores on average. Other work "
        "shared the machine: these timings are slower than the machine alone would give; "
        "measure again on a quiet machine to compare."
    )
    assert sharing.brief(busy) == "load average up to 3.42 on 2 cores"
    other = {**quiet, "other_benches": [{"pid": 42, "started": "2026-01-01T00:00:00+00:00"}]}
    assert (sharing.shared_note(other) or "").startswith(
        "another `rtc bench` ran at the same time: pid 42 (started 2026-01-01T00:00:00+00:00)"
    )
    assert sharing.brief(other) == "another rtc bench running"


def test_a_stale_lock_is_removed_and_no_lock_is_waited_on(tmp_path: Path) -> None:
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    runs = tmp_path / "runs"
    runs.mkdir()
    stale = runs / f".bench-{dead.pid}.lock"
    stale.write_text("{}")
    alive = runs / f".bench-{os.getppid()}.lock"  # a live process: another bench, for us
    alive.write_text(json.dumps({"started": "then", "results": "elsewhere"}))
    started = time.monotonic()
    watch = sharing.Watch(tmp_path, cores=1, lock_dir=tmp_path / "machine")
    assert time.monotonic() - started < 1  # never blocks
    assert (runs / f".bench-{os.getpid()}.lock").exists()
    assert (tmp_path / "machine" / f".bench-{os.getpid()}.lock").exists()
    seen = watch.finish()
    assert not stale.exists() and alive.exists()
    assert seen["load"]["other_benches"] == [
        {"pid": os.getppid(), "started": "then", "results": "elsewhere"}
    ]
    assert seen["shared"] is not None and f"pid {os.getppid()} (started then)" in seen["shared"]
    assert not (runs / f".bench-{os.getpid()}.lock").exists()


def test_the_timeout_is_spelled_in_the_name_only_when_it_is_not_the_default() -> None:
    from variants.registry import load_variant

    assert load_variant("pooled[workers=2,timeout=3]").name == "pooled[timeout=3,workers=2]:naive"
    assert load_variant("pooled[workers=2,timeout=10]").name == "pooled[workers=2]:naive"
    tracer = load_variant("pooled[workers=2,timeout=3]:cached").tracer
    assert getattr(tracer, "timeout", None) == 3
