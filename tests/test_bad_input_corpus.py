"""The malformed-input corpus (issue 19, item 4): every scene in ``tests/data/bad_input/``
through ``rtc render`` with the naive, cached and numba variants gives exit status 2, exactly
one line on stderr naming the scene file (and the line at fault), and no image.

Each corpus scene says in its first two lines what it breaks and the error it expects:
``# expect: LINE: TEXT`` (``-`` for an error about the whole file); ``{dir}`` in TEXT stands
for the corpus folder. The scenes are rendered in this process through the command line's
``main`` (all of them take about a second per variant); a few also run as real ``rtc``
processes, where a traceback or a hang would show as it would for a user.
"""

from __future__ import annotations

import re
import resource
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
from holding import HANG_SECONDS

from rtc.cli import main
from scene.limits import DEPTH_VARIABLE, SHAPES_VARIABLE

CORPUS = Path(__file__).parent / "data" / "bad_input"
VARIANTS = ("naive", "cached", "numba")
_EXPECT = re.compile(rb"^# expect: (\d+|-): (.*)$", re.MULTILINE)

# the classes of issue 19 and the classic mistakes: at least these scenes must be present
REQUIRED = (
    "nested-groups-300", "nested-groups-300-flow", "nested-by-definitions", "recursive-alias",
    "billion-laughs-aliases", "billion-laughs-defines", "obj-empty", "obj-binary",
    "obj-bad-face-index", "cylinder-min-above-max", "cone-min-above-max",
    "light-negative-intensity", "material-ambient-minus0_1", "material-diffuse-minus1",
    "material-specular-minus0_5", "material-shininess-0", "material-shininess-minus10",
    "material-transparency-1_5", "material-reflective-minus0_2", "material-refractive-index-0",
    "area-light-usteps-zero", "scale-1e-200", "unknown-key", "wrong-type", "missing-camera",
    "bad-colour-length", "bad-colour-word", "ppm-wrong-magic",
)  # fmt: skip


@dataclass(frozen=True)
class Case:
    """One corpus scene: path; line: where the error must point (None: the whole file);
    text: what the message must contain."""

    path: Path
    line: int | None
    text: str

    @property
    def prefix(self) -> str:
        where = str(self.path) if self.line is None else f"{self.path}:{self.line}"
        return f"rtc render: {where}: "


def _cases() -> list[Case]:
    found = []
    for path in sorted(CORPUS.glob("*.yml")):
        match = _EXPECT.search(path.read_bytes())
        assert match is not None, f"{path.name} has no '# expect: LINE: TEXT' line"
        line = None if match[1] == b"-" else int(match[1])
        text = match[2].decode("utf-8").replace("{dir}", str(CORPUS.resolve()))
        found.append(Case(path, line, text))
    return found


CASES = _cases()


@pytest.fixture(autouse=True)
def _default_limits(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(DEPTH_VARIABLE, raising=False)
    monkeypatch.delenv(SHAPES_VARIABLE, raising=False)


def test_the_corpus_covers_every_class() -> None:
    names = {case.path.stem for case in CASES}
    assert not set(REQUIRED) - names
    assert len(CASES) >= 50


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("case", CASES, ids=lambda case: case.path.stem)
def test_a_bad_scene_is_one_line_exit_2_and_no_image(
    case: Case, variant: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "out.png"
    start = time.thread_time()
    status = main(["render", str(case.path), "--variant", variant, "-o", str(output)])
    work = time.thread_time() - start  # this thread's CPU seconds: neither the load beside the
    # test nor another thread of this process (a warmer, a pool left by an earlier test) adds any
    out, err = capsys.readouterr()
    assert status == 2, out + err
    assert err.count("\n") == 1 and err.endswith("\n"), err
    assert err.startswith(case.prefix), err
    assert case.text in err, err
    assert "Traceback" not in err and "rendering" not in out
    assert not output.exists()
    # no hang: the slowest (the limits) take well under a CPU second here, the first numba
    # case of a process (importing numba) about 1.5; the billion shapes would take hours
    assert work < 10


def _children_cpu() -> float:
    """CPU seconds of this process's children that have ended: the work of a process run to
    its end, which (unlike its wall time) a busy machine does not stretch."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _rtc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "rtc.cli", *args],
        capture_output=True,
        text=True,
        timeout=HANG_SECONDS,
        check=False,
    )


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_real_rtc_process_stops_a_300_deep_scene_in_one_line(
    variant: str, tmp_path: Path
) -> None:
    case = next(c for c in CASES if c.path.stem == "nested-groups-300")
    output = tmp_path / "out.png"
    done = _rtc("render", str(case.path), "--variant", variant, "-o", str(output))
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith(case.prefix)
    assert "RecursionError" not in done.stderr and not output.exists()


def test_a_real_rtc_process_stops_a_billion_shapes_at_once(tmp_path: Path) -> None:
    case = next(c for c in CASES if c.path.stem == "billion-laughs-aliases")
    output = tmp_path / "out.png"
    before = _children_cpu()
    done = _rtc("render", str(case.path), "-o", str(output))
    assert _children_cpu() - before < 30  # the start of a process, not the billion
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and case.text in done.stderr
    assert not output.exists()
