"""``rtc kata``: run feature files against variants and show progress chapter by chapter."""

from __future__ import annotations

import argparse
from pathlib import Path

from rtc.cli import UserError

NAME = "kata"
HELP = "run .feature files (default: the project's features/) and show progress by chapter"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "path",
        nargs="?",
        type=Path,
        default=None,
        help="a folder of .feature files or one file (default: the project's features/)",
    )
    parser.add_argument(
        "--variant",
        action="append",
        default=None,
        metavar="NAME",
        help="the variant to run (repeatable; 'all' = every available one; default: naive)",
    )
    parser.add_argument(
        "--chapter",
        action="append",
        type=int,
        default=None,
        metavar="N",
        help="only the scenarios of chapter N (repeatable)",
    )
    parser.add_argument("--json", action="store_true", help="print the results as JSON")
    parser.add_argument("-v", "--verbose", action="store_true", help="show pytest's own output")


def run(args: argparse.Namespace) -> int:
    from steps import kata

    path = args.path if args.path is not None else kata.PROJECT_FEATURES
    if not path.exists():
        raise UserError(f"no such feature file or folder: {path}")
    for chapter in args.chapter or []:
        if not 1 <= chapter <= 99:
            raise UserError(f"--chapter {chapter}: the book's chapters are numbered from 1")
    try:
        result = kata.run_kata(path, args.variant or ["naive"], args.chapter or [], args.verbose)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0]}") from None
    print(kata.as_json(result) if args.json else kata.progress_table(result))
    return 0 if result.ok else 1
