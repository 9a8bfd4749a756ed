"""The report's summary table (``harness.document.summary``) and the figures it prints: speed-ups as
``36,900x``, fastest first, the busy flag at 80% of the cores asked, image error quoted from
a comparison of at least 160x120 pixels, heat maps only where they show something; and the
whole report built from the project's own run files."""

from __future__ import annotations

import re
import shutil
from pathlib import Path
from typing import Any

import pytest

from harness.document import summary
from harness.document.model import Table
from harness.engine import figures
from harness.report.build import build_report, heat_visible

RUNS = Path(__file__).resolve().parent.parent / "results" / "runs"


# ------------------------------------------------------------------ formatting


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (46_700.4, "46,700x"),
        (36_865.03, "36,900x"),
        (47_000.0, "47,000x"),
        (1_153.09, "1,150x"),
        (198.386, "198x"),
        (37.31, "37.3x"),
        (1.604, "1.6x"),
        (1.0, "1x"),
        (0.6356, "0.636x"),
        (0.000123, "0.000123x"),
    ],
)
def test_a_speedup_prints_with_separators_and_three_significant_digits(value, text):
    assert figures.speedup_text(value) == text
    assert "e" not in figures.speedup_text(value)


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(4.01 / 300, "13.4 ms"), (7.0e-3 / 19_200, "365 ns"), (2.5, "2.5 s"), (1.5e-5, "15 µs")],
)
def test_a_time_per_pixel_takes_the_unit_that_fits(seconds, text):
    assert figures.per_pixel_text(seconds) == text


@pytest.mark.parametrize(
    ("name", "cores", "asked"),
    [
        ("naive", 2, 1),
        ("prealloc", 8, 1),
        ("numba", 2, 2),  # every available core by default
        ("numba[float32]", 4, 4),
        ("numba[threads=1]", 2, 1),
        ("pooled[workers=2]:naive", 2, 2),
        ("pooled[workers=1]:numba", 2, 1),  # the workers count, not the inner threads
        ("pooled[workers=8]:naive", 2, 2),  # never more than the machine has
        ("wavefront", 2, 1),  # one thread unless asked
        ("wavefront[threads=2]", 2, 2),
        ("not a name[", 2, 1),
    ],
)
def test_the_cores_a_variant_asks_for_come_from_its_name(name, cores, asked):
    assert figures.cores_asked(name, cores) == asked


def _row(name: str, cpu: float, wall: float = 1.0, cores: int = 2, **extra: Any) -> dict:
    return {"name": name, "status": "ok", "wall": [wall], "cpu": [cpu * wall], "cores": cores,
            "section": "table", "size": [160, 120], "samples": 1, **extra}  # fmt: skip


def test_a_row_is_busy_below_80_percent_of_the_cores_it_asked_for():
    assert not figures.is_busy(_row("pooled[workers=2]:naive", 1.6))  # exactly 80%
    assert figures.is_busy(_row("pooled[workers=2]:naive", 1.59))
    assert figures.is_busy(_row("numba", 1.5))  # asked 2
    assert not figures.is_busy(_row("numba[threads=1]", 0.95))
    assert figures.is_busy(_row("naive", 0.66))  # the busy-machine run: 0.66 of 1
    assert not figures.is_busy(_row("pooled[workers=1]:numba", 1.49))  # over what it asked
    assert not figures.is_busy({**_row("naive", 0.1), "status": "failed"})


def test_the_cpu_cell_says_used_of_asked_and_flags_busy():
    assert summary.cpu_text(_row("numba", 1.5)) == "1.50 of 2 **busy**"
    assert summary.cpu_text(_row("numba[threads=1]", 1.0)) == "1.00 of 1"


# ------------------------------------------------------------------ the summary table


def _speedup(value: float) -> dict:
    return {"value": value, "basis": "per pixel (naive measured at 20x15)"}


def _error(psnr: float | None, off: int, pixels: int, size: str, max_abs: float = 0.0) -> dict:
    return {"psnr": psnr, "pixels_over_one_step": off, "pixels": pixels, "size": size,
            "max_abs": max_abs, "mean_abs": 0.0, "rmse": 0.0}  # fmt: skip


def _run(stem: str, rows: list[dict], compare: tuple[int, int] = (20, 15)) -> dict:
    return {
        "stem": stem, "started": "2026-11-24T20:00:31", "rows": rows, "series": [],
        "compare_size": list(compare), "machine": {"load_average": [0.2], "commit": "abc"},
        "settings": {"scene": {"name": "reference"}, "samples": 1, "depth": 5, "seed": 0,
                     "epsilon": None},
    }  # fmt: skip


