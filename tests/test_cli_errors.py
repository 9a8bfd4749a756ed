"""Bad input to ``rtc bench``, ``rtc render`` and ``rtc report`` is found before any work is
done and is one line (issue 19): a scene that does not load stops the bench before it
measures; output paths and ``--results-dir`` are checked before rendering; a damaged run file
is skipped with one warning on stderr naming the file and the field, and the report is still
built from the others, with no NaN timing in it."""

from __future__ import annotations

import ctypes
import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from holding import HANG_SECONDS

from harness.engine.results import ResultFileError, check_run, load_run
from rtc.cli import main

ROOT = Path(__file__).resolve().parent.parent
SCHEMA1 = Path(__file__).parent / "data" / "bench-schema1.json"
TINY_SCENE = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 1.0
  from: [0, 1, -4]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-4, 4, -4]
  intensity: [1, 1, 1]
- add: sphere
  material:
    color: [1, 0.2]
"""  # the sphere's colour has two numbers: line 13


def run_rtc(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def one_line(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[str, str]:
    """Run ``rtc ARGV``, which must fail with status 2 and one line on stderr; (that line,
    stdout)."""
    status, out, err = run_rtc(capsys, *argv)
    assert status == 2, (out, err)
    assert len(err.splitlines()) == 1, err
    assert "Traceback" not in err
    return err.strip(), out


CAP_DAC_OVERRIDE = 1  # linux/capability.h: write (and read) whatever a file's mode bits say
CAP_SETPCAP = 8  # may drop a capability from the bounding set
PR_CAPBSET_DROP = 24  # linux/prctl.h
PR_CAP_AMBIENT, PR_CAP_AMBIENT_CLEAR_ALL = 47, 4
CAPABILITY_VERSION_3 = 0x20080522
NOBODY = 65534


def _effective_capabilities() -> int:
    for line in Path("/proc/self/status").read_text(encoding="ascii").splitlines():
        if line.startswith("CapEff:"):
            return int(line.split()[1], 16)
    return 0


class _CapHeader(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint32), ("pid", ctypes.c_int)]


class _CapData(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint32) for name in ("effective", "permitted", "inheritable")]


def _without_dac_override() -> Callable[[], None]:
    """A ``preexec_fn`` that takes CAP_DAC_OVERRIDE from the child for good (from its
    bounding set too, so the program it runs does not get it back) and changes nothing else:
    it is still root, owner of what root made, and reaches the interpreter and the project
    wherever the clone lies. Everything is prepared here; the child only makes system calls."""
    libc = ctypes.CDLL(None, use_errno=True)
    header = _CapHeader(CAPABILITY_VERSION_3, 0)
    data = (_CapData * 2)()
    bit = 1 << CAP_DAC_OVERRIDE

    def drop() -> None:
        if libc.prctl(PR_CAPBSET_DROP, CAP_DAC_OVERRIDE, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP, CAP_DAC_OVERRIDE)")
        libc.prctl(PR_CAP_AMBIENT, PR_CAP_AMBIENT_CLEAR_ALL, 0, 0, 0)
        if libc.capget(ctypes.byref(header), data) != 0:
            raise OSError(ctypes.get_errno(), "capget")
        data[0].effective &= ~bit
        data[0].permitted &= ~bit
        data[0].inheritable &= ~bit
        if libc.capset(ctypes.byref(header), data) != 0:
            raise OSError(ctypes.get_errno(), "capset")

    return drop


def _as_nobody() -> None:
    os.setgid(NOBODY)
    os.setuid(NOBODY)


def _nobody_reaches(*paths: Path) -> bool:
    """Whether the nobody user can enter every folder above each of ``paths`` and read it."""
    for path in paths:
        for folder in [*path.resolve().parents][::-1]:
            if not folder.stat().st_mode & 0o001:
                return False
        if not path.resolve().stat().st_mode & 0o004:
            return False
    return True


def bits_respected() -> Callable[[], None] | None:
    """A ``preexec_fn`` under which a child honours a file's mode bits, so that a read-only
    folder is read-only for it: None for a plain user (they already do); for root (who
    writes anywhere), root without CAP_DAC_OVERRIDE; where root may not drop it (no
    CAP_SETPCAP), the nobody user, if nobody can reach the interpreter and the project (not
    from a clone in a private folder). Otherwise the test is skipped, saying why."""
    if os.geteuid() != 0:
        return None
    capabilities = _effective_capabilities()
    if not capabilities & (1 << CAP_DAC_OVERRIDE):
        return None  # a root without it (a restricted container): the bits hold already
    if capabilities & (1 << CAP_SETPCAP):
        return _without_dac_override()
    if _nobody_reaches(Path(sys.executable), ROOT / "rtc" / "cli.py"):
        return _as_nobody
    pytest.skip(
        "cannot make a folder read-only for a child of root here: this root may not drop "
        "CAP_DAC_OVERRIDE (no CAP_SETPCAP), and the nobody user cannot reach "
        f"{sys.executable} or the project (a clone in a private folder)"
    )


def rtc_unprivileged(base: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    """``rtc ARGV`` run so that a file's mode bits bind it (``bits_respected``), with a
    matplotlib cache under ``base`` (in case it runs as nobody, who cannot write root's)."""
    preexec = bits_respected()
    cache = base / "mpl"
    cache.mkdir(mode=0o777, exist_ok=True)
    cache.chmod(0o777)
    env = {**os.environ, "MPLCONFIGDIR": str(cache)}
    return subprocess.run(
        [sys.executable, "-m", "rtc.cli", *argv], cwd=ROOT, capture_output=True, text=True,
        timeout=HANG_SECONDS, preexec_fn=preexec, env=env,
    )  # fmt: skip


@pytest.fixture
def open_tmp() -> Iterator[Path]:
    """A fresh folder every user may enter (pytest's ``tmp_path`` sits in a folder only its
    owner may enter, and the child may run as nobody), removed afterwards."""
    folder = Path(tempfile.mkdtemp(prefix="rtc-test-"))
    folder.chmod(0o755)
    try:
        yield folder
    finally:
        for path in [folder, *folder.rglob("*")]:
            if path.is_dir():
                path.chmod(0o755)
        shutil.rmtree(folder)


def read_only_folder(base: Path) -> Path:
    folder = base / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    return folder


# ------------------------------------------------------------------ rtc bench


def test_a_scene_that_does_not_load_stops_the_bench_before_it_measures(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before, every variant's row failed on the scene, the other sections ran for a minute
    and a run file of failed rows replaced the report's tables."""
    scene = tmp_path / "broken.yml"
    scene.write_text(TINY_SCENE, encoding="utf-8")
    results = tmp_path / "results"
    results.mkdir()
    (results / "README.md").write_text("the previous report\n", encoding="utf-8")
    line, out = one_line(
        capsys, "bench", "--scene", str(scene), "--variants", "naive,cached",
        "--sections", "table", "--size", "8x6", "--results-dir", str(results),
    )  # fmt: skip
    assert line == (
        f"rtc bench: {scene}:13: the sphere at line 11: material: color must be a list of 3 "
        "numbers, got 2"
    )
    opening = "rtc bench: table of 2 variant(s), mode quick, into "
    assert [kept for kept in out.splitlines() if not kept.startswith(opening)] == []  # no table
    assert sorted(p.name for p in results.iterdir()) == ["README.md"]  # no runs/, no run file
    assert (results / "README.md").read_text(encoding="utf-8") == "the previous report\n"


def test_bench_refuses_an_empty_size(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    line, _ = one_line(capsys, "bench", "--size", "", "--results-dir", str(tmp_path))
    assert line == "rtc bench: bad size '': expected WIDTHxHEIGHT, e.g. 160x120"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", ["bench", "report", "stability"])
def test_a_results_dir_that_is_a_file_is_one_line(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    named = tmp_path / "results.txt"
    named.write_text("not a folder\n", encoding="utf-8")
    line, out = one_line(capsys, command, "--results-dir", str(named))
    assert line == f"rtc {command}: --results-dir '{named}': '{named}' is a file, not a folder"
    assert named.read_text(encoding="utf-8") == "not a folder\n" and out == ""


def test_a_results_dir_whose_runs_is_a_file_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "runs").write_text("", encoding="utf-8")
    line, _ = one_line(capsys, "report", "--results-dir", str(tmp_path))
    assert line.endswith(f"'{tmp_path / 'runs'}' is a file, not a folder")


def test_bench_into_a_read_only_results_dir_stops_before_measuring(open_tmp: Path) -> None:
    folder = read_only_folder(open_tmp)
    done = rtc_unprivileged(
        open_tmp, "bench", "--scene", "default-world", "--size", "8x6", "--variants", "naive",
        "--sections", "table", "--results-dir", str(folder / "results"),
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines() == [
        f"rtc bench: --results-dir '{folder / 'results'}': cannot write in '{folder}': "
        "Permission denied"
    ]
    assert list(folder.iterdir()) == []
    assert "table: naive" not in done.stderr  # nothing was measured


def test_a_report_into_a_read_only_results_dir_is_one_line(open_tmp: Path) -> None:
    folder = read_only_folder(open_tmp)
    folder.chmod(0o755)
    _write_run(folder, "bench-20250101T000000000Z-aaaaaa.json", None)
    for path in (folder, folder / "runs"):
        path.chmod(0o555)
    done = rtc_unprivileged(open_tmp, "report", "--results-dir", str(folder))
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"rtc report: --results-dir '{folder}': cannot write in '{folder}': Permission denied"
    ]
    assert sorted(p.name for p in folder.iterdir()) == ["runs"]


# ------------------------------------------------------------------ rtc render: the output

SCENE = ROOT / "scenes" / "reference.yml"


def render_error(capsys: pytest.CaptureFixture[str], output: str, *extra: str) -> str:
    line, out = one_line(capsys, "render", str(SCENE), "--size", "8x6", "-o", output, *extra)
    assert out == ""  # "rendering ..." is printed when the render starts: it never did
    return line


def test_an_output_that_is_a_folder_is_refused_before_rendering(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "picture.png"
    folder.mkdir()
    line = render_error(capsys, str(folder))
    assert line == f"rtc render: cannot write '{folder}': it is a folder"
    assert list(folder.iterdir()) == []


def test_an_output_spelled_as_a_folder_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    line = render_error(capsys, f"{tmp_path}/dir.png/")
    assert line == (
        f"rtc render: cannot write '{tmp_path}/dir.png/': it names a folder (it ends with '/')"
    )
    assert list(tmp_path.iterdir()) == []  # in particular, no dir.png


def test_an_output_under_a_file_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "notes.txt").write_text("", encoding="utf-8")
    line = render_error(capsys, str(tmp_path / "notes.txt" / "out.png"))
    assert line == (
        f"rtc render: cannot write '{tmp_path / 'notes.txt' / 'out.png'}': "
        f"'{tmp_path / 'notes.txt'}' is a file, not a folder"
    )


def test_an_empty_size_is_an_error_not_the_default(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    line, out = one_line(
        capsys, "render", str(SCENE), "--size", "", "-o", str(tmp_path / "out.png")
    )
    assert line == "rtc render: bad --size '': expected WIDTHxHEIGHT, e.g. 160x120"
    assert out == "" and list(tmp_path.iterdir()) == []


def test_an_output_in_a_read_only_folder_is_refused_before_rendering(open_tmp: Path) -> None:
    folder = read_only_folder(open_tmp)
    output = folder / "out.png"
    done = rtc_unprivileged(open_tmp, "render", str(SCENE), "--size", "8x6", "-o", str(output))
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"rtc render: cannot write '{output}': cannot write in '{folder}': Permission denied"
    ]
    assert done.stdout == ""  # refused before "rendering ..."
    assert list(folder.iterdir()) == []


def test_an_existing_output_that_cannot_be_written_is_refused_before_rendering(
    open_tmp: Path,
) -> None:
    open_tmp.chmod(0o777)  # nobody may make files here, but not write this one
    output = open_tmp / "out.png"
    output.write_bytes(b"an old picture")
    output.chmod(0o444)
    done = rtc_unprivileged(open_tmp, "render", str(SCENE), "--size", "8x6", "-o", str(output))
    assert done.returncode == 2
    assert done.stderr.splitlines() == [f"rtc render: cannot write '{output}': Permission denied"]
    assert done.stdout == "" and output.read_bytes() == b"an old picture"


# ------------------------------------------------------------------ rtc report


def _break_size(rtc: dict[str, Any]) -> None:
    del rtc["rows"][0]["size"]


def _settings_null(rtc: dict[str, Any]) -> None:
    rtc["settings"] = None


def _rows_not_a_list(rtc: dict[str, Any]) -> None:
    rtc["rows"] = {"naive": rtc["rows"][0]}


def _nan_wall(rtc: dict[str, Any]) -> None:
    rtc["rows"][1]["wall"] = [float("nan")]


def _infinite_point(rtc: dict[str, Any]) -> None:
    point = {"size": [8, 6], "samples": 1, "wall": float("inf")}
    rtc["series"] = [{"section": "sizes", "name": "naive", "status": "ok", "points": [point]}]


def _zero_wall(rtc: dict[str, Any]) -> None:
    rtc["rows"][0]["wall"] = [0.0]


def _size_as_text(rtc: dict[str, Any]) -> None:
    rtc["rows"][1]["size"] = "8x6"


def _no_machine(rtc: dict[str, Any]) -> None:
    del rtc["machine"]


def _kata_without_variant(rtc: dict[str, Any]) -> None:  # beyond the checks: the trial
    rtc["kata"] = {"variants": ["naive"], "summary": [{"chapter": 1, "title": "Tuples"}]}


DAMAGE = [
    (_break_size, "rows[0].size: missing"),
    (_settings_null, "settings: expected an object, got null"),
    (_rows_not_a_list, "rows: expected a list, got {"),
    (_nan_wall, "rows[1].wall[0]: nan is not a measurement"),
    (_infinite_point, "series[0].points[0].wall: inf is not a measurement"),
    (_zero_wall, "rows[0].wall: expected a list of seconds above 0 and below 1e+09, got [0.0]"),
    (_size_as_text, 'rows[1].size: expected [width, height], got "8x6"'),
    (_no_machine, "machine: missing"),
    (_kata_without_variant, "the report cannot use it: KeyError: 'variant'"),
]


def _write_run(folder: Path, name: str, change: Callable[[dict[str, Any]], None] | None) -> Path:
    data = json.loads(SCHEMA1.read_text(encoding="utf-8"))
    path = folder / "runs" / name
    data["rtc"]["stem"] = path.stem
    if change is not None:
        change(data["rtc"])
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data), encoding="utf-8")  # NaN and Infinity as Python writes them
    return path


@pytest.mark.parametrize(("damage", "field"), DAMAGE, ids=[d.__name__ for d, _ in DAMAGE])
def test_a_damaged_run_file_is_skipped_with_one_warning_and_the_report_is_built(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], damage: Any, field: str
) -> None:
    good = _write_run(tmp_path, "bench-20250101T000000000Z-aaaaaa.json", None)
    bad = _write_run(tmp_path, "bench-20250102T000000000Z-bbbbbb.json", damage)
    status, out, err = run_rtc(capsys, "report", "--results-dir", str(tmp_path))
    assert status == 0
    (line,) = err.splitlines()  # one warning, on stderr
    assert line.startswith(f"rtc report: warning: skipped {bad}: {field}")
    readme_path, page_path = tmp_path / "README.md", tmp_path / "report.html"
    assert out.splitlines() == [f"rtc report: wrote {readme_path} and {page_path}"]
    readme = (tmp_path / "README.md").read_text(encoding="utf-8")
    assert f"`{good.stem}`" in readme and "## Time" in readme  # built from the good run
    assert f"| `{bad.stem}`" not in readme  # the damaged run is in no table
    tables = readme.split("## Unreadable result files")[0]  # where the skip is listed
    assert "nan" not in tables.lower().replace("nanometre", "")
    assert "inf " not in tables and "µs" not in tables.split("## Time")[1].split("## ")[0]


