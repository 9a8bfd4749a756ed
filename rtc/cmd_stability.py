"""``rtc stability``: run the numerical stability suite on every variant; one new result
file per run (``results/runs/stability-*.json``), shown by ``rtc report``."""

from __future__ import annotations

import argparse
import json
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

from groundwork.sizes import parse_size
from rtc.cli import UserError, add_results_dir, cannot_write, check_writable

NAME = "stability"
DEFAULT_SIZE = "32x24"
GROUPS = (
    "scale", "cancel", "graze", "torus", "stiff", "singular", "refract", "degen", "path",
)
"""The case groups, in the suite's order (a test checks them against its cases)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--variants",
        default="all",
        metavar="A,B|all",
        help="variant names (the registry's grammar), comma-separated; 'all' (default) = "
        "every available variant, its float32/fastmath option sets, and robust",
    )
    parser.add_argument(
        "--size",
        default=DEFAULT_SIZE,
        metavar="WxH",
        help=f"the size of the cases' renders (default {DEFAULT_SIZE}; naive takes about "
        "18 ms per pixel of the reference scene, and the scale cases render it 6 times)",
    )
    parser.add_argument(
        "--cases",
        default=None,
        metavar="PREFIX,...",
        help=f"only the cases whose id starts with one of these (groups: {', '.join(GROUPS)}; "
        "or an id such as scale/1e-6)",
    )
    parser.add_argument("--json", action="store_true", help="print the run as JSON")
    parser.add_argument(
        "--details", action="store_true", help="also list what every failing cell saw"
    )
    add_results_dir(parser)


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~20 ms of rtc --help (harness.engine.machine)
    from harness.engine.machine import describe_machine

    # deferred: saves ~300 ms of rtc --help (the stability suite)
    from harness.stability import runfile, table

    # deferred: saves ~190 ms of rtc --help (the stability suite)
    from harness.stability.suite import run_suite, select_cases, select_variants

    try:
        size = parse_size(args.size)
        cases = select_cases(args.cases)
    except ValueError as error:
        raise UserError(str(error)) from None
    try:
        variants, unavailable = select_variants(args.variants)
    except LookupError as error:
        raise UserError(f"--variants: {error.args[0]}") from None
    check_writable(args.results_dir, f"--results-dir {str(args.results_dir)!r}")
    started_clock = time.monotonic()
    started = datetime.now(UTC)

    def log(message: str) -> None:
        elapsed = time.monotonic() - started_clock
        print(f"rtc stability [{elapsed:5.0f} s]: {message}", file=sys.stderr, flush=True)

    log(f"{len(cases)} cases on {len(variants)} variants, renders at {size.width}x{size.height}")
    cells = run_suite(variants, cases, (size.width, size.height), log)
    data = runfile.document(
        cells, cases, [v.name for v in variants], unavailable,
        {"size": [size.width, size.height], "cases": args.cases, "variants": args.variants},
        describe_machine(Path(__file__).resolve().parent.parent), started,
        time.monotonic() - started_clock,
    )  # fmt: skip
    try:
        path = runfile.write_run(args.results_dir, data)
    except OSError as error:  # a full disk: the run file is written whole or not at all
        raise UserError(cannot_write(error, args.results_dir)) from None
    if args.json:
        print(json.dumps(data, indent=1))
    else:
        print(table.text_table(data["rtc"], details=args.details))
    print(f"rtc stability: wrote {path}", file=sys.stderr if args.json else sys.stdout)
    return 0