def _latest() -> dict:
    rows = [
        _row("naive", 1.0, wall=4.0, size=[20, 15], speedup=_speedup(1.0), summary="the book"),
        _row("cached", 1.0, wall=2.0, speedup=_speedup(37.3), summary="inverses once",
             error_vs_naive=_error(None, 0, 300, "20x15"), compare_size=[20, 15],
             allocations={"count": 3000, "method": "hooks"}),
        _row("numba", 1.5, wall=0.007, speedup=_speedup(36_865.0), summary="compiled",
             error_vs_naive=_error(219.2, 0, 300, "20x15")),
        _row("numba[float32]", 1.5, wall=0.0064, speedup=_speedup(39_800.0), summary="compiled",
             error_vs_naive=_error(69.2, 1, 300, "20x15")),
        {"name": "broken", "status": "failed", "section": "table", "summary": "x"},
    ]  # fmt: skip
    return _run("bench-new", rows)


def _older() -> dict:
    """An earlier run that compared numba at 160x120 (and another scene's row, ignored)."""
    rows = [_row("numba", 1.9, wall=0.01, speedup=_speedup(30_000.0),
                 error_vs_naive=_error(209.9, 0, 19_200, "160x120"))]  # fmt: skip
    return _run("bench-old", rows, compare=(160, 120))


def _body(table: Table) -> list[list[str]]:
    return [[cell.replace("\u00a0", " ") for cell in row] for row in table.rows]


def test_the_summary_is_sorted_fastest_first_with_failed_rows_last():
    latest = _latest()
    body = _body(summary.table(latest, [_older(), latest]))
    assert [row[0] for row in body] == [
        "`numba[float32]`", "`numba`", "`cached`", "`naive`", "`broken`",
    ]  # fmt: skip
    assert [row[2] for row in body] == ["39,800x", "36,900x", "37.3x", "1x", "failed"]
    assert summary.fastest_first(latest["rows"])[-1]["name"] == "broken"


def test_the_summary_quotes_image_error_from_a_comparison_of_160x120_where_one_exists():
    latest, older = _latest(), _older()
    body = {row[0]: row for row in _body(summary.table(latest, [older, latest]))}
    header = summary.table(latest, [older, latest]).header
    psnr, off = header.index("PSNR vs naive"), header.index("pixels off > 1/255 (size compared)")
    assert body["`numba`"][psnr] == "209.9 dB"
    assert body["`numba`"][off] == "0 of 19,200 (160x120) [a]"  # from the older run
    assert body["`numba[float32]`"][off] == "1 of 300 (20x15)"  # its own: none larger
    assert body["`naive`"][psnr] == "(the reference)"
    notes = " ".join(summary.notes(latest, [older, latest]))
    assert "[a] run `bench-old`" in notes
    # another scene's comparison does not stand for this one's
    older["settings"] = {**older["settings"], "scene": {"name": "cpp-spheres"}}
    body = {row[0]: row for row in _body(summary.table(latest, [older, latest]))}
    assert body["`numba`"][off] == "0 of 300 (20x15)"


def test_the_summary_says_what_each_variant_changes_and_flags_busy_rows():
    latest = _latest()
    table = summary.table(latest, [latest])
    body = {row[0]: row for row in _body(table)}
    changes = table.header.index("what it changes")
    assert body["`cached`"][changes] == "inverses once"
    assert body["`numba[float32]`"][changes] == "compiled; option float32"  # shared summary
    assert body["`numba`"][changes] == "compiled"
    cpu = table.header.index("CPU: cores used of asked")
    assert body["`numba`"][cpu] == "1.50 of 2 **busy**"
    assert body["`cached`"][cpu] == "1.00 of 1"
    allocations = table.header.index("allocations per pixel")
    assert body["`cached`"][allocations] == "10"  # 3000 in a 20x15 render
    busy = summary.busy_text(latest, latest["rows"])
    assert "`numba` (1.50 of 2)" in busy and "busy" in busy and "`cached`" not in busy


def test_the_lead_names_the_fastest_by_how_much_and_its_error():
    latest = _latest()
    text = summary.lead(latest, [latest])
    assert text.startswith("**Fastest: `numba[float32]`, 39,800x naive's speed**")
    assert "PSNR 69.2 dB, 1 of 300 pixels off" in text
    assert "Fastest with no pixel off: `numba`, 36,900x." in text


def test_rows_whose_timed_renders_overlap_the_fastest_are_named_as_tied():
    fast = {**_row("a", 1.0), "wall": [1.0, 1.2], "size": [10, 10]}
    close = {**_row("b", 1.0), "wall": [1.1, 1.3], "size": [10, 10]}
    slow = {**_row("c", 1.0), "wall": [2.0, 2.1], "size": [10, 10]}
    assert summary.tied_with(fast, [fast, close, slow]) == [close]


def test_a_heat_map_is_shown_only_where_it_is_not_all_black():
    full = 16 / 255
    assert not heat_visible(0.0, full)
    assert not heat_visible(1.8e-10, full)  # numba's float64 rounding: the darkest colour
    assert heat_visible(0.00262, full)  # robust: one pixel a step above black
    assert heat_visible(full, full)


