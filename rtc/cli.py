"""``rtc``: one entry point, one module per sub-command (``rtc/cmd_*.py``).

Each command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
A user mistake (bad flag value, broken scene file) raises ``UserError``: one clear line on
stderr, exit status 2, no traceback.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import os
import sys
import tempfile
from pathlib import Path
from types import ModuleType

from compiled import KernelFolderError
from groundwork import knobs
from groundwork.escapes import printable
from groundwork.files import writable_target
from groundwork.images import FORMATS
from groundwork.memory import NotEnoughMemory, check, render_bytes

COMMANDS = [
    "rtc.cmd_variants",
    "rtc.cmd_new",
    "rtc.cmd_kata",
    "rtc.cmd_demo",
    "rtc.cmd_bench",
    "rtc.cmd_report",
    "rtc.cmd_compare",
    "rtc.cmd_render",
    "rtc.cmd_profile",
    "rtc.cmd_stability",
]


class UserError(Exception):
    """A mistake in what the user asked for; printed as one line, without a traceback."""


LOCAL_RESULTS = Path("results/local")
"""Where runs and reports go by default: a results folder of the user's own (git ignores it),
so that a learner's or a partial bench never rewrites the committed report."""
PUBLISHED_RESULTS = Path("results")
"""The committed runs and report (results/README.md, the README's figures): written only when
asked, ``--publish`` or ``--results-dir results``."""


def add_results_dir(
    parser: argparse.ArgumentParser,
    help: str = "where the run file goes (DIR/runs/; default ./results/local, your own)",
    publish: str | None = None,
) -> None:
    """The ``--results-dir DIR`` option of the commands that write or read ``results/``
    (``main`` refuses one that names a file; ``check_writable`` one that cannot be written),
    and ``--publish`` (``DIR`` = the committed ``results``) where ``publish`` says what it
    does."""
    parser.add_argument(
        "--results-dir", type=Path, default=LOCAL_RESULTS, metavar="DIR", help=help
    )
    if publish is not None:
        parser.add_argument("--publish", action="store_true", help=publish)


def publishing(args: argparse.Namespace) -> bool:
    """Whether the command writes the committed results (``--publish``, or ``--results-dir``
    naming the committed folder itself); ``--publish`` sets ``args.results_dir``. A
    ``UserError`` for ``--publish`` with another ``--results-dir``."""
    if getattr(args, "publish", False):
        if args.results_dir not in (LOCAL_RESULTS, PUBLISHED_RESULTS):
            raise UserError("--publish writes into results/: not with another --results-dir")
        args.results_dir = PUBLISHED_RESULTS
        return True
    return Path(os.path.abspath(args.results_dir)) == Path(os.path.abspath(PUBLISHED_RESULTS))


def check_results_dir(path: Path) -> None:
    """A ``UserError`` when ``--results-dir`` (or its ``runs/``) exists and is not a folder."""
    for folder in (path, path / "runs"):
        if _exists(folder, f"--results-dir {str(path)!r}") and not folder.is_dir():
            raise UserError(f"--results-dir {str(path)!r}: {str(folder)!r} is a file, not a folder")


def _exists(path: Path, what: str) -> bool:
    """Whether ``path`` exists; a ``UserError`` naming ``what`` when it cannot be looked at
    (a folder on the way that we may not enter)."""
    try:
        path.stat()
    except (FileNotFoundError, NotADirectoryError):  # NotADirectory: a file on the way
        return False
    except OSError as error:
        raise UserError(f"{what}: cannot reach {str(path)!r}: {error.strerror or error}") from None
    return True


def check_writable(path: Path, what: str) -> None:
    """A ``UserError`` naming ``what`` (an option and its value) unless files can be made in
    ``path``, or in the nearest folder above it that exists (``path`` is made later): a
    temporary file is made and removed there, so a read-only folder, a read-only file
    system or a full disk is found before any work is done."""
    folder = path
    while not _exists(folder, what) and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise UserError(f"{what}: {str(folder)!r} is not a folder")
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".rtc-write-check-"):
            pass
    except OSError as error:
        raise UserError(
            f"{what}: cannot write in {str(folder)!r}: {error.strerror or error}"
        ) from None


_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)  # what more space would cure


