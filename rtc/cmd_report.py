"""``rtc report``: build results/README.md and results/report.html from the bench history."""

from __future__ import annotations

import argparse

from rtc.cli import UserError, add_results_dir

NAME = "report"
HELP = "write results/README.md and a self-contained results/report.html from results/runs/"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_results_dir(
        parser, "the results folder (default ./results): reads DIR/runs/, writes DIR/README.md"
    )


def run(args: argparse.Namespace) -> int:
    from harness.report import build_report

    try:
        readme, page, problems = build_report(args.results_dir)
    except FileNotFoundError as error:
        raise UserError(str(error)) from None
    for problem in problems:
        print(f"rtc report: skipped {problem}")
    print(f"rtc report: wrote {readme} and {page}")
    return 0
