"""Hostile input, fourth round (issue 37): nothing of the user's is touched. A command writes
only what is its own, where it belongs: the report removes only plots it wrote (its
manifest), never writes through a symbolic link (``-o`` a link, a linked ``results/report``,
a linked ``results/README.md``) nor into a named pipe; a picture written again keeps its
permissions, a new file honours the umask; a run file's name cannot reach outside
``runs/``; a relative ``XDG_CACHE_HOME`` is ignored, as the XDG rules say.
"""

from __future__ import annotations

import json
import os
import shutil
import stat
from collections.abc import Iterator
from pathlib import Path

import pytest
from test_hostile import SCHEMA1, one_line, rtc, scene

from compiled import folder as compiled_folder
from groundwork.files import write_atomically, write_new
from harness.engine import results as results_module
from rtc.cli import main

RUN = "bench-20250101T000000000Z-aaaaaa.json"
FIGURES = """# Another project
<!-- figures: written by `rtc report` from results/runs/; do not edit -->
theirs
<!-- end of figures -->
"""


def results_with_a_run(folder: Path) -> Path:
    (folder / "runs").mkdir(parents=True)
    shutil.copy(SCHEMA1, folder / "runs" / RUN)
    return folder


@pytest.fixture
def umask_077() -> Iterator[None]:
    old = os.umask(0o077)
    try:
        yield
    finally:
        os.umask(old)


# ------------------------------------------------------------------------------ the report


