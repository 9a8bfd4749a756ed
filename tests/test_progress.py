"""Progress on stderr (issue 28, item 3): ``groundwork.progress`` on a clock of the test's
own, every variant family's render reporting all its rows, numba's bands, the line that names
a faster variant for a render that will take long, and ``rtc render --help`` naming the
registry's variants. No verdict here depends on how fast the machine is: the clocks are the
tests'."""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np
import pytest
from book_world import default_scene

from groundwork.progress import Progress, Ticker, compile_ticker, duration
from raytracer.camera import RenderSettings
from rtc import cmd_render
from rtc.cli import main
from variants.registry import load_variant, variant_names


class Clock:
    """A clock of the test's: it moves only when the test moves it, or by ``step`` at each
    reading."""

    def __init__(self, step: float = 0.0) -> None:
        self.now = 100.0
        self.step = step

    def __call__(self) -> float:
        self.now += self.step
        return self.now


def lines_of(stream: io.StringIO) -> list[str]:
    return stream.getvalue().splitlines()


# ------------------------------------------------------------------------ groundwork.progress


def test_nothing_is_shown_before_the_delay_then_a_plain_line_every_so_often() -> None:
    clock, out = Clock(), io.StringIO()
    progress = Progress("rtc render", 100, "row", mode="lines", stream=out, clock=clock)
    clock.now += 0.5
    progress(10)
    assert out.getvalue() == "" and not progress.shown  # within the delay: quiet
    clock.now += 0.5
    progress(10)  # 20 rows in 1 s
    assert lines_of(out) == ["rtc render: 20/100 rows, 1 s so far, about 4 s left"]
    clock.now += 5
    progress(10)  # 5 s after the first line: not yet
    assert len(lines_of(out)) == 1
    clock.now += 5
    progress(20)
    assert lines_of(out)[-1] == "rtc render: 50/100 rows, 11 s so far, about 11 s left"
    clock.now += 10
    progress(50)
    assert lines_of(out)[-1] == "rtc render: 100/100 rows, 21 s so far"  # nothing left
    progress.close()
    assert progress.lines == 3


def test_a_job_within_the_delay_shows_nothing_in_any_mode() -> None:
    for mode in ("bar", "lines", "none"):
        out = io.StringIO()
        progress = Progress("rtc render", 4, "row", mode=mode, stream=out, clock=Clock(0.1))
        for _ in range(4):
            progress(1)
        progress.close()
        assert out.getvalue() == "" and not progress.shown, mode


def test_the_bar_opens_after_the_delay_and_reaches_the_total() -> None:
    clock, out = Clock(), io.StringIO()
    progress = Progress("rtc render", 50, "row", mode="bar", stream=out, clock=clock)
    progress(5)
    assert progress.bar is None
    clock.now += 2
    progress(5)
    assert progress.bar is not None and progress.bar.n == 10 and progress.bar.total == 50
    for _ in range(40):
        progress(1)
    assert progress.bar.n == 50
    progress.close()
    assert progress.bar is None and progress.shown
    assert "rtc render" in out.getvalue()


def test_auto_is_lines_where_stderr_is_not_a_terminal() -> None:
    assert Progress("x", 1, "row", stream=io.StringIO()).mode == "lines"
    with pytest.raises(ValueError, match="progress mode 'loud'"):
        Progress("x", 1, "row", mode="loud")


def test_none_shows_nothing_however_long() -> None:
    clock, out = Clock(step=60.0), io.StringIO()
    progress = Progress("rtc render", 3, "row", mode="none", stream=out, clock=clock)
    for _ in range(3):
        progress(1)
    assert out.getvalue() == "" and progress.done == 3


def test_time_excluded_and_a_total_learned_late_count_from_then() -> None:
    clock, out = Clock(), io.StringIO()
    progress = Progress("rtc kata", 0, "scenario", mode="lines", stream=out, clock=clock)
    clock.now += 30  # pytest collecting
    progress.set_total(10)
    clock.now += 0.5
    progress(1)
    assert out.getvalue() == ""  # the 30 s before the total do not count
    clock.now += 20
    progress.exclude(19)  # a compile
    progress(1)
    assert lines_of(out) == ["rtc kata: 2/10 scenarios, 2 s so far, about 6 s left"]


