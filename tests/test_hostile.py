"""Hostile input and a damaged machine (issue 30): each case gives the right result or one
clear line, no signal ends a process and nothing hangs.

The classes, each over the naive, cached and numba variants where a render is involved:

- files that are not files: a named pipe (FIFO) or a device (``/dev/zero``) or a folder as
  the scene, an OBJ model, a texture, the ``-o`` target, a feature file or a run file;
- the report: a run file naming pictures outside the results folder, names with HTML,
  ``javascript:`` links and line breaks; its cost with the number of runs;
- run files with negative, empty, NaN, infinite or huge times;
- the kernel cache: private, and every library checked before it is loaded (cut short,
  changed, another kernel's, garbage, a folder, a pipe);
- sizes that do not fit in memory; a full disk; a stopped Dask worker;
- what was silently wrong: a 16-bit grey texture, an OBJ that starts with a byte-order
  mark, ``vn 0 0 0``, YAML 1.1's octal and base-60 numbers, package names pip cannot read,
  a generated mesh's name in another folder.

A case that could block for ever (a named pipe) runs as a real ``rtc`` process with a
timeout that only a hang reaches; everything else runs in this process through ``main``.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import resource
import shutil
import signal
import stat
import subprocess
import sys
import time
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from holding import HANG_SECONDS
from PIL import Image
from report_checks import check_html, check_markdown

from compiled import KernelFolderError, library, notices, records
from compiled import folder as compiled_folder
from groundwork.images import read_png
from harness.document import summary
from harness.document.model import to_markdown
from harness.engine.results import load_run
from harness.report.build import build_blocks
from rtc.cli import main
from scene.obj_mesh import read_mesh
from variants.numba.render import GENERIC_ONLY

ROOT = Path(__file__).resolve().parent.parent
SCHEMA1 = Path(__file__).parent / "data" / "bench-schema1.json"
VARIANTS = ("naive", "cached", "numba")
CAMERA = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
"""
TINY = library.Recipe(
    name="tiny_scale",
    module="compiled_tiny",
    function="scale",
    parameters=(("int64_t", "n"), ("double *", "src"), ("double *", "dst"), ("double", "k")),
    what="the test kernel",
)


def one_line(capsys: pytest.CaptureFixture[str], *argv: str, status: int = 2) -> str:
    """``rtc ARGV`` in this process: it must end with ``status`` and one line on stderr."""
    got = main(list(argv))
    out, err = capsys.readouterr()
    assert got == status, (out, err)
    assert err.count("\n") == 1 and err.endswith("\n"), err
    assert "Traceback" not in err
    return err.strip()


def rtc(*argv: str, env: dict[str, str] | None = None, memory: int | None = None,
        cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:  # fmt: skip
    """``rtc ARGV`` as a real process (``memory``: its address-space limit, in bytes)."""

    def limit() -> None:
        if memory is not None:
            resource.setrlimit(resource.RLIMIT_AS, (memory, memory))

    return subprocess.run(
        [sys.executable, "-m", "rtc.cli", *argv], capture_output=True, text=True,
        timeout=HANG_SECONDS, cwd=cwd, env={**os.environ, **(env or {})}, preexec_fn=limit,
    )  # fmt: skip


def clear(done: subprocess.CompletedProcess[str], text: str, status: int = 2) -> None:
    """A real process ended by itself (no signal) with ``status`` and one line holding
    ``text`` on stderr."""
    assert done.returncode == status, (done.stdout, done.stderr)
    assert done.stderr.count("\n") == 1, done.stderr
    assert text in done.stderr, done.stderr
    assert "Traceback" not in done.stderr


def scene(folder: Path, body: str, name: str = "scene.yml") -> Path:
    path = folder / name
    path.write_text(CAMERA + body, encoding="utf-8")
    return path


def obj_scene(folder: Path, file: str) -> Path:
    return scene(folder, f"- add: obj\n  file: {file}\n")


def texture_scene(folder: Path, file: str) -> Path:
    return scene(
        folder,
        "- add: plane\n  transform:\n    - [rotate-x, -1.5707963267948966]\n  material:\n"
        "    ambient: 1\n    diffuse: 0\n    specular: 0\n    pattern:\n      type: map\n"
        f"      mapping: planar\n      uv_pattern:\n        type: image\n        file: {file}\n",
    )


# ------------------------------------------------------------- files that are not files


def odd_file(folder: Path, kind: str, name: str) -> tuple[Path, str]:
    """A path in ``folder`` that is not a regular file, and the words that say what it is."""
    path = folder / name
    if kind == "fifo":
        os.mkfifo(path)
        return path, "a named pipe (FIFO), not a regular file"
    if kind == "device":
        path.symlink_to("/dev/zero")
        return path, "a character device, not a regular file"
    path.mkdir()
    return path, "a folder"


TARGETS = ("scene", "obj", "texture", "output")


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("target", TARGETS)
def test_a_named_pipe_is_refused_in_one_line_by_every_reader_and_writer(
    tmp_path: Path, variant: str, target: str
) -> None:
    """A real process: a reader that opened the pipe would wait for a writer for ever."""
    names = {"obj": "model.obj", "texture": "t.png", "output": "out.png"}
    pipe, words = odd_file(tmp_path, "fifo", names.get(target, "s.yml"))
    output = tmp_path / "picture.png"
    if target == "scene":
        path = pipe
    elif target == "obj":
        path = obj_scene(tmp_path, pipe.name)
    elif target == "texture":
        path = texture_scene(tmp_path, pipe.name)
    else:
        path, output = scene(tmp_path, "- add: sphere\n"), pipe
    done = rtc("render", str(path), "--variant", variant, "-o", str(output))
    clear(done, words)
    assert str(pipe) in done.stderr
    assert stat.S_ISFIFO(pipe.lstat().st_mode)  # left as it was


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("kind", ["device", "folder"])
@pytest.mark.parametrize("target", ["scene", "obj", "texture"])
def test_a_device_or_a_folder_is_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str, kind: str, target: str
) -> None:
    odd, words = odd_file(tmp_path, kind, "thing.yml" if target == "scene" else "thing.obj")
    path = {"scene": lambda: odd, "obj": lambda: obj_scene(tmp_path, odd.name),
            "texture": lambda: texture_scene(tmp_path, odd.name)}[target]()  # fmt: skip
    output = tmp_path / "out.png"
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o", str(output))
    assert words in line and not output.exists()


