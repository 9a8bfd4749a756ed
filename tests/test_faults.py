"""Faults leave one line and nothing behind (issue 19): Ctrl-C during ``rtc bench`` and
``rtc render``, a killed parent of a pooled render, a stopped pool worker (found by its
missing heartbeat), and two benches sharing the machine (noted in the run file and the
report). The signals are sent to real processes, as a terminal would."""

from __future__ import annotations

import json
import os
import re
import select
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
from holding import HANG_SECONDS, Hold

from harness.engine import sharing
from harness.engine.results import list_runs, load_run
from variants.pooled import HEARTBEAT_SECONDS, RenderWorkerError, _Link, _Pool, _Worker

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "scenes" / "reference.yml"
# a bench of the held variant (``tests/holding.py``; naive, the baseline, is measured first):
# its measuring process waits in its first render until the test lets it go
HELD_BENCH = ["bench", "--scene", "default-world", "--variants", "held", "--sections", "table",
              "--budget", "0"]  # fmt: skip


def start(*argv: str, locks: Path | None = None, hold: Hold | None = None) -> subprocess.Popen[str]:
    """``python -m rtc.cli ARGV`` in a session of its own, as a terminal runs a command: a
    signal to its group (``os.killpg``) is what Ctrl-C sends. ``locks``: the benches'
    machine-wide lock folder (so that benches other tests run meanwhile stay unseen);
    ``hold``: the ``held`` variant is installed for it (``tests/holding.py``)."""
    env = dict(hold.env if hold is not None else os.environ)
    if locks is not None:
        env["RTC_BENCH_LOCK_DIR"] = str(locks)
    return subprocess.Popen(
        [sys.executable, "-m", "rtc.cli", *argv], cwd=ROOT, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, start_new_session=True, env=env,
        preexec_fn=sigint_as_a_terminal_has_it,
    )  # fmt: skip


