"""``rtc report``: build results/README.md and results/report.html from the bench history."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from rtc.cli import UserError, add_results_dir, cannot_write, check_writable, publishing, say

NAME = "report"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_results_dir(
        parser,
        "the results folder (default ./results/local, your own: git ignores it): reads "
        "DIR/runs/, writes DIR/README.md, DIR/report.html and DIR/report/",
        publish="write the committed report, results/README.md, results/report.html and "
        "results/report/, from results/runs/, and the figures the project's README.md quotes",
    )


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~2 s of rtc --help (the report: matplotlib, every section)
    from harness.report.build import ReportError, build_report

    def warn(problem: str) -> None:  # one line per file on stderr; the report goes on
        say("report", f"warning: skipped {problem}")

    publish = publishing(args)
    check_writable(args.results_dir, f"--results-dir {str(args.results_dir)!r}")
    results = Path(args.results_dir)
    if results.is_symlink():  # written through, but said: it may be another project's
        print(f"rtc report: note: {results} is a link to {results.resolve()}; the report is "
              "written there", file=sys.stderr, flush=True)  # fmt: skip
    try:
        readme, page, _ = build_report(results, warn)
    except (FileNotFoundError, ReportError) as error:
        raise UserError(str(error)) from None
    except OSError as error:  # a full disk: each file is written whole or not at all
        raise UserError(cannot_write(error, results)) from None
    print(f"rtc report: wrote {readme} and {page}")
    if not publish:  # the project's README quotes the committed runs alone
        return 0
    # the README beside the results folder as named, not beside where a link leads
    project_readme = Path(os.path.abspath(results)).parent / "README.md"
    if update_readme(project_readme, args.results_dir):
        print(f"rtc report: updated the figures in {project_readme}")
    return 0


def update_readme(readme: Path, results: Path) -> bool:
    """Rewrite the figures ``readme`` quotes (between ``harness.report.readme_figures``' markers)
    from ``results``' runs; False when it has no such markers or nothing changed."""
    # deferred: saves ~150 ms of rtc --help (the report's figures)
    from harness.report import readme_figures

    # deferred: saves ~2 s of rtc --help (the report: matplotlib, every section)
    from harness.report.build import load_history

    runs, _ = load_history(results)
    try:
        return readme_figures.rewrite(readme, runs)
    except OSError as error:
        say("report", f"warning: cannot update {readme}: {error}")
        return False
