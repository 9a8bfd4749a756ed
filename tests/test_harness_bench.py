"""``rtc bench`` and ``rtc report`` end to end on the book's default world at 8x6 pixels:
a row per variant, the budget rule in a row, two runs kept, a killed run leaves no file."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
from holding import HANG_SECONDS, Hold

from harness.engine.results import STAGING_PREFIX, list_runs, load_run
from harness.report.build import build_report
from rtc.cli import main

TINY = ["--scene", "default-world", "--size", "8x6", "--repeat", "1", "--again", "0"]


def _bench(results: Path, *extra: str) -> int:
    return main(["bench", *TINY, "--results-dir", str(results), *extra])


# a budget no render fits, on any machine: a microsecond (three for naive's row) for renders of
# 48 pixels of pure Python, each far above that; so the rule certainly shrinks the row
STARVED = "1e-6"


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory) -> Path:
    """Two bench runs into one results folder: naive and cached, then a starved budget."""
    results = tmp_path_factory.mktemp("results")
    assert _bench(results, "--variants", "naive,cached", "--sections", "table") == 0
    assert _bench(results, "--variants", "naive", "--sections", "table", "--budget", STARVED) == 0
    return results


def test_two_runs_in_a_row_leave_two_files(two_runs):
    runs = list_runs(two_runs)
    assert len(runs) == 2
    assert all((path.parent / path.stem).is_dir() for path in runs)  # their pictures
    assert not list((two_runs / "runs").glob(f"{STAGING_PREFIX}*"))


def test_a_run_has_a_row_per_variant_with_every_figure(two_runs):
    rtc = load_run(list_runs(two_runs)[0])["rtc"]
    rows = {row["name"]: row for row in rtc["rows"]}
    assert list(rows) == ["naive", "cached"]
    for row in rows.values():
        assert row["status"] == "ok"
        assert row["size"] == [8, 6]
        assert len(row["wall"]) == 1 and row["wall"][0] > 0
        assert row["allocations"]["count"] > 0
        assert row["rays"]["camera"] == 48
        assert row["compare_size"] == [8, 6]
        assert (two_runs / "runs" / row["image"]).is_file()
    assert rows["naive"]["error_vs_naive"] is None  # the reference itself
    assert rows["cached"]["error_vs_naive"]["max_abs"] == 0  # cached renders naive's picture
    assert rows["cached"]["error_vs_naive"]["pixels"] == 48
    assert (two_runs / "runs" / rows["cached"]["heatmap"]).is_file()
    assert rows["naive"]["speedup"]["value"] == pytest.approx(1.0)
    assert rtc["machine"]["cpu_count"] >= 1
    assert rtc["settings"]["variants"] == ["naive", "cached"]


def test_the_budget_rule_shrinks_a_row_and_the_row_says_so(two_runs):
    rtc = load_run(list_runs(two_runs)[1])["rtc"]
    (row,) = rtc["rows"]
    assert row["reduced"] is True
    assert row["requested_size"] == [8, 6]
    width, height = row["size"]
    assert width * height < 48 and width * 3 == height * 4
    assert f"measured at {width}x{height} instead of 8x6" in row["budget_note"]


def test_the_report_shows_every_variant_the_images_and_the_history(two_runs):
    readme, page, problems = build_report(two_runs)
    assert problems == []
    text = readme.read_text()
    assert "`naive`" in text  # the latest run: naive alone, starved
    assert "measured at" in text and "instead of 8x6" in text
    assert "## History" in text
    assert text.count("| `bench-") == 2  # both runs in the history
    for target in [line.split('src="')[1].split('"')[0] for line in text.splitlines()
                   if 'src="' in line]:  # fmt: skip
        assert (two_runs / target).is_file(), target
    html = page.read_text()
    assert "data:image/png;base64," in html
    assert 'src="runs/' not in html  # self-contained: every image inlined


def test_the_report_of_a_full_table(tmp_path, two_runs):
    # the report of the first run alone: a row per variant in both tables
    (tmp_path / "runs").mkdir()
    first = list_runs(two_runs)[0]
    (tmp_path / "runs" / first.name).write_bytes(first.read_bytes())
    readme, _, _ = build_report(tmp_path)
    text = readme.read_text()
    time_table = text.split("## Time")[1].split("## Cost")[0]
    cost_table = text.split("## Cost and accuracy")[1].split("## Pictures")[0]
    for name in ("naive", "cached"):
        assert f"| `{name}` | 8x6 |" in time_table
        assert f"| `{name}` |" in cost_table


def test_user_mistakes_are_one_line_errors(tmp_path, capsys):
    assert main(["bench", "--size", "10", "--results-dir", str(tmp_path)]) == 2
    assert "bad size '10'" in capsys.readouterr().err
    assert main(["bench", "--variants", "nosuch", "--results-dir", str(tmp_path)]) == 2
    assert "unknown variant 'nosuch'" in capsys.readouterr().err
    assert main(["bench", "--sections", "tables", "--results-dir", str(tmp_path)]) == 2
    assert "--sections 'tables'" in capsys.readouterr().err
    assert main(["report", "--results-dir", str(tmp_path)]) == 2
    assert "run `rtc bench` first" in capsys.readouterr().err
    assert not list(tmp_path.rglob("*.json"))


@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGTERM])
def test_a_killed_run_leaves_no_result_file(tmp_path, how):
    """The bench measures the held variant (``tests/holding.py``; after naive, the baseline,
    whose row comes first): its measuring process waits in its first render and is never
    let go, so the run is certainly still measuring when it is killed, and a measuring
    process that ends has noticed its parent's death."""
    hold = Hold(tmp_path / "held")
    results = tmp_path / "results"
    command = [sys.executable, "-m", "rtc.cli", "bench", *TINY, "--variants", "held",
               "--sections", "table", "--budget", "0", "--results-dir", str(results)]  # fmt: skip
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, env=hold.env)
    try:
        measuring = hold.reached()  # it is measuring
        assert _children_of(process.pid) == measuring
        assert list((results / "runs").glob(f"{STAGING_PREFIX}*/jobs/*/job.json"))
        process.send_signal(how)
        process.wait(timeout=HANG_SECONDS)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    process.stderr.close()  # type: ignore[union-attr]
    assert list_runs(results) == []
    visible = [p for p in (results / "runs").iterdir() if not p.name.startswith(".")]
    assert visible == []
    if how == signal.SIGTERM:  # cleaned up at once
        assert process.returncode == 130
        assert list((results / "runs").iterdir()) == []
    # the measuring process, held for ever, ends because its parent did
    deadline = time.monotonic() + HANG_SECONDS
    while any(_running(pid) for pid in measuring) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not any(_running(pid) for pid in measuring), "hang guard: it outlived its parent"
    assert not (hold.folder / "release").exists()  # it was never let go
    # and the next run removes what a SIGKILL left behind
    assert main(["bench", *TINY, "--variants", "naive", "--sections", "table",
                 "--results-dir", str(results)]) == 0  # fmt: skip
    assert [p.name.startswith(STAGING_PREFIX) for p in (results / "runs").iterdir()] == [
        False,
        False,
    ]


