"""``rtc profile`` and ``rtc bench --sections profile`` (``harness.sections.profile.measure``, issue
18): the command's tables and flame graph for a tiny render, numba's stages, the one-line errors,
the figures read off cProfile, and the report's "Where the time goes" section."""

from __future__ import annotations

import cProfile
import json
import marshal
import pstats
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from groundwork.sizes import Size
from harness.document.model import Table, to_html, to_markdown
from harness.sections import DEFAULTS as DEFAULT_SECTIONS
from harness.sections import NAMES as SECTIONS
from harness.sections.profile import measure as profiling
from harness.sections.profile import profiler
from harness.sections.profile import report as profiling_report
from harness.sections.profile import stats as profile_stats
from rtc.cli import main

REFERENCE = Path(__file__).resolve().parent.parent / "scenes" / "reference.yml"


# --- the command ----------------------------------------------------------------------------


def test_rtc_profile_prints_both_tables_and_writes_a_flame_graph(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(
        ["profile", str(REFERENCE), "--variant", "naive", "--size", "4x3", "--top", "5",
         "-o", str(tmp_path)]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0
    lines = out.splitlines()
    own = lines.index("top 5 functions by own time (% of the render):")
    cum = next(i for i, line in enumerate(lines) if line.startswith("top 5 functions by cum"))
    for start in (own, cum):
        share = "own" if start == own else "cum"
        header = ["calls", "own", "s", "cum", "s", share, "%", "function"]
        assert lines[start + 1].split() == header
        rows = lines[start + 2 : start + 7]
        assert all(row.strip().split()[-1] and "%" in row for row in rows)
    # naive's time goes into inverting matrices: the own-time table is raytracer's code
    assert "raytracer/matrices.py:" in "\n".join(lines[own + 2 : own + 7])
    assert "Tracer.render_into" in "\n".join(lines[cum + 2 : cum + 7])
    assert "what it shows: naive: " in out and "function calls per pixel" in out
    flame = tmp_path / "profile-reference-naive.svg"
    assert flame.is_file() and flame.stat().st_size > 1000
    assert flame.read_text(errors="replace").lstrip().startswith(("<?xml", "<svg"))
    assert f"flame graph: {flame}" in out
    stats = pstats.Stats(str(tmp_path / "profile-reference-naive.pstats"))
    assert stats.total_calls > 1000  # type: ignore[attr-defined]
    assert (tmp_path / "profile-reference-naive.png").is_file()


def test_numba_is_profiled_by_its_stages_which_add_up_to_the_wall_time(tmp_path: Path) -> None:
    request = profiler.Request(
        variant="numba", scene=REFERENCE, size=Size(16, 12), folder=tmp_path, stem="n",
        flame=False, compiled=True,
    )  # fmt: skip
    entry = profiler.profile(request, tmp_path / "jobs", lambda message: None)
    assert entry["status"] == "ok", entry.get("error")
    stages = entry["stages"]
    assert list(stages) == ["load", "pack", "compile", "trace", "encode"]
    assert all(seconds > 0 for seconds in stages.values())
    assert sum(stages.values()) == pytest.approx(entry["wall"], rel=0.05)
    assert "cprofile" not in entry and "cprofile_skipped" in entry
    assert entry["kernels"].startswith(("loaded from the kernel cache", "built now"))
    assert entry["trace_again"] > 0
    finding = profile_stats.findings(entry)
    assert finding.startswith("numba: of ") and "pack (world to arrays" in finding
    text = "\n".join(profiling_report.text(entry, 10))
    assert "compile or cache load" in text and "cProfile: not run" in text


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["--variant", "nope", str(REFERENCE)], "rtc profile: --variant: unknown variant 'nope'"),
        (["--variant", "naive", "missing.yml"], "rtc profile: missing.yml: cannot read the scene"),
        (["--variant", "naive", str(REFERENCE), "--size", "32by24"], "rtc profile: bad --size"),
        (["--variant", "naive", str(REFERENCE), "--size", "0x3"], "rtc profile: bad --size"),
    ],
)
def test_a_mistake_is_one_line_and_exit_status_2(
    args: list[str], expected: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["profile", *args, "-o", str(tmp_path)]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(expected)
    assert captured.err.count("\n") == 1 and "Traceback" not in captured.err
    assert list(tmp_path.iterdir()) == []


def test_a_broken_scene_file_names_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scene = tmp_path / "bad.yml"
    scene.write_text("- add: camera\n  width: 10\n")
    assert main(["profile", str(scene), "--variant", "naive", "-o", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rtc profile: {scene}:1: ") and err.count("\n") == 1


def test_the_default_size_is_the_camera_scaled_to_about_768_pixels() -> None:
    assert profiler.profile_size(Size(640, 480)) == Size(32, 24)
    assert profiler.profile_size(Size(20, 10)) == Size(20, 10)  # small already: kept
    assert profiler.profile_size(Size(500, 500)).pixels <= profiler.DEFAULT_PIXELS
    # a naive probe (10 ms per pixel): the same; a compiled one (0.2 µs): a trace of ~0.5 s
    assert profiler.profile_size(Size(640, 480), 0.01) == Size(32, 24)
    fast = profiler.profile_size(Size(640, 480), 2e-7)
    assert fast.width * 3 == fast.height * 4 and fast.pixels == pytest.approx(2_000_000, rel=0.01)
    assert profiler.profile_size(Size(640, 480), 1e-5) == Size(256, 192)  # 50,000: shrunk


# --- the figures ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Small:
    x: float


@dataclass(frozen=True)
class Large:
    y: float


def _inner(n: int) -> list[Any]:
    return [Small(i) for i in range(n)] + [Large(i) for i in range(2 * n)]


def _outer(n: int) -> int:
    return len(_inner(n))


def test_every_dataclass_init_keeps_its_own_calls_where_pstats_merges_them() -> None:
    profile = cProfile.Profile()
    profile.enable()
    _outer(300)
    profile.disable()
    table = profile_stats.collect(profile)
    calls = {key[2]: row[1] for key, row in table.items() if key[0] == "<string>"}
    assert calls[f"{Small.__qualname__}.__init__"] == 300
    assert calls[f"{Large.__qualname__}.__init__"] == 600
    # pstats' own table keys both as ('<string>', 2, '__init__') and keeps one of them
    merged = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    assert sum(1 for key in merged if key[0] == "<string>") == 1
    summary = profile_stats.summarize(table, 3)
    assert summary["calls"] == sum(row[1] for row in table.values())
    assert summary["total"] == pytest.approx(sum(row[2] for row in table.values()))
    # building objects: the two __init__s' own time (nothing built-in is called from them)
    inits = sum(row[2] for key, row in table.items() if key[2].endswith(".__init__"))
    assert summary["constructors"] == pytest.approx(inits) and inits > 0
    assert len(summary["top_own"]) == 3 and summary["half"] >= 1


def test_the_hot_chain_climbs_callers_in_the_same_file() -> None:
    # c (own time) <- b <- a, all in one file; a is called from another file; P.__init__
    # calls a built-in that c calls too: the part it spends for P.__init__ is building objects
    a, b, c, other = ("f.py", 1, "a"), ("f.py", 5, "b"), ("f.py", 9, "c"), ("g.py", 1, "main")
    init, builtin = ("h.py", 3, "P.__init__"), ("~", 0, "<built-in method math.sqrt>")
    table: dict[Any, tuple[Any, ...]] = {
        other: (1, 1, 0.0, 1.0, {}),
        a: (1, 1, 0.01, 1.0, {other: (1, 1, 0.01, 1.0)}),
        b: (2, 2, 0.09, 0.99, {a: (2, 2, 0.09, 0.99)}),
        c: (9, 9, 0.7, 0.9, {b: (9, 9, 0.7, 0.9)}),
        init: (4, 4, 0.05, 0.1, {c: (4, 4, 0.05, 0.1)}),
        builtin: (5, 5, 0.15, 0.15, {init: (2, 2, 0.05, 0.05), c: (3, 3, 0.1, 0.1)}),
    }
    summary = profile_stats.summarize(table, 2)
    assert summary["hot"] == {"function": "f.py:1 a", "cum": 1.0}
    assert summary["constructors"] == pytest.approx(0.05 + 0.05)
    assert summary["half"] == 1 and summary["total"] == pytest.approx(1.0)
    entry = {"name": "v", "cprofile": summary, "pixels": 10}
    assert profile_stats.findings(entry).startswith("v: 100% of the render in `a()` (f.py)")


def test_labels_are_shortened_to_the_project() -> None:
    key = (str(profile_stats.ROOT / "raytracer" / "matrices.py"), 139, "inverse")
    assert profile_stats.label(key) == "raytracer/matrices.py:139 inverse"
    assert profile_stats.label(("~", 0, "<built-in method builtins.len>")) == (
        "<built-in method builtins.len>"
    )


# --- the bench section and the report -----------------------------------------------------------


def test_the_section_is_offered_but_not_run_by_default() -> None:
    assert "profile" in SECTIONS and "profile" not in DEFAULT_SECTIONS


def test_the_bench_section_records_entries_and_keeps_the_flame_graph(tmp_path: Path) -> None:
    images = tmp_path / "run"
    images.mkdir()
    plan = profiling.Plan(scene=REFERENCE, size=Size(4, 3), variants=("prealloc", "nope"))
    entries = profiling.run(plan, tmp_path / "jobs", lambda message: None, images, "run")
    assert [e["name"] for e in entries] == ["prealloc", "nope"]
    done, missing = entries
    assert missing["status"] == "unavailable" and "nope" in missing["error"]
    assert done["status"] == "ok" and done["flame"] == "run/profile-prealloc.svg"
    assert (images / "profile-prealloc.svg").stat().st_size > 1000
    assert done["finding"].startswith("prealloc: ")
    assert len(done["cprofile"]["top_own"]) >= profiling.REPORT_TOP
    json.dumps(entries)  # the run file keeps them as they are

    run = {"series": [{"section": "scene-size", "name": "x"}, *entries]}
    blocks = profiling_report.blocks(run, None, "context line")
    markdown = to_markdown(blocks)
    assert markdown.startswith("## Where the time goes")
    assert "[runs/run/profile-prealloc.svg](runs/run/profile-prealloc.svg)" in markdown
    assert "prealloc: not profiled" not in markdown and "nope: not profiled" in markdown
    tables = [b for b in blocks if isinstance(b, Table)]
    overview, functions = tables
    assert [row[0] for row in overview.rows] == ["`prealloc`"]
    assert len(functions.rows) == profiling.REPORT_TOP
    html = to_html(blocks, tmp_path, "t")
    assert '<a href="runs/run/profile-prealloc.svg">' in html
    assert profiling_report.newest([run, {"series": []}]) is run
    assert profiling_report.console_lines(run)[0] == done["finding"]


def test_the_pstats_file_is_the_collected_table(tmp_path: Path) -> None:
    profile = cProfile.Profile()
    profile.enable()
    _outer(50)
    profile.disable()
    path = tmp_path / "x.pstats"
    table = profile_stats.collect(profile)
    path.write_bytes(marshal.dumps(table))
    loaded = pstats.Stats(str(path))
    assert loaded.total_calls == sum(row[1] for row in table.values())  # type: ignore[attr-defined]
