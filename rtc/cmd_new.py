"""``rtc new NAME``: start your own tracer as a variant, with every book function a stub."""

from __future__ import annotations

import argparse
import importlib.util
import keyword
import re
import shlex
import sys
from importlib.metadata import entry_points
from pathlib import Path

from raytracer.api import BOOK_API
from rtc.cli import UserError
from variants.registry import ALL, GROUP

NAME = "new"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", metavar="NAME", help="your variant's name, a Python identifier")
    parser.add_argument(
        "--dir",
        type=Path,
        default=None,
        metavar="PATH",
        help="the folder to create (default: ./NAME); re-running never replaces your files",
    )


def _inside(location: str, folder: Path) -> bool:
    """True if ``location`` (a file path, or "built-in") lies inside ``folder``."""
    path = Path(location)
    return path.is_absolute() and path.resolve().is_relative_to(folder.resolve())


def _module_location(module: str) -> str | None:
    """Where a top-level module would be imported from: a file, or "built-in" / "frozen";
    None when there is none (or only a namespace package, which any folder of that name is).
    """
    try:
        spec = importlib.util.find_spec(module)
    except (ImportError, ValueError):
        return None
    return None if spec is None else spec.origin


MAX_NAME = 64  # the package's folder, its module and its pip name are all made of it
_ASCII_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def check_name(name: str, folder: Path) -> None:
    """A ``UserError`` unless ``name`` can name a new variant (and package) in ``folder``:
    a Python identifier of ASCII letters, digits and _ starting with a letter (pip reads
    only such a package name: ``rtc-variant-NAME``), not too long for a file name, not a
    keyword, not ``all``, not another variant's or module's name."""
    if len(name) > MAX_NAME:
        raise UserError(
            f"a name of {len(name)} characters ({name[:20]!r}...); at most {MAX_NAME}"
        )
    if not name.isidentifier() or keyword.iskeyword(name):
        raise UserError(
            f"{name!r} is not a Python identifier: use letters, digits and _, not starting "
            "with a digit, and not a Python keyword (e.g. my_tracer)"
        )
    if not _ASCII_NAME.fullmatch(name):
        raise UserError(
            f"{name!r} cannot name a package pip installs: use ASCII letters, digits and _, "
            "starting with a letter (e.g. my_tracer)"
        )
    if name == ALL:
        raise UserError("'all' means every variant; pick another name")
    for ep in entry_points().select(group=GROUP):
        if ep.name != name:
            continue
        location = _module_location(ep.module.split(".")[0])
        if location is None or not _inside(location, folder):
            where = f" (module {ep.module}" + (f", {location}" if location else "") + ")"
            raise UserError(
                f"there is already a variant called {name!r}{where}; pick another name "
                "(rtc variants lists them)"
            )
    location = _module_location(name)
    if location is not None and not _inside(location, folder):
        raise UserError(
            f"a Python module called {name!r} already exists ({location}); a package of that "
            "name would clash with it, pick another name"
        )


def _shown(path: Path) -> str:
    """``path`` relative to the working folder when inside it, else absolute."""
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def commands(name: str, folder: Path) -> tuple[str, str]:
    """The two commands to print: install (editable, with this environment's pip) and start."""
    python = Path(sys.executable)
    target = _shown(folder.absolute())
    install = shlex.join([_shown(python), "-m", "pip", "install", "-e", target])
    rtc = python.parent / "rtc"
    rtc_command = _shown(rtc) if rtc.exists() else "rtc"
    start = f"{rtc_command} kata --variant {name} --chapter 1"
    return install, start


def run(args: argparse.Namespace) -> int:
    # deferred: saves ~10 ms of rtc --help (rtc.scaffold)
    from rtc.scaffold import ScaffoldError, scaffold

    name: str = args.name
    folder: Path = (args.dir if args.dir is not None else Path(name)).expanduser().absolute()
    check_name(name, folder)
    install, start = commands(name, folder)
    try:
        existed = folder.exists()
        result = scaffold(name, folder, install, start)
    except (ScaffoldError, OSError) as error:
        raise UserError(str(error)) from None
    where = _shown(folder)
    if not existed:
        print(f"Created {where}, your own tracer {name!r}:")
        listing = {
            f"{name}/tracer.py": f"every book function ({len(BOOK_API)} names), a stub to write",
            f"{name}/variant.py": "the factory rtc calls to load it",
            "pyproject.toml": f"registers it as the variant {name!r}",
        }
        width = max(len(path) for path in listing)
        for path, what in listing.items():
            print(f"  {path:<{width}}  {what}")
    else:
        if result.kept:
            print(f"{where} already exists; left alone: {', '.join(result.kept)}")
        if result.created:
            print(f"added the missing: {', '.join(result.created)}")
        if result.undefined:
            print(
                f"{name}/tracer.py does not define {len(result.undefined)} book names "
                f"(scenarios calling them show as undefined): {', '.join(result.undefined)}"
            )
    print()
    print("Next:")
    print(f"  1. install it (once; editable, so your edits are seen):  {install}")
    print(f"  2. start:  {start}")
    return 0
