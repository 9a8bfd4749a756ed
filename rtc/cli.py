"""``rtc``: one entry point, one module per sub-command (``rtc/cmd_*.py``).

Each command module defines ``NAME``, ``add_arguments(parser)`` and ``run(args) -> int`` (and
``QUICK_EXIT = True`` when its process may end without the interpreter's teardown); its
one-line help is in ``COMMANDS`` here, so that ``rtc --help`` imports no command module (it
starts at Python's floor) and ``rtc NAME`` imports only its own.
A user mistake (bad flag value, broken scene file) raises ``UserError``: one clear line on
stderr, exit status 2, no traceback.
"""

from __future__ import annotations

import argparse
import atexit
import errno
import gc
import importlib
import os
import sys
from pathlib import Path

from compiled import KernelFolderError
from groundwork import knobs
from groundwork.escapes import printable
from groundwork.files import check_can_write, writable_target
from groundwork.memory import NotEnoughMemory, check, render_bytes

# Each command's module and its one line of help (``rtc --help``, and the command's own).
COMMANDS = {
    "rtc.cmd_variants":
        "list the registered variants, what each overrides, and whether it is available",
    "rtc.cmd_new":
        "start your own tracer: a package whose book functions are stubs for you to write",
    "rtc.cmd_kata":
        "run .feature files (default: the project's features/) and show progress by chapter",
    "rtc.cmd_demo": "draw a chapter's 'putting it together' picture (chapters 1 to 16) as a PNG",
    "rtc.cmd_bench":
        "time, count allocations and measure image error per variant; writes the runs into "
        "results/local/ (results/ with --publish)",
    "rtc.cmd_report":
        "write README.md and a self-contained report.html from the runs of a results folder "
        "(yours, results/local/, unless --publish)",
    "rtc.cmd_compare":
        "compare two bench runs: per variant the time ratio B/A, whether it is significant "
        "(Student's t-test over the timed renders, as pyperf compare_to) and the image error",
    "rtc.cmd_render": "render a scene file (the book's YAML scene format) to a PNG or PPM image",
    "rtc.cmd_profile":
        "profile a render of a scene file through a variant: the top functions by own and "
        "cumulative time, a flame graph, and (numba) the time of each stage",
    "rtc.cmd_stability":
        "run stiff and extreme cases (scale, cancellation, grazing rays, the torus's quartic, "
        "stiff transforms, refraction, degenerate input) on every variant against exact oracles",
}  # fmt: skip


BLAS_THREADS = "OPENBLAS_NUM_THREADS"
"""How many threads numpy's OpenBLAS starts when numpy is imported: one, in the command's
process and those it starts, unless the user set it. No command multiplies matrices large
enough to share out, and each extra thread spins on a core for about a tenth of a second
after numpy's import, beside the command's own work."""


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
        check_can_write(folder, ".rtc-write-check-")
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
    # deferred: groundwork.images brings numpy, which rtc --help does without
    from groundwork.images import FORMATS

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


SWITCH = {"on": True, "off": False}  # --light-sampling's words


def add_light_sampling(parser: argparse.ArgumentParser, help: str) -> None:
    """``--light-sampling on|off`` (``RenderSettings.light_sampling``; None when not given),
    as ``rtc render``, ``rtc bench`` and ``rtc profile`` take it."""
    parser.add_argument(
        "--light-sampling", dest="light_sampling", choices=tuple(SWITCH), help=help
    )


def parse_size(text: str) -> tuple[int, int]:
    """``--size``'s ``"200x100"`` -> (200, 100); anything else is a ``UserError``."""
    # deferred: groundwork.sizes brings the book's canvas, which rtc --help does without
    from groundwork import sizes

    try:
        size = sizes.parse_size(text, "--size")
    except ValueError as error:
        raise UserError(str(error)) from None
    return size.width, size.height


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


def _chosen(argv: list[str] | None) -> str | None:
    """The command module ``argv`` names first (``rtc/cmd_NAME.py``), if it names one."""
    chosen = f"rtc.cmd_{argv[0]}" if argv else None
    return chosen if chosen in COMMANDS else None