def _running(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rfind(")") + 2] != "Z"


def _children_of(pid: int) -> list[int]:
    """Processes still running whose parent was ``pid`` (Linux /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            fields = stat[stat.rfind(")") + 2 :].split()
            if int(fields[1]) == pid and fields[0] != "Z":
                found.append(int(entry.name))
    return found


@pytest.fixture(autouse=True)
def _no_numba_env_leak(monkeypatch):
    monkeypatch.delenv("RTC_ALLOCCOUNT_DIR", raising=False)
    yield
    assert "RTC_ALLOCCOUNT_DIR" not in os.environ


def test_each_section_of_the_report_comes_from_the_newest_run_that_measured_it():
    from harness.report.build import pick_runs

    everything = {
        "stem": "quick", "rows": [{"section": "table"}, {"section": "preset"}],
        "series": [{"section": "sweep", "part": "truth"}, {"section": "scaling", "part": "sizes"}],
        "kata": {"summary": [1]},
    }  # fmt: skip
    table_only = {"stem": "table", "rows": [{"section": "table"}], "series": []}
    chosen = pick_runs([everything, table_only])
    assert {section: run["stem"] for section, run in chosen.items()} == {
        "table": "table", "sweep": "quick", "scaling": "quick", "preset": "quick",
        "kata": "quick",
    }  # fmt: skip
    nothing = {"stem": "empty", "rows": [], "series": []}
    assert pick_runs([nothing]) == {}  # no section to show


# ------------------------------------------------------------------ busy rows measured again


def _fake_bench(tmp_path: Path, shares: list[float], monkeypatch) -> tuple[Any, list]:
    """A Bench whose jobs return made-up timings, with CPU ``shares`` in turn (numba asks
    for 2 cores); the tasks it was given are kept in the list returned."""
    import numpy as np

    from groundwork.sizes import Size
    from harness.engine import sharing
    from harness.engine.bench import Bench
    from harness.engine.jobs import JobOutcome
    from harness.engine.plan import QUICK, BenchSettings
    from harness.engine.results import RunWriter
    from harness.scenery.presets import SceneRef

    monkeypatch.setattr(sharing, "wait_for_quiet", lambda cores, longest, **_: "quiet")
    settings = BenchSettings(
        scene=SceneRef("default-world", None), size=Size(8, 6), samples=1, depth=5, seed=0,
        threads=None, repeat=1, budget=None, variants=["naive", "numba"], sections=("table",),
        mode=QUICK, results=tmp_path,
    )  # fmt: skip
    bench = Bench(settings, RunWriter(tmp_path), lambda message: None)
    given: list = []

    def job(variant, scene, tasks, depth=None):
        given.append(tasks[0])
        folder = tmp_path / f"job-{len(given)}"
        folder.mkdir()
        np.save(folder / "image.npy", np.zeros((6, 8, 3)))
        share = shares[len(given) - 1]
        task = {"size": [8, 6], "requested_size": [8, 6], "samples": 1, "wall": [1.0 + len(given)],
                "cpu": [share * (1.0 + len(given))], "cores": 2, "image": "image.npy"}  # fmt: skip
        return JobOutcome(folder, {"summary": "s", "tasks": [task]})

    monkeypatch.setattr(bench, "_job", job)
    return bench, given


def _task() -> dict:
    return {"kind": "row", "size": [8, 6], "samples": 1, "repeat": 1, "budget": None,
            "allocations": True, "rays": True, "compare_size": None}  # fmt: skip


def test_a_busy_row_is_timed_again_and_keeps_its_least_busy_measurement(tmp_path, monkeypatch):
    from harness.engine import figures
    from harness.scenery.presets import SceneRef

    bench, given = _fake_bench(tmp_path, [0.9, 1.2, 1.9], monkeypatch)
    row = bench.measure_row("table", "numba", SceneRef("default-world", None), _task())
    assert len(given) == 3  # busy twice, then it got its cores
    assert [a["busy"] for a in row["attempts"]] == [True, True, False]
    assert row["wall"] == [4.0] and not figures.is_busy(row)
    assert given[1]["allocations"] is False and given[1]["compare_size"] is None  # timing only
    assert row["image"].endswith("table-numba.png")  # the first measurement's picture


def test_a_row_that_stays_busy_is_marked_after_the_retries(tmp_path, monkeypatch):
    from harness.engine import figures
    from harness.scenery.presets import SceneRef

    bench, given = _fake_bench(tmp_path, [0.5, 1.1, 0.7], monkeypatch)
    row = bench.measure_row("table", "numba", SceneRef("default-world", None), _task())
    assert len(given) == 1 + bench.settings.again == 3
    assert figures.is_busy(row) and figures.cpu_share(row) == pytest.approx(1.1)


def test_a_row_that_got_its_cores_is_measured_once(tmp_path, monkeypatch):
    from harness.scenery.presets import SceneRef

    bench, given = _fake_bench(tmp_path, [1.95], monkeypatch)
    row = bench.measure_row("table", "numba", SceneRef("default-world", None), _task())
    assert len(given) == 1 and "attempts" not in row


def test_the_run_has_one_wait_budget_and_then_marks_busy_rows_without_waiting(
    tmp_path, monkeypatch
):
    from harness.engine import figures, sharing
    from harness.scenery.presets import SceneRef

    bench, given = _fake_bench(tmp_path, [0.5, 0.6, 0.5, 0.5, 0.5], monkeypatch)
    now = [0.0]
    bench.clock = lambda: now[0]
    waits: list[float] = []

    def wait(cores, longest, **_):  # the clock moves by the time waited
        waits.append(longest)
        now[0] += longest
        return "still busy"

    monkeypatch.setattr(sharing, "wait_for_quiet", wait)
    assert bench.wait_left == bench.settings.mode.wait_budget == 30.0
    first = bench.measure_row("table", "numba", SceneRef("default-world", None), _task())
    assert waits == [20.0, 10.0] and bench.wait_left == 0.0  # 20 s, then what was left
    assert len(given) == 3 and figures.is_busy(first)
    second = bench.measure_row("table", "numba", SceneRef("default-world", None), _task())
    assert len(given) == 4 and waits == [20.0, 10.0]  # no wait, no second timing: spent
    assert figures.is_busy(second) and "attempts" not in second


def test_only_one_core_python_rows_are_timed_beside_the_background_compile():
    from harness.engine.warmer import Warmer, compiles, one_core_python

    assert one_core_python("naive", 2) and one_core_python("prealloc", 2)
    assert not one_core_python("numba[threads=1]", 2)  # compiles: waits for its kernels
    assert not one_core_python("pooled[workers=2]:prealloc", 2)  # wants the second core
    assert compiles("pooled[workers=1]:numba") and not compiles("wavefront")
    logged: list[str] = []
    warmer = Warmer(Path("unused"), lambda name, rays: {}, logged.append, cores=1)
    warmer.add(["naive", "numba", "numba[float32]", "pooled[workers=2]:numba"], rays=False)
    assert warmer.names == ["numba", "numba[float32]"]  # no pool: its workers take a core
    warmer.start()  # one core: the compile would take the timed row's, so nothing starts
    warmer.before("numba")
    assert logged == []


def test_a_row_that_waits_for_the_background_compile_lets_every_core_compile(tmp_path):
    from harness.engine.warmer import Warmer

    # the first job holds its core until the second one runs: it is released only if the
    # waiting row starts a second compiling process beside it (certain, not timed: without
    # it, the first job gives up after two minutes and says so)
    record, go = tmp_path / "record.txt", tmp_path / "go"
    logged: list[str] = []
    warmer = Warmer(tmp_path / "warm", lambda name, rays: {}, logged.append, cores=2)
    warmer.add_job("first", "tests.warm_probe",
                   {"name": "first", "wait": str(go), "longest": 120, "record": str(record)})
    warmer.add_job("second", "tests.warm_probe",
                   {"name": "second", "make": str(go), "record": str(record)})  # fmt: skip
    warmer.start()
    warmer.before("naive")  # a one-core Python row is timed beside the compile: no wait
    assert not go.exists()  # one compiling process so far: the second job waits its turn
    warmer.before("numba")
    assert record.read_text().splitlines() == ["second made", "first released"]
    assert logged[0].startswith("compiling numba's kernels for first, second in the background")
    assert logged[-1].startswith("the background compile of first, second took")


def test_waiting_for_quiet_stops_when_the_cores_are_idle_or_after_the_longest(monkeypatch):
    from harness.engine import sharing

    monkeypatch.setattr(sharing.os, "cpu_count", lambda: 2)
    seen = iter([1.9, 1.5, 0.1])
    monkeypatch.setattr(sharing, "busy_cores", lambda step: next(seen))
    assert sharing.wait_for_quiet(2, 10) == "1.9 of 2 cores idle after 3 s"
    monkeypatch.setattr(sharing, "busy_cores", lambda step: 2.0)
    assert sharing.wait_for_quiet(1, 3) == "still 2.0 of 2 cores busy after 3 s"


def test_the_ladder_reuses_the_tables_rows_and_says_why_povray_is_absent(tmp_path, monkeypatch):
    # a POV-Ray that answers --version, so that the reason is the scene, on any machine
    fake = tmp_path / "povray"
    fake.write_text("#!/bin/sh\necho 'POV-Ray 3.7.0.10 (a stand-in)'\n")
    fake.chmod(0o755)
    monkeypatch.setenv("RTC_POVRAY", str(fake))
    assert _bench(tmp_path, "--variants", "naive,cached", "--sections", "ladder,table") == 0
    rtc = load_run(list_runs(tmp_path)[0])["rtc"]
    ladder = [r for r in rtc["rows"] if r["section"] == "ladder"]
    assert [r["name"] for r in ladder] == ["naive", "cached"]
    assert all(r["reused"] == "table" for r in ladder)  # measured once, by the table
    assert ladder[1]["over"] == "naive"
    assert ladder[1]["error_vs_over"]["max_abs"] == 0  # cached draws naive's picture
    (anchor,) = [e for e in rtc["series"] if e.get("anchor")]
    assert anchor["status"] == "unavailable"
    assert "no .pov version of the scene 'default-world'" in anchor["error"]
    readme = build_report(tmp_path)[0].read_text()
    assert readme.split("\n## ")[1].startswith("Step by step")
    assert "**No C++ anchor in this run:** no .pov version" in readme
    assert "| `cached` |" in readme.split("\n## ")[1]


ROOT = Path(__file__).resolve().parents[1]


def _strings(value: Any) -> Any:
    if isinstance(value, dict):
        for item in value.values():
            yield from _strings(item)
    elif isinstance(value, list):
        for item in value:
            yield from _strings(item)
    elif isinstance(value, str):
        yield value


def test_a_run_file_names_no_path_of_the_machine(tmp_path: Path) -> None:
    """A run file is committed and read elsewhere: the scene it rendered is named relative
    to the project, a folder outside the project by its name only."""
    results = tmp_path / "my-results"
    scene = ROOT / "scenes" / "reference.yml"
    assert main(["bench", "--scene", str(scene), "--size", "4x3", "--repeat", "1",
                 "--again", "0", "--variants", "naive", "--sections", "table",
                 "--results-dir", str(results)]) == 0  # fmt: skip
    data = load_run(list_runs(results)[0])
    settings = data["rtc"]["settings"]
    assert settings["scene"]["path"] == "scenes/reference.yml"
    assert settings["results"] == ".../my-results"
    assert not [text for text in _strings(data) if str(tmp_path) in text or str(ROOT) in text]


def test_no_committed_run_file_names_an_absolute_path() -> None:
    found = [
        (path.name, text)
        for path in list_runs(ROOT / "results")
        for text in _strings(load_run(path))
        if text.startswith("/") and Path(text).is_absolute() and text.count("/") > 1
    ]
    assert found == []