def test_check_run_names_the_first_bad_field_and_passes_every_kept_run() -> None:
    for path in [*sorted((ROOT / "results" / "runs").glob("bench-*.json")), SCHEMA1]:
        check_run(load_run(path)["rtc"], str(path))  # the project's own runs are fine
    rtc = load_run(SCHEMA1)["rtc"]
    rtc["rows"][0]["cpu"] = ["fast"]
    with pytest.raises(ResultFileError, match=r"^x\.json: rows\[0\]\.cpu\[0\]: expected a number"):
        check_run(rtc, "x.json")
    rtc = load_run(SCHEMA1)["rtc"]
    rtc["rows"][0]["status"] = "failed"  # a failed row needs no figures
    rtc["rows"][0].pop("wall")
    check_run(rtc, "x.json")


def test_when_every_run_file_is_damaged_the_warnings_come_before_the_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = _write_run(tmp_path, "bench-20250102T000000000Z-bbbbbb.json", _settings_null)
    status, out, err = run_rtc(capsys, "report", "--results-dir", str(tmp_path))
    assert status == 2 and out == ""
    assert err.splitlines() == [
        f"rtc report: warning: skipped {bad}: settings: expected an object, got null",
        f"rtc report: no usable bench or stability results in {tmp_path / 'runs'} (1 skipped: "
        "see above); run `rtc bench` first (or `rtc stability`)",
    ]
    assert not (tmp_path / "README.md").exists()


def test_a_run_that_is_not_json_is_one_line_too(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _write_run(tmp_path, "bench-20250101T000000000Z-aaaaaa.json", None)
    bad = tmp_path / "runs" / "bench-20250102T000000000Z-bbbbbb.json"
    bad.write_bytes(b"\x00\xff{ not json\n\n")
    status, _, err = run_rtc(capsys, "report", "--results-dir", str(tmp_path))
    assert status == 0
    (line,) = err.splitlines()
    assert line.startswith(f"rtc report: warning: skipped {bad}: cannot read the result file")


@pytest.mark.slow
def test_the_report_reads_the_project_results_without_warnings(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    shutil.copytree(ROOT / "results" / "runs", tmp_path / "runs")
    status, _, err = run_rtc(capsys, "report", "--results-dir", str(tmp_path))
    assert status == 0 and err == ""