def _terminal_columns() -> int:
    """The terminal's width as ``shutil.get_terminal_size`` finds it (``$COLUMNS``, else the
    terminal of standard output, else 80), without importing shutil and its archivers
    (bz2, lzma), which argparse's formatter would import for every argument added."""
    try:
        columns = int(os.environ.get("COLUMNS", "0"))
    except ValueError:
        columns = 0
    if columns > 0:
        return columns
    stdout = sys.__stdout__
    try:
        return (os.get_terminal_size(stdout.fileno()).columns if stdout else 0) or 80
    except (AttributeError, ValueError, OSError):  # not a terminal, or no file behind it
        return 80


class HelpFormatter(argparse.HelpFormatter):
    """argparse's own help layout, at the terminal's width (``_terminal_columns``)."""

    def __init__(
        self, prog: str, indent_increment: int = 2, max_help_position: int = 24,
        width: int | None = None,
    ) -> None:  # fmt: skip
        width = _terminal_columns() - 2 if width is None else width
        super().__init__(prog, indent_increment, max_help_position, width)


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The parser for ``argv``: the chosen command alone, its module imported and its
    arguments added (the others' parsers would only be shown by ``rtc --help``); without a
    command (``rtc --help``, a typo) every command by its help line alone, no module
    imported."""
    parser = argparse.ArgumentParser(
        prog="rtc", description="The Ray Tracer Challenge workbook and benchmark harness.",
        formatter_class=HelpFormatter,
    )  # fmt: skip
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    chosen = _chosen(argv)
    for name, help_line in COMMANDS.items():
        if chosen is not None and name != chosen:
            continue
        command = sub.add_parser(name.removeprefix("rtc.cmd_"), help=help_line,
                                 description=help_line, formatter_class=HelpFormatter)  # fmt: skip
        if name == chosen:
            module = importlib.import_module(name)
            module.add_arguments(command)
            command.set_defaults(run=module.run, quick_exit=getattr(module, "QUICK_EXIT", False))
    return parser


def _keep_loaded_modules_out_of_collections() -> None:
    """After the command's modules were imported with the collector off: move every object
    alive now (modules, classes, functions, tables: collections walking them again and again
    took about a tenth of a quick render's startup) out of the collector's reach, and turn
    it back on for the command's own work. Only when the process is the command: a test
    calling ``main`` again and again would keep whatever cyclic garbage it has at each
    call."""
    gc.freeze()
    gc.enable()


def _exit_at_once(status: int) -> None:
    """End the command's process with ``status`` once its output is flushed and the exit
    functions (``atexit``) have run, without the interpreter's teardown, which frees every
    module and object one by one (about a tenth of a quick render's CPU after its
    imports). Only when no other thread is alive; when the output cannot be flushed (a
    reader that went away), the usual exit, which says so as before."""
    threading = sys.modules.get("threading")  # not imported: no other thread was started
    if threading is not None and threading.active_count() > 1:
        return
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        return
    atexit._run_exitfuncs()
    try:  # what the exit functions said
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    os._exit(status)


def main(argv: list[str] | None = None) -> int:
    command_line = argv is None  # the process is this command (not a test calling main)
    argv = sys.argv[1:] if argv is None else argv
    if command_line:  # its modules live until the exit: not walked by the collector (below)
        gc.disable()
        os.environ.setdefault(BLAS_THREADS, "1")  # before numpy is imported (see BLAS_THREADS)
    try:  # Ctrl-C while the command's modules are imported: one line too
        args = build_parser(argv).parse_args(argv)
        if not hasattr(args, "run"):  # the command came after an option (rtc -- render ...)
            args = build_parser([args.command]).parse_args(argv)
    except KeyboardInterrupt:
        named = f" {argv[0]}" if argv and f"rtc.cmd_{argv[0]}" in COMMANDS else ""
        print(f"rtc{named}: interrupted", file=sys.stderr)
        return 130
    finally:
        if command_line:
            _keep_loaded_modules_out_of_collections()
    try:
        for problem in knobs.problems():  # numba's settings: before numba is imported
            raise UserError(problem)
        if isinstance(getattr(args, "results_dir", None), Path):
            check_results_dir(args.results_dir)
        status = int(args.run(args))
        if command_line and args.quick_exit:  # a command whose files are written and closed
            _exit_at_once(status)
        return status
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