def test_durations_read_as_a_person_says_them() -> None:
    assert [duration(s) for s in (0.2, 8, 59.6, 215, 3600 + 300)] == [
        "0 s", "8 s", "1 min 00 s", "3 min 35 s", "1 h 05 min",
    ]  # fmt: skip


def test_advice_is_shown_once_above_the_progress_for_a_long_estimate() -> None:
    clock, out = Clock(), io.StringIO()
    asked: list[float] = []

    def advice(seconds: float) -> str | None:
        asked.append(seconds)
        return "this will take long" if seconds > 60 else None

    progress = Progress("rtc render", 100, "row", mode="lines", stream=out, clock=clock,
                        advice=advice)  # fmt: skip
    clock.now += 0.5
    progress(1)
    assert asked == []  # not asked within the delay
    clock.now += 1.5
    progress(9)  # 10 rows in 2 s: 20 s in all
    assert asked == [20.0] and "this will take long" not in out.getvalue()
    clock.now += 18
    progress(10)  # 20 rows in 20 s: 100 s in all
    clock.now += 20
    progress(10)
    assert lines_of(out).count("this will take long") == 1
    assert lines_of(out)[1] == "this will take long"  # before the line that prompted it
    assert asked == [20.0, 100.0]  # never asked again once said


# ---------------------------------------------------- the "will take long" line of rtc render


def test_a_slow_variant_estimated_long_is_told_of_numba() -> None:
    advise = cmd_render._advice("naive", RenderSettings())
    assert advise is not None
    assert advise(5.0) is None and advise(cmd_render.LONG_SECONDS - 1) is None
    line = advise(215.0)
    assert line is not None
    assert line.startswith("rtc render: naive will take about 3 min 35 s for this render; ")
    assert "--variant numba renders it in under a second" in line
    slow = cmd_render._advice("prealloc", RenderSettings())
    assert slow is not None and "in about 3 s" in (slow(300.0) or "")


@pytest.mark.parametrize("name", ["numba", "numba[threads=1]", "pooled:numba", "wavefront"])
def test_a_compiled_variant_is_not_told_of_numba(name: str) -> None:
    assert cmd_render._advice(name, RenderSettings()) is None


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.yml"
    path.write_text(
        "- add: camera\n  width: 8\n  height: 6\n  field-of-view: 1.0\n  from: [0, 1, -4]\n"
        "  to: [0, 0.5, 0]\n  up: [0, 1, 0]\n- add: light\n  at: [-4, 4, -4]\n"
        "  intensity: [1, 1, 1]\n- add: plane\n- add: sphere\n",
        encoding="utf-8",
    )
    return path


