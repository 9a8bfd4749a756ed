"""The learner's path end to end: ``rtc new`` scaffolds a tracer, it is installed for the
test only, and ``rtc kata`` (plain, ``--next``, ``--watch``) runs it in subprocesses.

How the scaffold is installed: an editable install (``pip install -e FOLDER``) leaves two
things behind, the distribution's metadata (with the entry point that the generated
``pyproject.toml`` declares) and a path to the source folder. The ``learner`` fixture writes
exactly that into a private folder: ``TMP/site/<dist>.dist-info`` with ``entry_points.txt``
read from the generated ``pyproject.toml``, and runs rtc with ``PYTHONPATH=TMP/site:FOLDER``.
The registry then finds the variant through ``importlib.metadata`` as it would after pip,
every new process sees the edits to ``tracer.py``, and the shared environment is never
touched (nothing to uninstall if a test fails). pip itself is not used because it cannot
build offline here: the venv's setuptools 65 has no ``bdist_wheel`` without the ``wheel``
package (so ``--no-build-isolation`` fails), and an isolated build downloads setuptools.
"""

from __future__ import annotations

import json
import os
import queue
import re
import signal
import subprocess
import sys
import threading
import time
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from holding import HANG_SECONDS

from raytracer.api import BOOK_API
from rtc.cli import main
from steps.kata import PROJECT_FEATURES

# not the name `rtc new`'s help suggests (my_tracer), nor the README's (mine): a learner who
# has installed a tracer of that name where the suite runs would make `rtc new NAME` refuse
NAME = "suite_learner_tracer"
CHAPTER_1 = [name for name, chapter in BOOK_API.items() if chapter == 1]

# What a learner writes for chapter 1 (appended to tracer.py: it rebinds the stubs' names).
CHAPTER_1_CODE = """

# ---- chapter 1, written by the learner ----
import math


class Tup:
    def __init__(self, x, y, z, w):
        self.x, self.y, self.z, self.w = x, y, z, w

    def __add__(self, other):
        return Tup(self.x + other.x, self.y + other.y, self.z + other.z, self.w + other.w)

    def __sub__(self, other):
        return Tup(self.x - other.x, self.y - other.y, self.z - other.z, self.w - other.w)

    def __neg__(self):
        return Tup(-self.x, -self.y, -self.z, -self.w)

    def __mul__(self, k):
        return Tup(self.x * k, self.y * k, self.z * k, self.w * k)

    def __truediv__(self, k):
        return Tup(self.x / k, self.y / k, self.z / k, self.w / k)


def tuple_(x, y, z, w):
    return Tup(x, y, z, w)


def point(x, y, z):
    return Tup(x, y, z, 1.0)


def vector(x, y, z):
    return Tup(x, y, z, 0.0)


def magnitude(v):
    return math.sqrt(v.x**2 + v.y**2 + v.z**2 + v.w**2)


def normalize(v):
    return v / magnitude(v)


def dot(a, b):
    return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w


def cross(a, b):
    return vector(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)


EPSILON = 0.0001
"""


@dataclass
class Learner:
    """A scaffolded tracer, installed for one test."""

    folder: Path
    env: dict[str, str]

    @property
    def tracer(self) -> Path:
        return self.folder / NAME / "tracer.py"

    def command(self, *args: str) -> list[str]:
        return [sys.executable, "-m", "rtc.cli", *args]

    def rtc(self, *args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            self.command(*args), env=self.env, capture_output=True, text=True, timeout=HANG_SECONDS
        )

    def write(self, code: str) -> None:
        with self.tracer.open("a", encoding="utf-8") as out:
            out.write(code)


def install_for_test(folder: Path, site: Path) -> dict[str, str]:
    """What ``pip install -e folder`` amounts to, in ``site``: the metadata with the entry
    points of ``folder/pyproject.toml``; returns the environment that sees it."""
    project = tomllib.loads((folder / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    dist = site / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n",
        encoding="utf-8",
    )
    sections = [
        f"[{group}]\n" + "".join(f"{key} = {value}\n" for key, value in table.items())
        for group, table in project["entry-points"].items()
    ]
    (dist / "entry_points.txt").write_text("\n".join(sections), encoding="utf-8")
    paths = [str(site), str(folder), os.environ.get("PYTHONPATH", "")]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p)}