def cannot_write(error: OSError, results: Path) -> str:
    """One line for a write the disk refused while a run was being kept under ``results``
    (full, read-only, over quota): what, where, and that nothing was kept."""
    where = f" {error.filename}" if error.filename else ""
    advice = " (free some space and run again)" if error.errno in _FULL else ""
    return (
        f"cannot write{where} under {str(results)!r}: {error.strerror or error}; nothing "
        f"was kept{advice}"
    )


def check_output(text: str) -> Path:
    """``-o``'s path, checked before anything is rendered: a known image extension, not a
    folder (nor spelled as one, ``out.png/``), in a folder that exists and takes new files,
    and, when the file exists, one that can be written."""
    output = Path(text)
    what = f"cannot write {text!r}"
    if text.endswith(("/", os.sep)):
        raise UserError(f"{what}: it names a folder (it ends with '/')")
    if output.suffix.lower() not in FORMATS:
        raise UserError(
            f"{what}: unknown image extension {output.suffix or '(none)'}; "
            f"use {' or '.join(FORMATS)}"
        )
    exists = _exists(output, what) or os.path.lexists(output)
    if exists and output.is_dir() and not output.is_symlink():
        raise UserError(f"{what}: it is a folder")
    if exists:  # a link is not written through; a pipe would block the writer
        check_target(output, what)
    folder = output.parent
    if _exists(folder, what) and not folder.is_dir():
        raise UserError(f"{what}: {str(folder)!r} is a file, not a folder")
    if not folder.is_dir():
        raise UserError(f"{what}: no folder {str(folder)!r}")
    check_writable(folder, what)
    if exists:
        try:
            os.close(os.open(output, os.O_WRONLY))  # opened, not truncated: left as it is
        except OSError as error:
            raise UserError(f"cannot write {text!r}: {error.strerror or error}") from None
    return output


def check_target(path: Path, what: str) -> None:
    """A ``UserError`` naming ``what`` when ``path`` is there and is a symbolic link or not a
    regular file (``groundwork.files.writable_target``): nothing is written through a link."""
    try:
        writable_target(path)
    except OSError as error:
        raise UserError(f"{what}: {error.strerror or error}") from None


def say(command: str, message: str) -> None:
    """One line on stderr, ``rtc COMMAND: MESSAGE``, with the control characters of what the
    message quotes from a user's file escaped (``groundwork.escapes``)."""
    print(f"rtc {command}: {printable(message)}", file=sys.stderr, flush=True)


def check_memory(variant: str, width: int, height: int) -> None:
    """A ``UserError`` naming the size, the memory it needs and the memory left, when a
    ``width`` x ``height`` render with ``variant`` would not fit (before it starts)."""
    try:
        check(render_bytes(variant, width, height), f"a {width}x{height} picture with {variant}")
    except NotEnoughMemory as error:
        raise UserError(f"{error}; choose a smaller --size") from None


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
    try:  # Ctrl-C while the command's modules are imported: one line too
        args = build_parser(argv).parse_args(argv)
    except KeyboardInterrupt:
        named = f" {argv[0]}" if argv and f"rtc.cmd_{argv[0]}" in COMMANDS else ""
        print(f"rtc{named}: interrupted", file=sys.stderr)
        return 130
    try:
        for problem in knobs.problems():  # numba's settings: before numba is imported
            raise UserError(problem)
        if isinstance(getattr(args, "results_dir", None), Path):
            check_results_dir(args.results_dir)
        return int(args.run(args))
    except (UserError, KernelFolderError) as error:
        say(args.command, str(error))
        return 2
    except KeyboardInterrupt:
        print(f"rtc {args.command}: interrupted", file=sys.stderr)
        return 130
    except MemoryError as error:  # what the checks before the work did not foresee
        say(args.command, f"out of memory{f': {error}' if str(error) else ''}; "
            "try a smaller size or scene")  # fmt: skip
        return 1
    except BrokenPipeError:  # `rtc kata | head`: the reader went away; not an error of ours
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so the interpreter's final flush is quiet
        return 0
    except NotImplementedError as error:  # a learner's stub (rtc new) that a command reached
        # deferred: saves ~7 ms (variants.learner) of every command that reaches no stub
        from variants.learner import NotImplementedYet

        if not isinstance(error, NotImplementedYet):
            raise
        say(args.command, f"{error}; rtc kata --next shows what to write")
        return 2


if __name__ == "__main__":  # python -m rtc.cli: the commands raise rtc.cli's UserError
    from rtc.cli import main as rtc_main

    sys.exit(rtc_main())
