"""The bench's sections in one table (``harness.sections``): every section is a package of its own
with a module that measures, one that reports and one that plots (where it has a plot), with the
functions the protocol names; the command line and the report read the table; the run files name
rows and entries by the command line's section names (schema 1's other names migrated); the report
leaves no stale plot."""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import pytest

from harness import sections
from harness.engine.results import RENAMED_SECTIONS, load_run

SCHEMA1 = Path(__file__).parent / "data" / "bench-schema1.json"


@pytest.mark.parametrize("section", sections.SECTIONS, ids=lambda s: s.name)
def test_each_section_is_a_package_that_measures_reports_and_plots(section):
    measure = section.module("measure").measure
    assert list(inspect.signature(measure).parameters) == ["bench"]
    report = sections.reporting(section.name)
    for name in ("newest", "blocks", "console_lines"):
        assert callable(getattr(report, name)), name
    assert len(inspect.signature(report.blocks).parameters) == 4  # run, plot, context, runs
    assert report.newest([]) is None
    folder = Path(sections.__file__).parent / section.package.rpartition(".")[2]
    assert (folder / "plot.py").is_file() == bool(section.plot_file)
    if section.plot_file:
        plot = section.module("plot").plot
        assert list(inspect.signature(plot).parameters) == ["run", "path"]


def test_the_table_lists_every_section_package():
    folder = Path(sections.__file__).parent
    packages = {path.parent.name for path in folder.glob("*/__init__.py")}
    assert packages == {section.package.rpartition(".")[2] for section in sections.SECTIONS}


def test_the_command_line_reads_the_table():
    assert set(sections.DEFAULTS) == {s.name for s in sections.SECTIONS if s.default}
    import argparse

    from rtc.cli import build_parser

    parser = build_parser(["bench"])
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    bench = commands.choices["bench"]
    (option,) = [a for a in bench._actions if a.dest == "sections"]
    assert set(sections.QUICK_DEFAULTS) == {s.name for s in sections.SECTIONS if s.quick}
    assert all(f"{s.name}" in option.help and s.about in option.help for s in sections.SECTIONS)
    assert option.default is None  # the mode's: QUICK_DEFAULTS, or DEFAULTS with --full
    assert ",".join(sections.QUICK_DEFAULTS) in option.help
    assert ",".join(sections.DEFAULTS) in option.help


def test_a_section_is_measured_after_the_sections_it_reads():
    assert sections.measuring_order(["ladder", "kata", "table"]) == ["table", "ladder", "kata"]
    assert sections.measuring_order(["ladder"]) == ["ladder"]  # the table not asked for
    for section in sections.SECTIONS:
        assert all(other in sections.BY_NAME for other in section.after)


def test_schema_1_names_are_the_command_lines_with_a_part(tmp_path):
    data = json.loads(SCHEMA1.read_text(encoding="utf-8"))
    data["rtc"]["rows"].append({**data["rtc"]["rows"][0], "section": "threads"})
    data["rtc"]["series"] = [
        {"section": old, "name": "x", "points": []} for old in RENAMED_SECTIONS
    ] + [{"section": "sweep", "name": "y", "points": []}]
    path = tmp_path / "bench-old.json"
    path.write_text(json.dumps(data))
    rtc = load_run(path)["rtc"]
    assert rtc["rows"][-1]["section"] == "scaling" and rtc["rows"][-1]["part"] == "threads"
    found = [(e["section"], e.get("part")) for e in rtc["series"]]
    assert found == [*RENAMED_SECTIONS.values(), ("sweep", None)]
    names = {section for section, _ in found} | {r["section"] for r in rtc["rows"]}
    assert names <= set(sections.NAMES)


def test_the_report_removes_the_plots_it_no_longer_draws(tmp_path):
    import shutil

    from harness.report.build import build_report

    shutil.copy(SCHEMA1, tmp_path / "x.json")
    (tmp_path / "runs").mkdir()
    shutil.copy(SCHEMA1, tmp_path / "runs" / "bench-20250101T000000000Z-aaaaaa.json")
    (tmp_path / "report").mkdir()
    stale = tmp_path / "report" / "time-vs-pixels.png"  # an older report's name
    stale.write_bytes(b"old")
    (tmp_path / "report" / ".written").write_text("time-vs-pixels.png\n")  # which it wrote
    mine = tmp_path / "report" / "my-notes.png"  # a file the report did not write
    mine.write_bytes(b"mine")
    build_report(tmp_path)
    assert not stale.exists()
    assert mine.read_bytes() == b"mine"
    assert (tmp_path / "report" / "speedup.png").is_file()
