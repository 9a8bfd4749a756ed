"""``rtc``: one entry point, one module per sub-command (``rtc/cmd_*.py``).

Each command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
A user mistake (bad flag value, broken scene file) raises ``UserError``: one clear line on
stderr, exit status 2, no traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from types import ModuleType

COMMANDS = [
    "rtc.cmd_variants",
    "rtc.cmd_new",
    "rtc.cmd_kata",
    "rtc.cmd_demo",
    "rtc.cmd_bench",
    "rtc.cmd_report",
    "rtc.cmd_render",
    "rtc.cmd_profile",
    "rtc.cmd_stability",
]


class UserError(Exception):
    """A mistake in what the user asked for; printed as one line, without a traceback."""


def add_results_dir(
    parser: argparse.ArgumentParser,
    help: str = "where the run file goes (DIR/runs/; default ./results)",
) -> None:
    """The ``--results-dir DIR`` option of the commands that write or read ``results/``."""
    from pathlib import Path

    parser.add_argument(
        "--results-dir", type=Path, default=Path("results"), metavar="DIR", help=help
    )


def _commands(argv: list[str] | None = None) -> list[ModuleType]:
    """The command modules the parser needs: only the chosen one when ``argv`` starts with a
    command's name (``rtc/cmd_NAME.py``), so that start-up imports only what runs."""
    chosen = f"rtc.cmd_{argv[0]}" if argv else None
    names = [chosen] if chosen in COMMANDS else COMMANDS
    return [importlib.import_module(name) for name in names]


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rtc", description="The Ray Tracer Challenge workbook and benchmark harness."
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in _commands(argv):
        command = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(command)
        command.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    args = build_parser(argv).parse_args(argv)
    try:
        return int(args.run(args))
    except UserError as error:
        print(f"rtc {args.command}: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"rtc {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `rtc kata | head`: the reader went away; not an error of ours
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so the interpreter's final flush is quiet
        return 0
    except NotImplementedError as error:  # a learner's stub (rtc new) that a command reached
        from variants.learner import NotImplementedYet

        if not isinstance(error, NotImplementedYet):
            raise
        print(f"rtc {args.command}: {error}; rtc kata --next shows what to write", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