def test_rtc_render_estimated_long_says_so_once_and_shows_lines(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each reading of the render's clock is 20 s later: 6 rows are a long render."""
    monkeypatch.setattr(cmd_render, "_clock", Clock(step=20.0))
    output = tmp_path / "out.png"
    assert main(["render", str(tiny), "-o", str(output), "--progress", "lines"]) == 0
    out, err = capsys.readouterr()
    lines = err.splitlines()
    advice = [line for line in lines if "--variant numba" in line]
    assert len(advice) == 1 and advice[0].startswith("rtc render: naive will take about ")
    progress = [line for line in lines if re.match(r"rtc render: \d+/6 rows, ", line)]
    assert progress and progress[-1].startswith("rtc render: 6/6 rows, ")
    assert len(lines) == len(progress) + 1 and lines[0] == advice[0]
    assert output.exists() and "rendered in" in out


def test_rtc_render_within_a_second_shows_nothing(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(cmd_render, "_clock", Clock(step=0.01))
    for mode in ("auto", "lines", "bar"):
        assert main(["render", str(tiny), "-o", str(tmp_path / "o.png"), "--progress", mode]) == 0
        _, err = capsys.readouterr()
        assert err == "", mode


def test_rtc_render_help_lists_exactly_the_registered_variants(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit):
        main(["render", "--help"])
    text = " ".join(capsys.readouterr().out.split())  # argparse wraps the lines
    listed = re.search(r"the tracer to use, one of: (.*?) \(default: naive", text)
    assert listed is not None, text
    assert listed.group(1).split(", ") == variant_names()


# ------------------------------------------------------------------ every family's rows


FAMILIES = [
    "naive", "cached", "prealloc", "robust",
    "pooled[workers=2]:cached", "pooled[granularity=pixel,workers=2]:cached",
    "pooled[granularity=tile,tile=4,workers=2]:cached", "dask[tile=4,workers=2]:cached",
    "numba", "numba[float32,threads=1]", "wavefront", "wavefront[max_mb=1]",
]  # fmt: skip


@pytest.mark.parametrize("name", FAMILIES)
def test_every_family_reports_every_row_once(name: str) -> None:
    """``rtc render``'s bar counts rows: each family's render reports all of them, in
    pieces that add up (a row never twice), whether it renders rows, pixels, tiles, chunks
    of rows or passes."""
    variant = load_variant(name)
    c, w = default_scene(variant, 13, 11)
    rows: list[int] = []
    variant.api["render"](c, w, RenderSettings(), rows.append)
    assert sum(rows) == 11 and all(n > 0 for n in rows), rows


def test_wavefront_reports_each_pass() -> None:
    """wavefront[max_mb=1]: passes of 512 rays, so 13x110 pixels take three."""
    variant = load_variant("wavefront[max_mb=1]")
    c, w = default_scene(variant, 13, 110)
    rows: list[int] = []
    variant.api["render"](c, w, RenderSettings(), rows.append)
    assert sum(rows) == 110 and len(rows) > 1


# ----------------------------------------------------------------------- numba's chunks


def test_a_numba_threads_chunks_are_sized_by_their_time() -> None:
    from variants.numba.render import CHUNK_GROWTH, CHUNK_SECONDS, chunk_rows

    assert chunk_rows(500, 0, 0.0) == 1  # a first row, then by their time
    assert chunk_rows(500, 10, CHUNK_SECONDS) == 10  # the same rate: the same rows
    assert chunk_rows(500, 10, 100.0) == 1  # slow rows: a report after each
    assert chunk_rows(500, 10, 0.0) == 10 * CHUNK_GROWTH  # fast rows grow by at most this
    assert chunk_rows(7, 10, 0.0) == 7  # never past the rows left


def test_numba_in_chunks_is_the_same_picture_as_in_one_call(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``CHUNK_SECONDS`` 0: every chunk is one row; one thread reports each row, whatever
    the machine's speed (with more, the calling thread reports after each of its chunks,
    and how many it takes depends on the machine)."""
    from variants.numba import render as numba_render

    variant = load_variant("numba")
    c, w = default_scene(variant, 24, 40)
    whole = variant.api["render"](c, w, RenderSettings())
    monkeypatch.setattr(numba_render, "CHUNK_SECONDS", 0.0)
    rows: list[int] = []
    chunked = variant.api["render"](c, w, RenderSettings(), rows.append)
    assert sum(rows) == 40
    assert np.array_equal(whole.array, chunked.array)
    one = load_variant("numba[threads=1]")  # one thread: every row its own report
    rows.clear()
    alone = one.api["render"](c, w, RenderSettings(), rows.append)
    assert rows == [1] * 40 and np.array_equal(whole.array, alone.array)


# ---------------------------------------------------------------- the compile's ticker


def test_the_ticker_speaks_at_each_interval_until_stopped() -> None:
    said: list[float] = []
    clock = Clock()
    ticker = Ticker(said.append, every=10.0, clock=clock)
    waits = iter([False, False, False, True])

    def wait(seconds: float) -> bool:
        assert seconds == 10.0
        clock.now += seconds
        return next(waits)

    ticker.wait = wait
    ticker.run()  # in this thread: three intervals pass, then the stop
    assert said == [10.0, 20.0, 30.0]


def test_the_compile_ticker_stops_when_the_compile_ends() -> None:
    said: list[str] = []
    listener = compile_ticker(said.append, every=3600.0)
    listener("a kernel", None)
    listener("a kernel", 1.5)  # joins the ticker's thread: none is left running
    import threading

    assert not [t for t in threading.enumerate() if t.name == "rtc-ticker"]
    assert said == []  # an hour never passed