@pytest.fixture
def learner(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> Learner:
    folder = tmp_path / "mine"
    assert main(["new", NAME, "--dir", str(folder)]) == 0
    printed = capsys.readouterr().out
    assert f"-m pip install -e {folder}" in printed
    assert f"kata --variant {NAME} --chapter 1" in printed
    return Learner(folder, install_for_test(folder, tmp_path / "site"))


def kata_json(learner: Learner, *args: str) -> dict:  # type: ignore[type-arg]
    done = learner.rtc("kata", "--variant", NAME, "--json", *args)
    assert done.returncode in (0, 1), done.stderr
    return json.loads(done.stdout)


def first_scenario_of_chapter_1() -> tuple[int, int, str]:
    """In tuples.feature: the line of the first @chapter01 scenario, of its first step, and
    that step's text (read from the file, not written down here)."""
    lines = (PROJECT_FEATURES / "tuples.feature").read_text(encoding="utf-8").splitlines()
    tag = next(n for n, text in enumerate(lines, 1) if text.strip() == "@chapter01")
    scenario = next(n for n in range(tag + 1, len(lines) + 1) if "Scenario" in lines[n - 1])
    return scenario, scenario + 1, lines[scenario].strip()


@pytest.mark.slow
def test_a_fresh_scaffold_is_all_to_do_and_writing_chapter_1_passes_it(
    learner: Learner,
) -> None:
    fresh = kata_json(learner)
    assert fresh["results"], "no scenario ran"
    assert {r["status"] for r in fresh["results"]} == {"todo"}
    assert all("is not written yet" in r["message"] for r in fresh["results"])
    rows = {row["chapter"]: row for row in fresh["summary"]}
    assert list(rows) == sorted(rows) and 1 in rows
    first = rows[1]
    assert first["todo"] > 0 and first["passed"] == first["failed"] == first["undefined"] == 0
    assert first["code"] == f"own 0/{len(CHAPTER_1)}" and sorted(first["stubs"]) == sorted(
        CHAPTER_1
    )
    chapter_1 = [r for r in fresh["results"] if r["chapter"] == 1]
    assert {r["missing"] for r in chapter_1} <= set(CHAPTER_1)
    assert all(str(learner.tracer) in r["origin"] for r in chapter_1)

    learner.write(CHAPTER_1_CODE)
    written = kata_json(learner)
    rows = {row["chapter"]: row for row in written["summary"]}
    assert rows[1]["passed"] == len(chapter_1)
    assert rows[1]["failed"] == rows[1]["todo"] == rows[1]["undefined"] == 0
    assert rows[1]["code"] == f"own {len(CHAPTER_1)}/{len(CHAPTER_1)}"
    others = [r for r in written["results"] if r["chapter"] != 1]
    assert others and {r["status"] for r in others} == {"todo"}
    assert not written["ok"]


@pytest.mark.slow
def test_next_shows_the_first_scenario_with_the_missing_function_then_a_failed_check(
    learner: Learner,
) -> None:
    done = learner.rtc("kata", "--variant", NAME, "--next")
    assert done.returncode == 1, done.stderr
    out = done.stdout
    scenario_line, step_line, step_text = first_scenario_of_chapter_1()
    assert out.startswith(f"next for {NAME}: chapter 1, Tuples, Points, and Vectors: 0 passed")
    assert f"tuples.feature:{scenario_line}\n" in out
    assert re.search(rf"^→ +{step_line} +{re.escape(step_text)}$", out, re.MULTILINE)
    assert "to do: the book's tuple() is not written yet (chapter 1, Tuples, Points, and" in out
    where = re.search(r"write it in (\S+):(\d+) in tuple_\(\)", out)
    assert where, out
    stub_line = learner.tracer.read_text(encoding="utf-8").splitlines()[int(where[2]) - 1]
    assert stub_line.strip() == 'raise NotImplementedYet("tuple")'

    learner.write(CHAPTER_1_CODE.replace("math.sqrt(", "("))  # forgot the square root
    done = learner.rtc("kata", "--variant", NAME, "--next", "--chapter", "1")
    assert done.returncode == 1, done.stderr
    assert "failed: Then magnitude(v) = √14" in done.stdout
    assert re.search(r"^  expected: 3\.74\d*$", done.stdout, re.MULTILINE), done.stdout
    assert re.search(r"^  got: +14(\.0)?$", done.stdout, re.MULTILINE), done.stdout


def test_rtc_new_twice_leaves_the_learners_files_alone(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    folder = tmp_path / "mine"
    assert main(["new", NAME, "--dir", str(folder)]) == 0
    tracer = folder / NAME / "tracer.py"
    edited = tracer.read_text(encoding="utf-8").replace(
        'def cross(a, b):\n    """', 'def crossed(a, b):\n    """'
    )
    edited += "\n\ndef mine():\n    return 42\n"
    tracer.write_text(edited, encoding="utf-8")
    pyproject = (folder / "pyproject.toml").read_text(encoding="utf-8") + "# my note\n"
    (folder / "pyproject.toml").write_text(pyproject, encoding="utf-8")
    (folder / "README.md").unlink()
    capsys.readouterr()

    assert main(["new", NAME, "--dir", str(folder)]) == 0
    out = capsys.readouterr().out
    assert tracer.read_text(encoding="utf-8") == edited
    assert (folder / "pyproject.toml").read_text(encoding="utf-8") == pyproject
    assert (folder / "README.md").is_file()
    assert "added the missing: README.md" in out
    assert f"left alone: pyproject.toml, {NAME}/__init__.py, {NAME}/variant.py, " in out
    assert f"{NAME}/tracer.py does not define 1 book names" in out and ": cross" in out


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("2fast", "'2fast' is not a Python identifier"),
        ("class", "'class' is not a Python identifier"),
        ("all", "'all' means every variant"),
        ("naive", "there is already a variant called 'naive'"),
        ("json", "a Python module called 'json' already exists"),
    ],
)
def test_rtc_new_refuses_a_name_that_cannot_be_a_new_variant(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, message: str
) -> None:
    assert main(["new", name, "--dir", str(tmp_path / "x")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_rtc_new_refuses_a_folder_that_is_another_project(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "other"\n', encoding="utf-8")
    assert main(["new", NAME, "--dir", str(tmp_path)]) == 2
    assert f"does not register the variant '{NAME}'" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pyproject.toml"]


def _lines(stream: object, into: queue.Queue[str]) -> None:
    for line in iter(stream.readline, ""):  # type: ignore[attr-defined]
        into.put(line)


def _wait_for(lines: queue.Queue[str], pattern: str, seen: list[str], timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            line = lines.get(timeout=0.2)
        except queue.Empty:
            continue
        seen.append(line)
        if re.search(pattern, line):
            return
    raise AssertionError(f"no line matching {pattern!r} in {timeout} s; output:\n{''.join(seen)}")


@dataclass
class Watcher:
    """``rtc kata --watch`` running: its output read as it comes, line by line."""

    process: subprocess.Popen[str]
    lines: queue.Queue[str]
    errors: queue.Queue[str]
    readers: list[threading.Thread]

    def all_errors(self) -> str:
        """Everything on its stderr, once it has exited: the readers have reached the end."""
        for reader in self.readers:
            reader.join(timeout=HANG_SECONDS)
            assert not reader.is_alive(), "hang guard: its output is still open"
        return "".join(self.errors.get() for _ in range(self.errors.qsize()))


@pytest.fixture
def watcher(learner: Learner) -> Iterator[Watcher]:
    """``rtc kata --watch`` on the learner's package as a terminal starts it (Ctrl-C not
    ignored, even when this test runs in a background job, which ignores SIGINT and passes
    that on), its stdout and stderr read as they come."""
    process = subprocess.Popen(
        learner.command("kata", "--variant", NAME, "--chapter", "1", "--watch"),
        env=learner.env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    lines: queue.Queue[str] = queue.Queue()
    errors: queue.Queue[str] = queue.Queue()
    readers = [
        threading.Thread(target=_lines, args=(process.stdout, lines), daemon=True),
        threading.Thread(target=_lines, args=(process.stderr, errors), daemon=True),
    ]
    for reader in readers:
        reader.start()
    try:
        yield Watcher(process, lines, errors, readers)
    finally:
        if process.poll() is None:
            process.kill()
        process.wait(timeout=HANG_SECONDS)


@pytest.mark.slow
def test_watch_runs_again_when_the_learner_saves_and_stops_cleanly_on_ctrl_c(
    learner: Learner, watcher: Watcher
) -> None:
    process, lines = watcher.process, watcher.lines
    seen: list[str] = []
    _wait_for(lines, r"^── watching ", seen, timeout=HANG_SECONDS)
    first = "".join(seen)
    assert "run 1 at" in first and f"own 0/{len(CHAPTER_1)}" in first

    learner.write(CHAPTER_1_CODE)
    seen.clear()
    _wait_for(lines, r"^── run 2 finished", seen, timeout=HANG_SECONDS)
    second = "".join(seen)
    assert re.search(r"^── rtc kata --watch: run 2 at .*\(changed: .*tracer\.py\)$", second, re.M)
    assert re.search(rf"own {len(CHAPTER_1)}/{len(CHAPTER_1)} +\d+ +0 +0 +0", second), second

    _wait_for(lines, r"^── watching ", seen, timeout=HANG_SECONDS)
    process.send_signal(signal.SIGINT)
    assert process.wait(timeout=HANG_SECONDS) in (0, 130)
    assert "Traceback" not in watcher.all_errors()  # all of it: the readers have finished


@pytest.mark.slow
def test_all_leaves_a_half_written_tracer_out_and_runs_it_when_named(learner: Learner) -> None:
    """With a fresh scaffold installed (every book name a stub), ``--variant all`` is still
    the project's own variants, so ``python3 run.py test`` stays green; the learner's
    tracer is listed by ``rtc variants`` and runs when named."""
    root = Path(__file__).resolve().parent.parent
    features = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:randomly", "-p", "no:cacheprovider",
         "tests/test_features.py", "--variant", "all", "-k", "tuple and point"],
        cwd=root, env=learner.env, capture_output=True, text=True, timeout=HANG_SECONDS,
    )  # fmt: skip
    assert features.returncode == 0, features.stdout[-2000:] + features.stderr[-2000:]
    assert f"[{NAME}]" not in features.stdout and "passed" in features.stdout
    listed = learner.rtc("variants")
    assert (
        listed.returncode == 0
        and listed.stdout.count(f"\n{NAME} ") + (listed.stdout.startswith(f"{NAME} ")) == 1
    ), listed.stdout
    everyone = learner.rtc("kata", "--variant", "all", "--json", "--chapter", "1")
    assert everyone.returncode in (0, 1), everyone.stderr
    assert NAME not in json.loads(everyone.stdout)["variants"]
    assert kata_json(learner, "--chapter", "1")["variants"] == [NAME]
