"""``rtc compare RUN_A RUN_B``: two bench runs compared row by row (``harness.report.compare``):
the time ratio B/A with Student's t-test over the timed renders, as ``pyperf compare_to``
does, and the change in image error against naive."""

from __future__ import annotations

import argparse

from rtc.cli import UserError, add_results_dir

NAME = "compare"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    for name, which in (("run_a", "the earlier run, A"), ("run_b", "the run compared, B")):
        parser.add_argument(
            name,
            metavar=name.upper(),
            help=f"{which}: a run file's path, its name in DIR/runs/ (bench-...), latest or "
            "previous",
        )
    add_results_dir(parser, "the results folder the run names are looked up in (default ./results)")


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~80 ms of rtc --help (harness.report.compare)
    from harness.report.compare import RunChoiceError, compare_runs, load, table_lines

    try:
        a = load(args.run_a, args.results_dir)
        b = load(args.run_b, args.results_dir)
    except RunChoiceError as error:
        raise UserError(str(error)) from None
    print("\n".join(table_lines(compare_runs(a, b))))
    return 0
