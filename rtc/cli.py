"""``rtc``: one entry point, one module per sub-command (``rtc/cmd_*.py``).

Each command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
A user mistake (bad flag value, broken scene file) raises ``UserError``: one clear line on
stderr, exit status 2, no traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from types import ModuleType

COMMANDS = [
    "rtc.cmd_variants",
    "rtc.cmd_kata",
    "rtc.cmd_demo",
]


class UserError(Exception):
    """A mistake in what the user asked for; printed as one line, without a traceback."""


def _commands() -> list[ModuleType]:
    return [importlib.import_module(name) for name in COMMANDS]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rtc", description="The Ray Tracer Challenge workbook and benchmark harness."
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in _commands():
        command = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(command)
        command.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.run(args))
    except UserError as error:
        print(f"rtc {args.command}: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"rtc {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