def test_dev_zero_as_the_scene_is_one_line_not_all_the_memory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    line = one_line(capsys, "render", "/dev/zero", "-o", str(tmp_path / "out.png"))
    assert line == (
        "rtc render: /dev/zero: cannot read the scene file: it is a character device, not a "
        "regular file"
    )


def test_a_scene_file_too_large_is_refused_before_it_is_read(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from scene import loader

    monkeypatch.setattr(loader, "MAX_SCENE_BYTES", 100)
    path = scene(tmp_path, "- add: sphere\n")
    line = one_line(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    assert line.endswith("cannot read the scene file: the file is 178 bytes; files up to 100 "
                         "bytes are read")  # fmt: skip


def test_a_named_pipe_as_a_feature_file_or_a_run_file_is_one_line(tmp_path: Path) -> None:
    feature, words = odd_file(tmp_path, "fifo", "a.feature")
    clear(rtc("kata", str(feature)), words)
    folder = tmp_path / "features"
    folder.mkdir()
    odd_file(folder, "fifo", "b.feature")
    clear(rtc("kata", str(folder)), f"{folder / 'b.feature'}: cannot read the feature file")
    run, words = odd_file(tmp_path, "fifo", "bench-x.json")
    clear(rtc("compare", str(run), str(run)), words)
    results = tmp_path / "results"
    (results / "runs").mkdir(parents=True)
    pipe = results / "runs" / "bench-20250101T000000000Z-aaaaaa.json"
    os.mkfifo(pipe)
    done = rtc("report", "--results-dir", str(results))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert done.stderr.splitlines() == [
        f"rtc report: warning: skipped {pipe}: cannot read the result file: it is {words}",
        f"rtc report: no usable bench or stability results in {results / 'runs'} (1 skipped: "
        "see above); run `rtc bench` first (or `rtc stability`)",
    ]


def test_dev_zero_as_a_run_file_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    line = one_line(capsys, "compare", "/dev/zero", "/dev/zero")
    assert line == "rtc compare: /dev/zero: it is a character device, not a regular file"


def test_a_binary_feature_file_is_one_line_naming_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    feature = tmp_path / "binary.feature"
    feature.write_bytes(b"Feature: x\n\x89PNG\x00\xff\xfe")
    line = one_line(capsys, "kata", str(feature))
    assert line == (
        f"rtc kata: {feature}:2: the feature file is not UTF-8 text (byte 0x89); save it as UTF-8"
    )


# ------------------------------------------------------------- the report


HOSTILE = {
    "name": 'naive<script>alert(1)</script>"><img src=x onerror=alert(2)>',
    "summary": "[click](javascript:alert(3)) <iframe src=//evil>",
    "hostname": "vm\n# INJECTED heading\n<script>alert(4)</script>",
    "note": "a note [x](javascript:alert(5)) `code` **bold** \\[esc](#fine)",
}


def hostile_results(tmp_path: Path) -> Path:
    """A results folder with one run whose pictures point outside it (a path with ``..``,
    an absolute one, a link to a file outside, a pipe, a file that is no PNG) and whose
    names carry HTML, links and line breaks."""
    results = tmp_path / "results"
    data = json.loads(SCHEMA1.read_text(encoding="utf-8"))
    rtc_part = data["rtc"]
    stem = "bench-20250101T000000000Z-aaaaaa"
    pictures = results / "runs" / stem
    pictures.mkdir(parents=True)
    outside = tmp_path / "secret.png"
    outside.write_bytes(b"\x89PNG\r\n\x1a\nSECRET-OUTSIDE")
    (pictures / "link.png").symlink_to(outside)
    os.mkfifo(pictures / "pipe.png")
    (pictures / "text.png").write_text("not a picture", encoding="utf-8")
    shutil.copy(ROOT / "scenes" / "textures" / "planet.png", pictures / "ok.png")
    images = ["../../../secret.png", str(outside), f"{stem}/link.png", f"{stem}/pipe.png",
              f"{stem}/text.png", f"{stem}/ok.png"]  # fmt: skip
    naive, other = rtc_part["rows"]
    rtc_part["rows"] = [naive] + [dict(other, name=f"cached[{i}]") for i in range(len(images))]
    for row, image in zip(rtc_part["rows"], images + images[:1], strict=False):
        row["image"] = image
        row["summary"] = HOSTILE["summary"]
    rtc_part["rows"][0]["name"] = HOSTILE["name"]
    rtc_part["machine"]["hostname"] = HOSTILE["hostname"]
    rtc_part["notes"] = [HOSTILE["note"]]
    (results / "runs" / f"{stem}.json").write_text(json.dumps(data), encoding="utf-8")
    return results


def test_the_report_embeds_no_file_outside_the_results_folder_and_escapes_every_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = hostile_results(tmp_path)
    assert main(["report", "--results-dir", str(results)]) == 0
    capsys.readouterr()
    page = (results / "report.html").read_text(encoding="utf-8")
    readme = (results / "README.md").read_text(encoding="utf-8")
    assert "SECRET" not in page and "U0VDUkVU" not in page  # nor its base64
    own = "runs/bench-20250101T000000000Z-aaaaaa"
    for shown in ("not a file of the results folder: runs/../../../secret.png",
                  f"not a file of the results folder: runs/{tmp_path / 'secret.png'}",
                  f"not a file of the results folder: {own}/link.png",
                  f"cannot be read: it is a named pipe (FIFO), not a regular file: {own}/pipe",
                  f"not a PNG image: {own}/text.png"):  # fmt: skip
        assert f"<em>{shown}" in page, shown
    assert page.count('<img src="data:image/png;base64,') >= 1  # ok.png, inside
    check_html(page, results)
    headings = sum(line.startswith("#") for line in readme.splitlines())
    check_markdown(readme, results, headings)
    assert "INJECTED" in readme  # the hostname is shown, on the machine's line
    assert not any(line.startswith("# INJECTED") for line in readme.splitlines())
    assert "&lt;script&gt;" in page  # shown as text
    assert "[x] (javascript:alert(5))" not in page  # shown as text, not as a link
    assert 'href="javascript' not in page


def test_the_report_costs_in_proportion_to_the_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """Counted, not timed: the summary reads each run's rows a fixed number of times for the
    report, whatever the number of runs (it read every run's for each of them: 1,000 runs
    took over 400 s)."""
    run = load_run(SCHEMA1)["rtc"]
    calls = [0]
    real = summary._table_rows

    def counted(r: Any) -> Any:
        calls[0] += 1
        return real(r)

    monkeypatch.setattr(summary, "_table_rows", counted)
    reads = []
    for count in (10, 40):
        runs: list[Mapping[str, Any]] = [dict(run, stem=f"b-{i:03d}") for i in range(count)]
        calls[0] = 0
        to_markdown(build_blocks(runs, {}))
        reads.append(calls[0])
    assert reads[1] <= 4.5 * reads[0], reads  # four times the runs, four times the reads


# ------------------------------------------------------------- run files' numbers


def _times(value: Any) -> Callable[[dict[str, Any]], None]:
    def change(rtc_part: dict[str, Any]) -> None:
        rtc_part["rows"][1]["wall"] = value

    return change


NUMBERS = [
    ("negative", _times([-1.5, -1.6]), "rows[1].wall[0] is -1.5, not a time in seconds"),
    ("empty", _times([]), "rows[1].wall is empty"),
    ("nan", _times([float("nan"), 1.0]), "nan is not a measurement"),
    ("infinite", _times([float("inf"), 1.0]), "inf is not a measurement"),
    ("huge", _times([1e300, 1e300]), "rows[1].wall[0]: 1e+300 is not a measurement"),
    ("huge-elsewhere", lambda r: r.update(seconds=1e308), "seconds: 1e+308 is not a measurement"),
]


@pytest.mark.parametrize(("damage", "text"), [(d, t) for _, d, t in NUMBERS],
                         ids=[n for n, _, _ in NUMBERS])  # fmt: skip
def test_a_run_file_with_times_that_are_no_times_is_refused_by_compare_and_the_gate(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], damage: Any, text: str
) -> None:
    data = json.loads(SCHEMA1.read_text(encoding="utf-8"))
    good = tmp_path / "good.json"
    good.write_text(json.dumps(data), encoding="utf-8")
    damage(data["rtc"])
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data), encoding="utf-8")  # NaN and Infinity as Python writes
    line = one_line(capsys, "compare", str(good), str(bad))
    assert line.startswith(f"rtc compare: {bad}: ") and text in line
    line = one_line(capsys, "bench", "--compare-to", str(bad), "--fail-slower", "10%",
                    "--results-dir", str(tmp_path))  # fmt: skip
    assert line.startswith(f"rtc bench: --compare-to {bad}: ") and text in line
    runs = tmp_path / "results" / "runs"
    runs.mkdir(parents=True)
    shutil.copy(bad, runs / "bench-20250101T000000000Z-aaaaaa.json")
    assert main(["report", "--results-dir", str(tmp_path / "results")]) == 2
    assert "warning: skipped" in capsys.readouterr().err  # never in the report's tables