def sigint_as_a_terminal_has_it() -> None:
    """A ``preexec_fn``: Ctrl-C's signal at its default, as a terminal starts a command, even
    when the suite runs in a background job (a shell starts those with SIGINT ignored, and
    an ignored signal stays ignored across ``exec``: Python would never see the Ctrl-C)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


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


def read_to_end(stream: Any, seconds: float = HANG_SECONDS) -> str:
    """All that ``stream`` (a pipe) brings until every process that holds its other end has
    closed it or exited; a hang guard after ``seconds``."""
    chunks: list[bytes] = []
    fd = stream.fileno()
    deadline = time.monotonic() + seconds
    while True:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            raise AssertionError(f"hang guard: the pipe was still open after {seconds:g} s")
        chunk = os.read(fd, 65536)
        if not chunk:
            return b"".join(chunks).decode()
        chunks.append(chunk)


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
    hold = Hold(tmp_path / "held")
    results = tmp_path / "results"
    bench = start(*HELD_BENCH, "--size", "8x6", "--repeat", "1", "--results-dir", str(results),
                  hold=hold)  # fmt: skip
    stop_leftovers.append(bench)
    measuring = hold.reached()  # the measuring process is in its first render, held there
    cmdlines = {c: Path(f"/proc/{c}/cmdline").read_bytes() for c in children(bench.pid)}
    assert measuring == [c for c, cmdline in cmdlines.items() if b"harness.engine.child" in cmdline]
    os.killpg(bench.pid, signal.SIGINT)
    out, err = bench.communicate(timeout=HANG_SECONDS)
    assert bench.returncode == 130
    no_traceback(err)
    assert err.splitlines()[-1] == "rtc bench: interrupted"
    assert all(
        line.startswith(("rtc bench [", "  [naive]", "  [held]")) for line in err.splitlines()[:-1]
    )  # naive first: the baseline
    assert out.startswith("rtc bench: ") and len(out.splitlines()) == 1  # what it measures
    assert list_runs(results) == []
    assert [p.name for p in (results / "runs").iterdir()] == []  # staging and lock removed
    wait_for(lambda: all(gone(pid) for pid in measuring), HANG_SECONDS,
             "the measuring process to end")  # fmt: skip


def test_a_measuring_process_sent_sigint_itself_exits_quietly(tmp_path: Path) -> None:
    hold = Hold(tmp_path / "held")
    job = {
        "variant": "held", "scene": {"name": "default-world", "path": None}, "depth": 5,
        "seed": 0, "epsilon": None, "threads": None,
        "tasks": [{"kind": "row", "size": [40, 30], "samples": 1, "repeat": 50,
                   "budget": None, "compare_size": None}],
    }  # fmt: skip
    (tmp_path / "job.json").write_text(json.dumps(job))
    child = subprocess.Popen(
        [sys.executable, "-m", "harness.engine.child", str(tmp_path / "job.json")], cwd=ROOT,
        stderr=subprocess.PIPE, text=True, env=hold.env, preexec_fn=sigint_as_a_terminal_has_it,
    )  # fmt: skip
    try:
        assert hold.reached() == [child.pid]  # in its first render, held there
        child.send_signal(signal.SIGINT)
        _, err = child.communicate(timeout=HANG_SECONDS)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == 130
    no_traceback(err)
    assert not (tmp_path / "result.json").exists()


@pytest.mark.parametrize("variant", ["held", "pooled[workers=2]:held"])
def test_ctrl_c_during_rtc_render_is_one_line_and_writes_no_image(
    variant: str, tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    """The render is held (``tests/holding.py``): it cannot have finished when Ctrl-C comes.
    In this process (``held``): in its first line; in a pool, at once: while the workers'
    interpreters start."""
    hold = Hold(tmp_path / "held")
    output = tmp_path / "out.png"
    render = start("render", str(REFERENCE), "--variant", variant, "--size", "64x48",
                   "-o", str(output), hold=hold)  # fmt: skip
    stop_leftovers.append(render)
    assert render.stdout is not None
    assert render.stdout.readline().startswith("rendering ")  # it is rendering
    if variant.startswith("pooled"):
        pool = wait_for(lambda: workers_of(render.pid), HANG_SECONDS, "the workers")
    else:
        assert hold.reached() == [render.pid]
    os.killpg(render.pid, signal.SIGINT)
    out, err = render.communicate(timeout=HANG_SECONDS)
    assert render.returncode == 130
    assert err == "rtc render: interrupted\n"
    assert out == "" and not output.exists()
    if variant.startswith("pooled"):
        wait_for(lambda: all(gone(pid) for pid in pool), HANG_SECONDS, "the workers to end")


# ------------------------------------------------------------------ a pooled render's faults


def test_killing_the_parent_of_a_pooled_render_leaves_no_traceback(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    """The workers are held in their first job (``tests/holding.py``) and never let go: the
    render cannot finish, and a worker that ends has noticed that its parent died (how soon:
    ``test_a_worker_whose_parent_is_gone_exits_at_its_next_beat``)."""
    hold = Hold(tmp_path / "held")
    render = start("render", str(REFERENCE), "--variant", "pooled[workers=2]:held",
                   "--size", "64x48", "-o", str(tmp_path / "out.png"), hold=hold)  # fmt: skip
    stop_leftovers.append(render)
    pool = hold.reached(2)  # both workers are in a job
    assert sorted(workers_of(render.pid)) == pool
    render.kill()
    assert render.stderr is not None
    err = read_to_end(render.stderr)  # every worker (which shares it) has exited
    render.wait()
    no_traceback(err)
    assert err == ""
    wait_for(lambda: all(gone(pid) for pid in pool), HANG_SECONDS, "the workers to end")
    assert not (tmp_path / "held" / "hold" / "release").exists()  # they were never let go
    assert not (tmp_path / "out.png").exists()


def test_a_stopped_worker_fails_the_render_within_its_timeout(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    """The heartbeat: a SIGSTOPped worker sends nothing; the render fails once it has been
    silent for the ``timeout`` (1 s here; 10 s by default), naming the worker. The workers
    are held in their first job and never let go (``tests/holding.py``), so nothing but the
    silence can end the render; when the pool notices it, on a clock of the test's own:
    ``test_the_pool_notices_a_silence_at_its_first_check_past_the_timeout``."""
    hold = Hold(tmp_path / "held")
    output = tmp_path / "out.png"
    render = start("render", str(REFERENCE), "--variant", "pooled[workers=2,timeout=1]:held",
                   "--size", "64x48", "-o", str(output), hold=hold)  # fmt: skip
    stop_leftovers.append(render)
    pool = hold.reached(2)
    assert sorted(workers_of(render.pid)) == pool
    wait_for(lambda: beating(pool), HANG_SECONDS, "the workers' heartbeats")
    stopped = pool[0]
    os.kill(stopped, signal.SIGSTOP)
    out, err = render.communicate(timeout=HANG_SECONDS)
    assert render.returncode == 2
    (line,) = err.splitlines()
    assert re.match(
        re.escape(
            f"rtc render: pooled[timeout=1,workers=2]:held could not render {REFERENCE}: "
            "pooled render: worker "
        )
        + rf"[01] \(pid {stopped}\) sent no heartbeat for (\d+\.\d) s ",
        line,
    ), line
    silence = float(line.split("sent no heartbeat for ")[1].split(" s ")[0])
    assert silence >= 1.0  # the silence it measured reached the limit
    assert "(the limit is 1 s: pooled[timeout=T])" in line
    assert "it is stopped (a SIGSTOP, Ctrl-Z or a debugger)" in line
    assert line.endswith("jobs were done; no image is returned")
    assert not output.exists() and "rendered in" not in out
    wait_for(lambda: all(gone(pid) for pid in pool), HANG_SECONDS,
             "the workers (the stopped one too)")  # fmt: skip
    assert not (tmp_path / "held" / "hold" / "release").exists()  # they were never let go


class _Clock:
    """A clock of the test's: ``variants.pooled``'s ``time.monotonic`` and ``time.sleep``,
    and its ``wait`` for messages, which lets the time it waits pass and hears nothing."""

    def __init__(self) -> None:
        self.now = 1000.0
        self.slept: list[float] = []

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.slept.append(seconds)
        self.now += seconds

    def wait(self, objects: list[Any], timeout: float) -> list[Any]:
        self.now += timeout
        return []


def test_the_pool_notices_a_silence_at_its_first_check_past_the_timeout(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Within the ``timeout`` plus one check interval (``HEARTBEAT_SECONDS``), and not
    before: the pool's loop on the test's clock, with a worker that stays silent."""
    clock = _Clock()
    monkeypatch.setattr("variants.pooled.time", clock)
    monkeypatch.setattr("variants.pooled.wait", clock.wait)
    pool = _Pool.__new__(_Pool)  # no processes: the loop and its checks
    pool.timeout = 1.0
    ours, theirs = Pipe()
    try:
        worker = _worker(ours, heard_ago=0.0, now=clock.now, held=0)
        worker.process = SimpleNamespace(pid=os.getpid(), sentinel=theirs)
        pool.workers = [worker]
        started = clock.now
        with pytest.raises(RenderWorkerError) as error:
            for _ in pool.results([(0, 0, 4, 1), (0, 1, 4, 2)]):
                pass
        silence = clock.now - started
        assert pool.timeout < silence <= pool.timeout + HEARTBEAT_SECONDS
        assert silence == pool.timeout + HEARTBEAT_SECONDS  # the first check past the limit
        assert "sent no heartbeat for 1.2 s (the limit is 1 s" in str(error.value)
        assert "while holding job 0 (line 0), job 1 (line 1)" in str(error.value)
    finally:
        ours.close()
        theirs.close()


