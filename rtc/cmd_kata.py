"""``rtc kata``: run feature files against variants and show progress chapter by chapter;
``--next`` shows only the next scenario to make pass, ``--watch`` re-runs on every save."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from groundwork.escapes import printable
from groundwork.files import describe, read_bytes
from groundwork.progress import MODES, Progress
from rtc.cli import UserError

NAME = "kata"


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
        help="the variant to run (repeatable; 'all' = the project's own available ones, a "
        "learner's tracer runs when named; default: naive)",
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
    parser.add_argument(
        "--progress", choices=MODES, default="auto",
        help="how to show the progress of a run that takes more than a second, on stderr: "
        "auto (the default: a bar on a terminal, else lines), bar, lines (one every 10 s) or "
        "none",
    )  # fmt: skip
    parser.add_argument(
        "--next",
        action="store_true",
        help="show only the next scenario to make pass (the first not passing, in book order)",
    )
    parser.add_argument(
        "--watch",
        action="store_true",
        help="run again whenever the variant's files or the feature files change (Ctrl-C stops)",
    )


MAX_FEATURE_BYTES = 16 << 20  # the book's longest feature file is some 20 kB
MAX_LINE = 4096  # characters in a feature file's line; the book's longest is under 200
MAX_DEPTH = 64  # folders inside each other under the path; the project's features/ has 1


def feature_files(folder: Path) -> list[Path]:
    """The ``.feature`` files under ``folder``, sorted, walked without recursion (a folder
    nested thousands deep would exhaust Python's stack) and without following links; a
    ``UserError`` for folders nested more than ``MAX_DEPTH`` deep."""
    found: list[Path] = []
    stack = [(folder, 0)]
    while stack:
        here, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise UserError(
                f"{folder}: folders nested more than {MAX_DEPTH} deep under it; name the "
                "folder of the feature files itself"
            )
        try:
            entries = list(os.scandir(here))
        except OSError as error:
            raise UserError(f"{here}: cannot list the folder: {error.strerror}") from None
        for entry in entries:
            if entry.is_dir(follow_symlinks=False):
                stack.append((Path(entry.path), depth + 1))
            elif entry.name.endswith(".feature"):
                found.append(Path(entry.path))
    return sorted(found)


def check_features(path: Path) -> None:
    """A ``UserError`` naming the first feature file under ``path`` that pytest-bdd could not
    read: not a regular file (a named pipe would block it), too large, or not UTF-8 text."""
    odd = describe(path)
    if odd is not None and not path.is_dir():
        raise UserError(f"{path}: {odd}")
    files = [path] if not path.is_dir() else feature_files(path)
    for file in files:
        try:
            data = read_bytes(file, MAX_FEATURE_BYTES)
        except OSError as error:
            raise UserError(f"{file}: cannot read the feature file: {error.strerror}") from None
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as error:
            line = data[: error.start].count(b"\n") + 1
            raise UserError(
                f"{file}:{line}: the feature file is not UTF-8 text (byte "
                f"0x{data[error.start]:02x}); save it as UTF-8"
            ) from None
        _check_lines(file, text)


def _check_lines(file: Path, text: str) -> None:
    """A ``UserError`` naming the first line of ``text`` longer than ``MAX_LINE`` characters:
    the step library's patterns are not meant for such text (some backtrack for minutes)."""
    for number, line in enumerate(text.splitlines(), 1):
        if len(line) > MAX_LINE:
            raise UserError(
                f"{file}:{number}: the line is {len(line):,} characters long; feature file "
                f"lines up to {MAX_LINE:,} are read"
            )


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~650 ms of rtc --help (pytest, the step library)
    from steps import kata

    path = args.path if args.path is not None else kata.PROJECT_FEATURES
    if not path.exists():
        raise UserError(f"no such feature file or folder: {path}")
    check_features(path)
    for chapter in args.chapter or []:
        if not 1 <= chapter <= 99:
            raise UserError(f"--chapter {chapter}: the book's chapters are numbered from 1")
    variants = args.variant or ["naive"]
    if args.next and (len(variants) > 1 or variants[0].strip() == "all"):
        raise UserError("--next shows one variant's next scenario: give one --variant NAME")
    if args.watch:
        return _watch(args, path, variants)
    mode = "none" if args.verbose else args.progress  # pytest's own output says it
    progress = Progress("rtc kata", 0, "scenario", mode=mode)
    try:
        result = kata.run_kata(path, variants, args.chapter or [], args.verbose, progress)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0]}") from None
    finally:
        progress.close()
    if args.next:
        # deferred: saves ~650 ms of rtc --help (pytest, the step library)
        from steps.next_scenario import next_json, next_report, next_scenario

        variant = result.variants[0]
        print(next_json(result, variant) if args.json else shown(next_report(result, variant)))
        return 0 if next_scenario(result, variant) is None and not result.errors else 1
    print(kata.as_json(result) if args.json else shown(kata.progress_table(result)))
    return 0 if result.ok else 1


def shown(text: str) -> str:
    """``text``'s lines with the control characters they quote from a feature file (its
    scenario names) escaped."""
    return "\n".join(printable(line) for line in text.split("\n"))


def _watch(args: argparse.Namespace, path: Path, variants: list[str]) -> int:
    """Check the variant names once, then hand the same command (without ``--watch``) to
    ``rtc.watch``, which runs it in a fresh process on every change."""
    # deferred: saves ~30 ms of rtc --help and of rtc kata without --watch (watchfiles)
    from rtc.watch import distinct, variant_folders, watch

    # deferred: saves ~600 ms of rtc --help (pytest, the step library)
    from steps.plugin import select_variants

    try:
        select_variants(variants)
    except LookupError as error:
        raise UserError(f"--variant: {error.args[0]}") from None
    command = [sys.executable, "-m", "rtc.cli", "kata", str(path.absolute())]
    for name in variants:
        command += ["--variant", name]
    for chapter in args.chapter or []:
        command += ["--chapter", str(chapter)]
    command += [flag for flag, on in (("--json", args.json), ("-v", args.verbose)) if on]
    command += ["--progress", args.progress]
    command += ["--next"] if args.next else []
    return watch(command, distinct([path, *variant_folders(variants)]))