def test_heat_maps_are_amplified_on_a_logarithmic_scale_that_shows_float32_rounding():
    import numpy as np

    from harness.instruments import imagediff
    from harness.sections.table.report import HeatScale, heat_scale

    assert imagediff.heat_level(0.0) == 0 and imagediff.heat_level(imagediff.HEAT_LOW) == 0
    assert imagediff.heat_level(1.0) == pytest.approx(1.0)
    assert imagediff.heat_level(1e-3) == pytest.approx(0.5)  # half way, in decades
    reference = np.zeros((2, 3, 3))
    image = reference.copy()
    image[0, 0, 1] = 3e-6  # a float32 rounding: dark, but not black
    image[1, 2, 0] = 1 / 255  # a byte's step: brighter
    heat = imagediff.heat_map(image, reference)
    black = heat[0, 1].sum()
    assert black < heat[0, 0].sum() < heat[1, 2].sum()
    scale = heat_scale({"heat_scale": {"kind": "log", "low": 1e-6, "high": 1.0}})
    assert scale.visible(3e-6) and not scale.visible(1e-7)
    assert "logarithmic" in scale.text()
    older = heat_scale({"heat_full_scale": 16 / 255})  # a run before the log scale
    assert older == HeatScale("linear", 0.0, 16 / 255) and not older.visible(1.8e-10)


def test_where_two_pictures_differ_is_the_box_of_most_of_their_differing_pixels():
    import numpy as np

    from harness.instruments import imagediff

    reference = np.zeros((100, 100, 3))
    image = reference.copy()
    image[40:60, 20:50] = 0.5  # 600 pixels
    image[0, 99] = 0.5  # a stray one
    found = imagediff.where_different(image, reference)
    assert found["pixels_off"] == 601 and found["pixels"] == 10_000
    x0, y0, x1, y1 = found["box"]
    assert x0 >= 20 and x1 <= 50 and y0 >= 40 and y1 <= 60  # the stray pixel left out
    assert "box" not in imagediff.where_different(reference, reference)


# ------------------------------------------------------------------ from the run files


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> tuple[str, str]:
    """The report built from a copy of the project's ``results/runs``."""
    results = tmp_path_factory.mktemp("results")
    shutil.copytree(RUNS, results / "runs")
    readme, page, problems = build_report(results)
    assert problems == []
    return readme.read_text(encoding="utf-8"), page.read_text(encoding="utf-8")


def _summary_lines(text: str) -> list[list[str]]:
    section = text.split("## Summary")[1].split("\n## ")[0]
    lines = [line for line in section.splitlines() if line.startswith("| `")]
    return [[cell.strip() for cell in line.strip("|").split(" | ")] for line in lines]


def test_the_report_opens_with_the_summary_sorted_fastest_first(report):
    readme, page = report
    assert readme.index("## Summary") < readme.index("## Time") < readme.index("## Pictures")
    rows = _summary_lines(readme)
    assert len(rows) >= 2
    speedups = [row[2] for row in rows if row[2].endswith("x")]
    assert all(re.fullmatch(r"[0-9][0-9,]*(\.[0-9]+)?x", s) for s in speedups), speedups
    values = [float(s[:-1].replace(",", "")) for s in speedups]
    assert values == sorted(values, reverse=True)
    assert "e+0" not in readme.split("## Error against run time")[0]
    assert "**Fastest: `" in readme
    assert '<h2 id="summary">Summary</h2>' in page and "Fastest: <code>" in page


def test_the_report_flags_what_the_run_files_say_was_busy(report):
    from harness.report.build import load_history, pick_runs

    runs, _ = load_history(RUNS.parent)
    latest = pick_runs(runs)["table"]
    busy = {row["name"] for row in latest["rows"] if row["section"] == "table"
            and figures.is_busy(row)}  # fmt: skip
    flagged = {row[0].strip("`") for row in _summary_lines(report[0]) if "**busy**" in row[-1]}
    assert flagged == busy
    if busy:
        assert "**Busy:**" in report[0]


def test_the_pictures_show_each_variant_once_and_only_visible_heat_maps(report):
    readme = report[0]
    pictures = readme.split("## Pictures")[1].split("\n## ")[0]
    lines = [line for line in pictures.splitlines() if line.startswith("| `")]
    names = [line.split("`")[1] for line in lines]
    assert len(names) == len(set(names))  # once per variant
    for line in lines:
        if "-diff.png" in line:
            assert "differs from naive's" in line
        assert line.count("<img") <= 2


def test_a_series_point_is_flagged_busy_like_a_row():
    numba = {"name": "numba", "cores": 2}
    assert summary.point_busy(numba, {"wall": 0.0033, "cpu": 0.0035})  # 1.06 of 2
    assert summary.point_cpu_text(numba, {"wall": 1.0, "cpu": 1.9}) == "1.90\u00a0of\u00a02"
    prealloc = {"name": "prealloc", "cores": 2}
    assert not summary.point_busy(prealloc, {"wall": 2.0, "cpu": 2.0})
    assert not summary.point_busy(prealloc, {"skipped": "over the budget"})
    assert summary.point_cpu_text(prealloc, {"skipped": "over the budget"}) == "-"