def test_a_worker_whose_parent_is_gone_exits_at_its_next_beat(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A worker's heartbeat thread finds its parent gone (the pipe closed) at its next beat,
    ``HEARTBEAT_SECONDS`` on, and ends the worker quietly (exit status 0): on the test's
    clock, with ``os._exit`` caught."""

    class Exited(Exception):
        pass

    def exit_(status: int) -> None:
        raise Exited(status)

    clock = _Clock()
    monkeypatch.setattr("variants.pooled.time", clock)
    monkeypatch.setattr("variants.pooled.os", SimpleNamespace(_exit=exit_))
    ours, theirs = Pipe()
    theirs.close()  # the parent's end: it died
    try:
        with pytest.raises(Exited) as exited:
            _Link(ours).beat(HEARTBEAT_SECONDS)
    finally:
        ours.close()
    assert exited.value.args == (0,)
    assert clock.slept == [HEARTBEAT_SECONDS]


def test_a_ctrl_c_while_a_worker_starts_is_held_back_not_lost() -> None:
    from variants.jobs import sigint_blocked

    # Python's own Ctrl-C handler, even when the suite runs with SIGINT ignored (in a
    # background job); put back afterwards
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    reached = []
    try:
        with pytest.raises(KeyboardInterrupt):
            with sigint_blocked():
                os.kill(os.getpid(), signal.SIGINT)  # a worker started now inherits the block
                blocked = signal.pthread_sigmask(signal.SIG_BLOCK, set())
                if threading.active_count() == 1:  # no other thread can take it: it waits
                    time.sleep(0.05)
                    reached.append(signal.SIGINT in blocked)
            time.sleep(0.05)  # delivered by now, to our own handler
    finally:
        signal.signal(signal.SIGINT, previous)
    assert reached in ([], [True])


def _worker(conn: Any, *, heard_ago: float, now: float, held: int = 1) -> _Worker:
    process = SimpleNamespace(pid=os.getpid())  # a running process: ours
    worker = _Worker(0, process, conn, deque(range(held)), now - heard_ago)
    worker.talked = True
    return worker


def test_the_heartbeat_check_blames_silence_not_unread_messages(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    clock = _Clock()  # the pool's clock is the test's: the silences are exact
    monkeypatch.setattr("variants.pooled.time", clock)
    pool = _Pool.__new__(_Pool)  # no processes: only the check
    pool.timeout = 1.0
    jobs = [(0, 0, 4, 1)]
    ours, theirs = Pipe()
    try:
        pool._check_heard(_worker(ours, heard_ago=1.0, now=clock.now), jobs, 1)  # at the limit
        theirs.send(("beat", -1, None))  # said something we have not read yet (we were busy)
        pool._check_heard(_worker(ours, heard_ago=30.0, now=clock.now), jobs, 1)
        ours.recv()
        with pytest.raises(RenderWorkerError) as error:
            pool._check_heard(_worker(ours, heard_ago=30.0, now=clock.now), jobs, 1)
        message = str(error.value)
        assert f"worker 0 (pid {os.getpid()}) sent no heartbeat for 30.0 s" in message
        assert "while holding job 0 (line 0)" in message
        assert "it is frozen or starved of CPU; 0 of 1 jobs were done" in message
        quiet = _worker(ours, heard_ago=30.0, now=clock.now)
        quiet.talked = False  # before its first word: the startup allowance
        pool._check_heard(quiet, jobs, 1)
    finally:
        ours.close()
        theirs.close()


# ------------------------------------------------------------------ two benches at once


@pytest.mark.slow
def test_two_benches_at_once_each_note_the_other_and_the_report_shows_it(
    tmp_path: Path, stop_leftovers: list[subprocess.Popen[str]]
) -> None:
    """The two runs certainly overlap: each is held in its first render until the test lets
    it go (``tests/holding.py``). The second starts while the first is held (it sees the
    first's lock as it starts); the first is let go and ends while the second is held (it
    sees the second's lock as it ends)."""
    locks = tmp_path / "machine-locks"
    results = tmp_path / "results"
    holds = [Hold(tmp_path / "first"), Hold(tmp_path / "second")]
    first = start(*HELD_BENCH, "--size", "8x6", "--repeat", "1", "--results-dir", str(results),
                  locks=locks, hold=holds[0])  # fmt: skip
    stop_leftovers.append(first)
    holds[0].reached()
    assert (results / "runs" / f".bench-{first.pid}.lock").exists()
    second = start(*HELD_BENCH, "--size", "8x6", "--repeat", "1", "--results-dir", str(results),
                   locks=locks, hold=holds[1])  # fmt: skip
    stop_leftovers.append(second)
    holds[1].reached()
    for bench, hold in zip((first, second), holds, strict=True):
        hold.release()
        _, err = bench.communicate(timeout=HANG_SECONDS)
        assert bench.returncode == 0, err
        assert "rtc bench [" in err and "the machine was shared: another `rtc bench`" in err
    runs = [load_run(path)["rtc"] for path in list_runs(results)]
    assert len(runs) == 2
    for run, other in zip(runs, (second, first), strict=True):
        load = run["load"]
        assert [o["pid"] for o in load["other_benches"]] == [other.pid]
        assert len(load["start"]) == len(load["end"]) == 3 and load["peak"] >= load["start"][0]
        assert load["cores"] >= 1 and 0 < load["cpu_share"] < 64
        assert run["shared"].startswith(
            f"another `rtc bench` ran at the same time: pid {other.pid}"
        )
    assert list((results / "runs").glob(".bench-*")) == list(locks.iterdir()) == []  # released
    report = subprocess.run([sys.executable, "-m", "rtc.cli", "report", "--results-dir",
                             str(results)], cwd=ROOT, capture_output=True, text=True)  # fmt: skip
    assert report.returncode == 0 and report.stderr == ""
    readme = (results / "README.md").read_text(encoding="utf-8")
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
    alive = runs / f".bench-{os.getppid()}.lock"  # the live process that wrote it: a bench
    alive.write_text(json.dumps({"started": "then", "results": "elsewhere",
                                 "process_started": sharing.process_started(os.getppid())}))
    init = runs / ".bench-1.lock"  # a live process that is no rtc bench (the machine's init)
    init.write_text(json.dumps({"started": "then", "results": "elsewhere"}))
    # never blocks: the live lock's process (our parent) outlives this test, so a Watch that
    # waited for it would never be made (a hang guard, not a speed limit)
    made: list[sharing.Watch] = []
    maker = threading.Thread(
        target=lambda: made.append(sharing.Watch(tmp_path, cores=1, lock_dir=tmp_path / "machine"))
    )
    maker.start()
    maker.join(timeout=HANG_SECONDS)
    assert made, "hang guard: the Watch is still waiting"
    (watch,) = made
    assert (runs / f".bench-{os.getpid()}.lock").exists()
    assert (tmp_path / "machine" / f".bench-{os.getpid()}.lock").exists()
    seen = watch.finish()
    assert not stale.exists() and alive.exists()
    assert not init.exists() or sharing.process_started(1) is None  # no /proc: only alive
    assert seen["load"]["other_benches"] == [
        {"pid": os.getppid(), "started": "then", "results": "elsewhere"}
    ]
    assert seen["shared"] is not None and f"pid {os.getppid()} (started then)" in seen["shared"]
    assert not (runs / f".bench-{os.getpid()}.lock").exists()


@pytest.mark.skipif(sharing.process_started(1) is None, reason="needs /proc (Linux)")
def test_a_lock_names_a_bench_only_when_its_process_is_the_bench_that_wrote_it() -> None:
    mine = {"process_started": sharing.process_started(os.getpid())}
    assert sharing.is_bench(os.getpid(), mine)  # the process that wrote it
    assert not sharing.is_bench(1, {"started": "then"})  # init: alive, but no rtc bench
    assert not sharing.is_bench(1, mine)  # another process's start: a reused pid
    assert not sharing.is_bench(os.getpid(), {})  # pytest's command line is no rtc bench


def test_the_timeout_is_spelled_in_the_name_only_when_it_is_not_the_default() -> None:
    from variants.registry import load_variant

    assert load_variant("pooled[workers=2,timeout=3]").name == "pooled[timeout=3,workers=2]:naive"
    assert load_variant("pooled[workers=2,timeout=10]").name == "pooled[workers=2]:naive"
    tracer = load_variant("pooled[workers=2,timeout=3]:cached").tracer
    assert getattr(tracer, "timeout", None) == 3