# ------------------------------------------------------------- the kernel cache


@pytest.fixture(scope="module")
def built_once(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A private kernel folder with the test kernel built in it, once for this module."""
    folder = tmp_path_factory.mktemp("built") / "kernels"
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("RTC_NUMBA_KERNELS", str(folder))
        patch.delenv("CC", raising=False)
        compiled = library.load(TINY)
        assert compiled.origin.startswith("shared library"), compiled.origin
        library._loaded.pop(str(TINY.path()), None)
    return folder


@pytest.fixture
def kernels(
    built_once: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[Path]:
    """A fresh private kernel folder for this test, holding the test kernel, sound."""
    folder = tmp_path / "kernels"
    shutil.copytree(built_once, folder, ignore=shutil.ignore_patterns("numba-cache"))
    monkeypatch.setenv("RTC_NUMBA_KERNELS", str(folder))
    monkeypatch.delenv("CC", raising=False)
    yield folder
    library._loaded.pop(str(TINY.path()), None)


def scaled(compiled: library.Compiled) -> list[float]:
    src, dst = np.arange(4.0), np.zeros(4)
    compiled.function(4, src, dst, 2.0)
    return [float(v) for v in dst]


RIGHT = [0.25, 2.25, 4.25, 6.25]


def said_lines(err: str) -> list[str]:
    """The lines the kernel cache said (``rtc: ...``); any other is a command's notice of a
    compile (``rtc render: compiling ...``) that a render earlier in this process asked for."""
    other = [line for line in err.splitlines() if not line.startswith("rtc: ")]
    assert all(line.startswith("rtc render: compil") for line in other), err
    return [line for line in err.splitlines() if line.startswith("rtc: ")]


def the_library(folder: Path) -> tuple[Path, Path]:
    """The test kernel's (record, library file) in ``folder``."""
    (record,) = folder.glob("rtc_tiny_scale_*.json")
    name = json.loads(record.read_text(encoding="utf-8"))["library"]
    return record, folder / name


def _cut(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _code(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 3 : len(data) // 3 + 4] = b"\xff\xff\xff\xff"
    path.write_bytes(bytes(data))


def _constant(path: Path) -> None:  # the 0.25 every result adds, one bit changed
    data = bytearray(path.read_bytes())
    at = data.find(np.float64(0.25).tobytes())
    assert at >= 0
    data[at + 7] ^= 1
    path.write_bytes(bytes(data))


def _foreign(path: Path) -> None:  # another shared library under this one's name
    import _ctypes

    path.write_bytes(Path(_ctypes.__file__).read_bytes())


def _folder(path: Path) -> None:
    path.unlink()
    path.mkdir()
    (path / "x").write_text("x", encoding="utf-8")


def _pipe(path: Path) -> None:
    path.unlink()
    os.mkfifo(path)


DAMAGE: list[tuple[str, Callable[[Path], object], str]] = [
    ("cut-to-half", _cut, "is not the one built"),
    ("four-bytes-of-code", _code, "is not the one built"),
    ("one-bit-of-a-constant", _constant, "is not the one built"),
    ("another-program", _foreign, "is not the one built"),
    ("empty", lambda p: p.write_bytes(b""), "is not the one built"),
    ("garbage", lambda p: p.write_bytes(os.urandom(4096)), "is not the one built"),
    ("a-folder", _folder, "cannot be read (it is a folder, not a regular file)"),
    ("a-pipe", _pipe, "cannot be read (it is a named pipe (FIFO), not a regular file)"),
    ("missing", lambda p: p.unlink(), "is missing"),
]


def test_an_unreadable_library_is_built_again_or_read_as_it_is(
    kernels: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Mode 000: a user cannot read it (built again, one line); root can (its digest is
    right, so it is loaded as it is, in silence)."""
    _record, file = the_library(kernels)
    file.chmod(0)
    notices._said.clear()
    compiled = library.load(TINY)
    assert scaled(compiled) == RIGHT
    err = capsys.readouterr().err
    if os.geteuid() == 0:
        assert err == ""
    else:
        (said,) = said_lines(err)
        assert "cannot be read (Permission denied)" in said, err


RECORD_DAMAGE: list[tuple[str, Callable[[Path], object], str]] = [
    ("garbage", lambda p: p.write_bytes(os.urandom(64)), "is damaged"),
    ("not-an-object", lambda p: p.write_text("[1, 2]", encoding="utf-8"), "is damaged"),
    ("a-folder", _folder, "cannot be read"),
    ("a-pipe", _pipe, "cannot be read"),
    ("another-build", lambda p: p.write_text(
        p.read_text(encoding="utf-8").replace('"key": "', '"key": "0'), encoding="utf-8"),
     "another kernel's library under its name"),
    ("a-path-outside", lambda p: p.write_text(json.dumps(
        {**json.loads(p.read_text(encoding="utf-8")), "library": "../evil.so"}),
        encoding="utf-8"), "is damaged"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("damaged", "damage", "words"),
    [("library", d, w) for _, d, w in DAMAGE] + [("record", d, w) for _, d, w in RECORD_DAMAGE],
    ids=[f"library-{n}" for n, _, _ in DAMAGE] + [f"record-{n}" for n, _, _ in RECORD_DAMAGE],
)
def test_a_damaged_library_or_record_is_built_again_with_one_line(
    kernels: Path, capsys: pytest.CaptureFixture[str], damaged: str, damage: Any, words: str
) -> None:
    record, file = the_library(kernels)
    damage(file if damaged == "library" else record)
    notices._said.clear()
    compiled = library.load(TINY)
    assert scaled(compiled) == RIGHT and compiled.origin.startswith("shared library")
    err = capsys.readouterr().err
    (said,) = said_lines(err)
    assert words in said and "building it again" in said, err
    assert records.verify(TINY.path())[0] is not None  # sound again


@pytest.mark.slow
def test_a_half_cut_render_library_is_rebuilt_and_the_render_is_right(tmp_path: Path) -> None:
    """A real ``rtc render`` with the numba variant: a render library cut in half ended the
    process with SIGBUS, and four changed bytes with SIGILL or SIGSEGV."""
    path = scene(tmp_path, "- add: sphere\n")
    # a kernel for the sphere alone (specialized): the subject is the damaged library, and
    # the generic kernel's build again in a folder of the test's own cost minutes
    sphere_only = {GENERIC_ONLY: "on"}
    for explain in ([], ["--explain"]):  # built (or found) in the usual folder; then where
        first = rtc("render", str(path), "--variant", "numba", "-o", str(tmp_path / "a.png"),
                    *explain, env=sphere_only)  # fmt: skip
        assert first.returncode == 0, first.stderr
    (known,) = re.findall(r"compiled render: (\S+\.so) \(built\)", first.stdout)
    record = Path(known).with_suffix(".json")
    name = json.loads(record.read_text(encoding="utf-8"))["library"]
    folder = tmp_path / "kernels"
    folder.mkdir(mode=0o700)
    shutil.copy(record, folder)
    shutil.copy(record.parent / name, folder)
    _cut(folder / name)
    env = {"RTC_NUMBA_KERNELS": str(folder), **sphere_only}
    done = rtc("render", str(path), "--variant", "numba", "-o", str(tmp_path / "b.png"), env=env)
    assert done.returncode == 0, done.stderr
    assert "is not the one built" in done.stderr and "Traceback" not in done.stderr
    assert read_png(tmp_path / "a.png") == read_png(tmp_path / "b.png")


def test_the_kernel_folder_is_private(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("RTC_NUMBA_KERNELS", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    folder = compiled_folder.kernel_folder()
    assert folder == tmp_path / "cache" / "rtc-workbook" / "numba-kernels"
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    os.chmod(folder, 0o755)  # an older version's: made private
    compiled_folder._folders.clear()
    assert compiled_folder.kernel_folder() == folder
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700


def test_a_kernel_folder_others_could_write_in_is_emptied_and_made_private(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.delenv("RTC_NUMBA_KERNELS", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    folder = tmp_path / "cache" / "rtc-workbook" / "numba-kernels"
    folder.mkdir(parents=True)
    (folder / "rtc_numba_0123456789abcdef.so").write_bytes(b"planted")
    (folder / "rtc_numba_0123456789abcdef.json").write_text("{}", encoding="utf-8")
    (folder / "mine.txt").write_text("not ours to remove", encoding="utf-8")
    os.chmod(folder, 0o777)
    compiled_folder._folders.clear()
    notices._said.clear()
    assert compiled_folder.kernel_folder() == folder
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert sorted(p.name for p in folder.iterdir()) == ["mine.txt"]
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "was writable by other users (mode 777): emptied" in err


def test_a_shared_folder_another_user_made_first_is_never_used(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The home cache cannot be written; the temporary folder's ``rtc-numba-kernels-UID``
    was made by someone else (here: this user pretends to be another), with a library in
    it: a fresh private folder is used, for this process alone, and one line says so."""
    monkeypatch.delenv("RTC_NUMBA_KERNELS", raising=False)
    monkeypatch.delenv("XDG_RUNTIME_DIR", raising=False)
    blocked = tmp_path / "not-a-folder"
    blocked.write_text("", encoding="utf-8")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    monkeypatch.setattr("tempfile.tempdir", str(temporary))  # compiled.folder imports it then
    me = os.geteuid()
    # the folder is not "ours"
    monkeypatch.setattr(compiled_folder.os, "geteuid", lambda: me + 4242)
    planted = temporary / f"rtc-numba-kernels-{me + 4242}"
    planted.mkdir(mode=0o777)
    (planted / "rtc_numba_0123456789abcdef.so").write_bytes(b"planted")
    compiled_folder._folders.clear()
    notices._said.clear()
    folder = compiled_folder.kernel_folder()
    assert folder != planted and folder.parent == temporary
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "it belongs to another user" in err and str(folder) in err
    compiled_folder._folders.clear()


def test_a_kernel_folder_others_can_write_in_is_refused_in_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o1777)
    monkeypatch.setenv("RTC_NUMBA_KERNELS", str(shared))
    compiled_folder._folders.clear()
    with pytest.raises(KernelFolderError, match=r"other users can write in it \(mode 1777\)"):
        compiled_folder.kernel_folder()
    path = scene(tmp_path, "- add: sphere\n")
    done = rtc("render", str(path), "--variant", "numba", "-o", str(tmp_path / "o.png"),
               env={"RTC_NUMBA_KERNELS": str(shared)})  # fmt: skip
    clear(done, "other users can write in it")
    compiled_folder._folders.clear()


def test_a_damaged_file_in_numbas_cache_is_a_miss(
    kernels: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without a C compiler the function runs in numba, from numba's disk cache (in the
    kernel folder); a garbage index or data file there is compiled again, one line each."""
    monkeypatch.setenv("CC", "/bin/false")
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    code = (
        "import numpy as np\nfrom compiled import library\n"
        f"f = library.load(library.{TINY!r})\n"
        "src, dst = np.arange(4.0), np.zeros(4)\nf.function(4, src, dst, 2.0)\n"
        "print(f.origin.split(' (')[0], dst.tolist())\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent), str(ROOT)])}
    env.pop("NUMBA_CACHE_DIR", None)
    env.pop(compiled_folder.NUMBA_CACHE_SET, None)

    def run() -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              env=env, timeout=HANG_SECONDS, cwd=ROOT)  # fmt: skip

    for built in kernels.glob("rtc_tiny_scale_*"):  # no library: numba runs it
        built.unlink()
    first = run()
    assert first.returncode == 0, first.stderr
    assert first.stdout.split(" [")[0] == "numba with its disk cache"
    cache = kernels / "numba-cache"
    files = sorted(cache.rglob("*.nbi")) + sorted(cache.rglob("*.nbc"))
    assert files
    for file in files:
        file.write_bytes(os.urandom(200))
    again = run()
    assert again.returncode == 0, again.stderr
    assert again.stdout.strip().endswith(str(RIGHT))
    assert "is damaged" in again.stderr and "Traceback" not in again.stderr
    quiet = run()
    assert quiet.returncode == 0 and quiet.stderr == ""  # rewritten


# ------------------------------------------------------------- memory, disk, workers


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_size_that_does_not_fit_in_memory_is_refused_before_rendering(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    variant: str,
) -> None:  # fmt: skip
    from groundwork import memory

    monkeypatch.setattr(memory, "available", lambda: memory.Room(2 << 30, "left (a test)"))
    path = scene(tmp_path, "- add: sphere\n")
    output = tmp_path / "out.png"
    line = one_line(capsys, "render", str(path), "--variant", variant, "--size",
                    "16384x16384", "-o", str(output))  # fmt: skip
    assert line.startswith(f"rtc render: a 16384x16384 picture with {variant} needs about ")
    assert "GB of memory; 2 GB left (a test); choose a smaller --size" in line
    assert not output.exists()


def test_under_a_memory_limit_a_real_process_says_so_in_one_line(tmp_path: Path) -> None:
    path = scene(tmp_path, "- add: sphere\n")
    done = rtc("render", str(path), "--size", "16384x16384", "-o", str(tmp_path / "o.png"),
               memory=2 << 30)  # fmt: skip
    clear(done, "left under this process's address-space limit of 2 GB")


def test_a_texture_that_does_not_fit_in_memory_is_refused_before_it_is_decoded(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from groundwork import memory

    monkeypatch.setattr(memory, "available", lambda: memory.Room(1 << 20, "left (a test)"))
    ppm = tmp_path / "big.ppm"
    ppm.write_text("P3\n300 300\n255\n" + "1 2 3\n" * 90_000, encoding="ascii")
    path = texture_scene(tmp_path, ppm.name)
    line = one_line(capsys, "render", str(path), "-o", str(tmp_path / "o.png"))
    assert f"the 300x300 texture {ppm} needs about 25.7 MB of memory; 1 MB left" in line


def _full_disk(monkeypatch: pytest.MonkeyPatch, where: Any, name: str) -> None:
    def full(*args: Any, **kwargs: Any) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(where, name, full)


BENCH = ["bench", "--scene", "default-world", "--variants", "naive", "--sections", "table",
         "--budget", "0", "--size", "4x3", "--repeat", "1"]  # fmt: skip


def test_a_full_disk_stops_the_bench_in_one_line_with_no_run_and_no_lock(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from harness.engine import results

    monkeypatch.setenv("RTC_BENCH_LOCK_DIR", str(tmp_path / "locks"))
    _full_disk(monkeypatch, results, "write_new_file")  # the run file: the last write
    status = main([*BENCH, "--results-dir", str(tmp_path / "results")])
    err = capsys.readouterr().err.splitlines()
    assert status == 2
    assert err[-1] == (
        f"rtc bench: cannot write under {str(tmp_path / 'results')!r}: No space left on "
        "device; nothing was kept (free some space and run again)"
    )
    assert not any("Traceback" in line for line in err)
    assert not list((tmp_path / "results" / "runs").iterdir())  # no run, lock or staging
    assert not list((tmp_path / "locks").iterdir())


def test_a_measuring_process_that_cannot_write_stops_the_bench(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from harness.engine import jobs

    monkeypatch.setenv("RTC_BENCH_LOCK_DIR", str(tmp_path / "locks"))
    monkeypatch.setattr(jobs, "wait_child", lambda process: (process.kill(), process.wait(),
                                                             jobs.CANNOT_WRITE)[2])  # fmt: skip
    status = main([*BENCH, "--results-dir", str(tmp_path / "results")])
    err = capsys.readouterr().err.splitlines()
    assert status == 2 and "No space left on device; nothing was kept" in err[-1]
    assert not list((tmp_path / "results" / "runs").iterdir())


def test_a_result_the_disk_refuses_is_one_line_and_a_status(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from harness.engine import jobs

    _full_disk(monkeypatch, Path, "write_text")
    assert jobs.write_result(tmp_path, {"x": 1}) == jobs.CANNOT_WRITE
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot write its result" in err
    assert not list(tmp_path.iterdir())


def test_a_full_disk_in_rtc_stability_and_rtc_report_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from harness.report import build as report
    from harness.stability import runfile

    _full_disk(monkeypatch, runfile, "write_new_file")
    status = main(["stability", "--variants", "naive", "--cases", "degen/zero", "--size", "4x3",
                   "--results-dir", str(tmp_path / "r")])  # fmt: skip
    err = capsys.readouterr().err
    assert status == 2 and "Traceback" not in err  # its progress lines, then the one error
    assert err.splitlines()[-1] == (
        f"rtc stability: cannot write under {str(tmp_path / 'r')!r}: No space left on device; "
        "nothing was kept (free some space and run again)"
    )
    assert not list((tmp_path / "r" / "runs").glob("*"))
    folder = tmp_path / "results" / "runs"
    folder.mkdir(parents=True)
    shutil.copy(SCHEMA1, folder / "bench-20250101T000000000Z-aaaaaa.json")
    _full_disk(monkeypatch, report, "write_atomically")
    line = one_line(capsys, "report", "--results-dir", str(tmp_path / "results"))
    assert "No space left on device" in line
    assert not (tmp_path / "results" / "README.md").exists()


@pytest.mark.skipif(shutil.which("unshare") is None, reason="needs unshare (util-linux)")
def test_a_really_full_disk_stops_a_real_bench_in_one_line(tmp_path: Path) -> None:
    """On a 64 kB file system (a tmpfs in a user namespace of its own) with 8 kB free."""
    mount = tmp_path / "small"
    mount.mkdir()
    fill = "dd if=/dev/zero of=$0/fill bs=1k count=56 2>/dev/null"
    command = (
        f"mount -t tmpfs -o size=64k tmpfs $0 && {fill} && "
        f"RTC_BENCH_LOCK_DIR=$0/locks {sys.executable} -m rtc.cli {' '.join(BENCH)} "
        "--results-dir $0/results; echo status=$?; ls -A $0 $0/results/runs $0/locks 2>&1"
    )
    probe = subprocess.run(["unshare", "-Urm", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip(f"user namespaces are not allowed here: {probe.stderr.decode().strip()}")
    done = subprocess.run(["unshare", "-Urm", "sh", "-c", command, str(mount)], cwd=ROOT,
                          capture_output=True, text=True, timeout=HANG_SECONDS)  # fmt: skip
    assert "status=2" in done.stdout, (done.stdout, done.stderr)
    assert done.stderr.splitlines()[-1].endswith("nothing was kept (free some space and run "
                                                 "again)")  # fmt: skip
    assert "Traceback" not in done.stderr
    listing = done.stdout.split("status=2", 1)[1]
    assert "bench-" not in listing and ".lock" not in listing and ".staging" not in listing


@pytest.mark.slow
def test_a_stopped_dask_worker_is_replaced_and_its_tasks_go_elsewhere(tmp_path: Path) -> None:
    """Each worker holds a task until this test releases them (a file appears), so the stop
    happens while work is out, for certain; the stopped worker's task runs again elsewhere
    (it waited for ever: Dask's worker-ttl is 5 minutes unless set)."""
    from dask_hold import held

    from variants.dask_cluster import connected

    release = tmp_path / "release"
    with connected(None, 2, 30) as client:
        pids = sorted(client.run(os.getpid).values())
        futures = client.map(held, [str(tmp_path)] * 2, [str(release)] * 2, range(2),
                             pure=False)  # fmt: skip
        deadline = time.monotonic() + HANG_SECONDS
        while len(list(tmp_path.glob("started-*"))) < 2:  # one task on each worker
            assert time.monotonic() < deadline, "the tasks did not start"
            time.sleep(0.05)
        os.kill(pids[0], signal.SIGSTOP)
        try:
            release.touch()
            results = [f.result(timeout=HANG_SECONDS) for f in futures]  # a hang fails, not hangs
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pids[0], signal.SIGKILL)
        assert sorted(index for index, _pid in results) == [0, 1]
        assert pids[0] not in {pid for _index, pid in results}


# ------------------------------------------------------------- what was silently wrong


def _grey_png(path: Path, level: int, bits: int) -> None:
    if bits == 16:
        Image.fromarray(np.full((4, 4), level * 257, dtype=np.uint16)).save(path)
    else:
        Image.fromarray(np.full((4, 4), level, dtype=np.uint8)).save(path)


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_16_bit_grey_texture_shows_its_grey_not_white(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    pixels = []
    for bits in (8, 16):
        _grey_png(tmp_path / f"grey{bits}.png", 64, bits)
        path = texture_scene(tmp_path, f"grey{bits}.png")
        output = tmp_path / f"out{bits}.png"
        assert main(["render", str(path), "--variant", variant, "-o", str(output)]) == 0
        capsys.readouterr()
        width, height, data = read_png(output)
        pixels.append(data[(height // 2 * width + width // 2) * 3])
    assert pixels == [64, 64]  # 25% grey, from 8 bits and from 16 (was 255 from 16)


def test_an_obj_file_that_starts_with_a_byte_order_mark_keeps_its_first_vertex() -> None:
    text = "v 1 2 3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    plain = read_mesh(text.encode(), "plain.obj")
    marked = read_mesh(b"\xef\xbb\xbf" + text.encode(), "marked.obj")
    assert marked.positions.tolist() == plain.positions.tolist() == [[1, 2, 3], [1, 0, 0],
                                                                    [0, 1, 0]]  # fmt: skip
    assert marked.triangles.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize("variant", VARIANTS)
def test_an_obj_model_that_starts_with_a_byte_order_mark_renders_as_without(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    text = b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 9 9 9\nf 1 2 3\n"
    pictures = []
    for name, data in (("plain.obj", text), ("marked.obj", b"\xef\xbb\xbf" + text)):
        (tmp_path / name).write_bytes(data)
        path = obj_scene(tmp_path, name)
        output = tmp_path / f"{name}.png"
        assert main(["render", str(path), "--variant", variant, "-o", str(output)]) == 0
        pictures.append(read_png(output))
    capsys.readouterr()
    assert pictures[0] == pictures[1]
    assert len(set(pictures[0][2])) > 1  # the triangle is in the picture


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_corner_normal_of_length_0_is_refused_naming_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    model = tmp_path / "model.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 0\nf 1//1 2//2 3//1\n",
                     encoding="ascii")  # fmt: skip
    path = obj_scene(tmp_path, model.name)
    line = one_line(capsys, "render", str(path), "--variant", variant,
                    "-o", str(tmp_path / "o.png"))  # fmt: skip
    assert f"{model}, line 5: 'vn 0 0 0': a vertex normal of length 0 has no direction" in line


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize(("written", "words"), [
    ("020", "'020' starts with 0, so YAML 1.1 reads it as the octal number 16; write 20"),
    ("1:30", "'1:30' is a base-60 number to YAML 1.1 (90)"),
])  # fmt: skip
def test_a_yaml_11_number_that_reads_as_another_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str, written: str, words: str
) -> None:
    path = tmp_path / "s.yml"
    path.write_text(CAMERA.replace("width: 8", f"width: {written}") + "- add: sphere\n",
                    encoding="utf-8")  # fmt: skip
    line = one_line(capsys, "render", str(path), "--variant", variant,
                    "-o", str(tmp_path / "o.png"))  # fmt: skip
    assert line.startswith(f"rtc render: {path}:2: the camera's width: {words}")


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_generated_mesh_name_in_another_folder_is_not_written_there(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    path = obj_scene(tmp_path, "elsewhere/ring-1k.obj")
    line = one_line(capsys, "render", str(path), "--variant", variant,
                    "-o", str(tmp_path / "o.png"))  # fmt: skip
    assert "OBJ file not found" in line and "ring-1k.obj" in line
    assert not (tmp_path / "elsewhere").exists()


PEP_508_NAME = re.compile(r"^([A-Z0-9]|[A-Z0-9][A-Z0-9._-]*[A-Z0-9])$", re.IGNORECASE)


@pytest.mark.parametrize(("name", "words"), [
    ("ñame", "'ñame' cannot name a package pip installs"),
    ("_", "'_' cannot name a package pip installs"),
    ("_hidden", "'_hidden' cannot name a package pip installs"),
    ("a" * 300, "a name of 300 characters ('aaaaaaaaaaaaaaaaaaaa'...); at most 64"),
])  # fmt: skip
def test_rtc_new_refuses_a_name_pip_cannot_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, words: str
) -> None:
    line = one_line(capsys, "new", name, "--dir", str(tmp_path / "x"))
    assert line.startswith(f"rtc new: {words}")
    assert not (tmp_path / "x").exists()


def test_rtc_new_writes_a_package_name_pip_can_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import tomllib

    for name in ("x_", "my__tracer2"):
        assert main(["new", name, "--dir", str(tmp_path / name)]) == 0
        data = tomllib.loads((tmp_path / name / "pyproject.toml").read_text(encoding="utf-8"))
        assert PEP_508_NAME.match(data["project"]["name"]), data["project"]["name"]
    capsys.readouterr()
    line = one_line(capsys, "new", "ok", "--dir", str(tmp_path / ("d" * 300)))
    assert "File name too long" in line