def test_the_report_never_removes_a_file_it_did_not_write(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = results_with_a_run(tmp_path / "results")
    notes = results / "report" / "my-notes.png"
    notes.parent.mkdir()
    notes.write_bytes(b"mine")
    assert main(["report", "--results-dir", str(results)]) == 0
    assert main(["report", "--results-dir", str(results)]) == 0
    capsys.readouterr()
    assert notes.read_bytes() == b"mine"
    written = (results / "report" / ".written").read_text(encoding="utf-8").split()
    assert "history.png" in written and "my-notes.png" not in written


def test_the_report_removes_a_plot_it_wrote_and_no_longer_draws(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = results_with_a_run(tmp_path / "results")
    assert main(["report", "--results-dir", str(results)]) == 0
    old = results / "report" / "renamed-plot.png"
    old.write_bytes(b"an older report's")
    manifest = results / "report" / ".written"
    manifest.write_text(manifest.read_text(encoding="utf-8") + "renamed-plot.png\n")
    assert main(["report", "--results-dir", str(results)]) == 0
    capsys.readouterr()
    assert not old.exists()
    assert (results / "report" / "history.png").is_file()


@pytest.mark.parametrize("target", ["report", "README.md", "report.html", "report/history.png"])
def test_the_report_writes_through_no_symbolic_link(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], target: str
) -> None:
    results = results_with_a_run(tmp_path / "results")
    theirs = tmp_path / "pictures"
    theirs.mkdir()
    for name in ("a.png", "b.png", "history.png"):
        (theirs / name).write_bytes(b"the user's")
    link = results / target
    link.parent.mkdir(exist_ok=True)
    link.symlink_to(theirs if target == "report" else theirs / "a.png")
    line = one_line(capsys, "report", "--results-dir", str(results))
    assert "symbolic link" in line and str(link) in line
    assert sorted(p.name for p in theirs.iterdir()) == ["a.png", "b.png", "history.png"]
    assert all(p.read_bytes() == b"the user's" for p in theirs.iterdir())
    assert link.is_symlink()


@pytest.mark.parametrize("kind", ["fifo", "folder"])
def test_a_results_readme_that_is_no_file_is_one_line_and_no_hang(
    tmp_path: Path, kind: str
) -> None:
    """A real process: the report must not open the pipe."""
    results = results_with_a_run(tmp_path / "results")
    readme = results / "README.md"
    os.mkfifo(readme) if kind == "fifo" else readme.mkdir()
    done = rtc("report", "--results-dir", str(results))
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.count("\n") == 1
    assert "not a regular file" in done.stderr and "free some space" not in done.stderr


def test_a_linked_results_folder_is_said_and_the_other_projects_readme_is_left(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    other = tmp_path / "other"
    results_with_a_run(other / "results")
    (other / "README.md").write_text(FIGURES, encoding="utf-8")
    project = tmp_path / "project"
    project.mkdir()
    (project / "results").symlink_to(other / "results")
    monkeypatch.chdir(project)
    assert main(["report", "--publish"]) == 0  # the committed folder, here a link
    out, err = capsys.readouterr()
    assert f"results is a link to {other / 'results'}" in err
    assert (other / "README.md").read_text(encoding="utf-8") == FIGURES
    assert "updated the figures" not in out


def test_a_run_file_whose_name_leaves_the_runs_folder_is_skipped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = results_with_a_run(tmp_path / "results")
    path = results / "runs" / RUN
    data = json.loads(path.read_text(encoding="utf-8"))
    data["rtc"]["stem"] = "../../../../tmp/evil"
    path.write_text(json.dumps(data), encoding="utf-8")
    assert main(["report", "--results-dir", str(results)]) == 2
    err = capsys.readouterr().err
    assert "stem: expected a plain name" in err and "'../../../../tmp/evil'" in err


# ------------------------------------------------------------------ -o and the profile


def _linked_output(tmp_path: Path) -> tuple[Path, Path]:
    pointed = tmp_path / "kept.png"
    pointed.write_bytes(b"the old picture")
    link = tmp_path / "out.png"
    link.symlink_to(pointed)
    return link, pointed


@pytest.mark.parametrize("command", ["render", "demo"])
def test_an_output_that_is_a_symbolic_link_is_refused_and_left(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    link, pointed = _linked_output(tmp_path)
    argv = ["demo", "4"]
    if command == "render":
        argv = ["render", str(scene(tmp_path, "- add: sphere\n")), "--variant", "naive"]
    line = one_line(capsys, *argv, "-o", str(link))
    assert "symbolic link" in line and str(link) in line
    assert link.is_symlink() and pointed.read_bytes() == b"the old picture"


@pytest.mark.parametrize("kind", ["link", "fifo"])
def test_a_profile_output_that_is_a_link_or_a_pipe_is_refused_before_the_work(
    tmp_path: Path, kind: str
) -> None:
    """A real process: opening the pipe would block."""
    path = scene(tmp_path, "- add: sphere\n")
    out = tmp_path / "pout"
    out.mkdir()
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes", encoding="utf-8")
    pstats = out / "profile-scene-naive.pstats"
    pstats.symlink_to(notes) if kind == "link" else os.mkfifo(pstats)
    done = rtc("profile", str(path), "--variant", "naive", "--no-flame", "-o", str(out))
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "profile-scene-naive.pstats" in done.stderr
    assert ("symbolic link" if kind == "link" else "named pipe") in done.stderr
    assert notes.read_text(encoding="utf-8") == "my notes"


# --------------------------------------------------------------------------- permissions


def test_a_private_picture_rendered_again_stays_private(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = scene(tmp_path, "- add: sphere\n")
    out = tmp_path / "private.png"
    out.write_bytes(b"")
    out.chmod(0o600)
    assert main(["render", str(path), "--variant", "naive", "-o", str(out)]) == 0
    capsys.readouterr()
    assert stat.S_IMODE(out.stat().st_mode) == 0o600
    assert out.stat().st_size > 0


@pytest.mark.parametrize("write", [write_atomically, write_new])
def test_a_new_file_honours_the_umask(tmp_path: Path, umask_077: None, write: object) -> None:
    target = tmp_path / "new.png"
    write(target, b"data")  # type: ignore[operator]
    assert stat.S_IMODE(target.stat().st_mode) == 0o600


def test_a_new_picture_and_run_file_honour_the_umask(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], umask_077: None
) -> None:
    path = scene(tmp_path, "- add: sphere\n")
    out = tmp_path / "new.png"
    assert main(["render", str(path), "--variant", "naive", "-o", str(out)]) == 0
    results = tmp_path / "results"
    assert main(["report", "--results-dir", str(results_with_a_run(results))]) == 0
    capsys.readouterr()
    for made in (out, results / "README.md", results / "report" / "history.png"):
        assert stat.S_IMODE(made.stat().st_mode) == 0o600, made


@pytest.mark.parametrize("value", [".", "relative/cache"])
def test_a_relative_xdg_cache_home_is_ignored(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, value: str
) -> None:
    monkeypatch.delenv("RTC_NUMBA_KERNELS", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("XDG_CACHE_HOME", value)
    monkeypatch.chdir(tmp_path)
    compiled_folder._folders.clear()
    try:
        folder = compiled_folder.kernel_folder()
    finally:
        compiled_folder._folders.clear()
    assert folder == tmp_path / "home" / ".cache" / "rtc-workbook" / "numba-kernels"
    assert not (tmp_path / "rtc-workbook").exists() and not (tmp_path / "relative").exists()


# ------------------------------------------------------------------ two benches, one folder


def test_a_living_runs_staging_folder_is_kept_whatever_its_process_id_says(
    tmp_path: Path,
) -> None:
    """Another PID namespace (a second container on the same results volume): the staging
    folder's process id names no process here, but its run holds the lock and is alive."""
    staging = tmp_path / "runs" / f"{results_module.STAGING_PREFIX}bench-x-999999999"
    staging.mkdir(parents=True)
    (staging / "picture.png").write_bytes(b"the other run's")
    held = results_module._hold_lock(results_module._lock_path(staging))
    assert held is not None
    try:
        assert results_module.remove_stale_staging(tmp_path) == []
        writer = results_module.RunWriter(tmp_path)  # a second bench starting beside it
        assert (staging / "picture.png").read_bytes() == b"the other run's"
        writer.abandon()
    finally:
        os.close(held)  # the other run ends: its lock goes with it
    assert results_module.remove_stale_staging(tmp_path) == [staging]
    assert not staging.exists() and not list((tmp_path / "runs").iterdir())
