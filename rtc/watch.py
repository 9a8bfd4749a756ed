"""``rtc kata --watch``: re-run a command whenever the learner's files change.

Each run is a fresh ``python -m rtc.cli ...`` subprocess: Python caches imported modules, so
only a new process sees the edits. The subprocess gets a session of its own, so Ctrl-C
reaches only the watcher, which stops the run and exits cleanly.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import time
from collections.abc import Iterable, Sequence
from importlib.metadata import entry_points
from pathlib import Path

from watchfiles import DefaultFilter
from watchfiles import watch as watch_changes

from variants.registry import ALL, GROUP, VariantSpec, parse_variant_name

WATCHED_SUFFIXES = (".py", ".feature", ".obj", ".toml", ".yml", ".yaml")
CLEAR_SCREEN = "\033[2J\033[H"
PROJECT = Path(__file__).resolve().parent.parent


def _spec_names(spec: VariantSpec) -> list[str]:
    names = [spec.name]
    if spec.inner is not None:
        names += _spec_names(spec.inner)
    return names


def _package_folder(module: str) -> Path | None:
    """The folder of a top-level package (or the file of a module), without importing it."""
    try:
        spec = importlib.util.find_spec(module.split(".")[0])
    except (ImportError, ValueError):
        return None
    if spec is None:
        return None
    if spec.submodule_search_locations:
        return Path(next(iter(spec.submodule_search_locations)))
    return Path(spec.origin) if spec.origin else None


def variant_folders(variant_names: Iterable[str]) -> list[Path]:
    """The code behind the named variants: each one's package folder. A variant of this
    project (``variants.*``) also brings the reference, ``raytracer/``, which it builds on."""
    eps = {ep.name: ep for ep in entry_points().select(group=GROUP)}
    wanted: list[str] = []
    for text in variant_names:
        if text.strip() == ALL:
            wanted += list(eps)
            continue
        try:
            wanted += _spec_names(parse_variant_name(text))
        except LookupError:
            continue  # the run itself reports the bad name
    folders: list[Path] = []
    for name in wanted:
        if name not in eps:
            continue
        top = eps[name].module.split(".")[0]
        candidates = [_package_folder(top)]
        if top in ("variants", "raytracer"):
            candidates.append(PROJECT / "raytracer")
        folders += [folder for folder in candidates if folder is not None]
    return folders


def distinct(paths: Iterable[Path]) -> list[Path]:
    """Existing paths, each once, none inside another."""
    resolved = sorted(
        {path.resolve() for path in paths if path.exists()}, key=lambda p: len(p.parts)
    )
    kept: list[Path] = []
    for path in resolved:
        if not any(path.is_relative_to(outer) for outer in kept):
            kept.append(path)
    return kept


def is_watched(_: object, path: str) -> bool:
    """Source files, not caches: a ``watchfiles`` filter."""
    return path.endswith(WATCHED_SUFFIXES) and DefaultFilter()(_, path)  # type: ignore[arg-type]


def _shown(path: Path) -> str:
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def run_once(command: Sequence[str]) -> int:
    """Run ``command`` to completion in its own session; Ctrl-C stops it and is re-raised."""
    sys.stdout.flush()
    process = subprocess.Popen(list(command), start_new_session=True)
    try:
        return process.wait()
    except KeyboardInterrupt:
        process.terminate()
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        raise


def watch(command: Sequence[str], paths: Sequence[Path], clear: bool | None = None) -> int:
    """Run ``command``, then again after every saved change under ``paths``, until Ctrl-C
    (exit status 0). ``clear``: clear the screen before each run (default: on a terminal)."""
    clear = sys.stdout.isatty() if clear is None else clear
    watched = ", ".join(_shown(path) for path in paths)
    run = 0
    changed: list[str] = []
    try:
        changes = watch_changes(
            *paths,
            watch_filter=is_watched,
            debounce=400,
            rust_timeout=250,
            yield_on_timeout=True,
        )
        armed = False
        while True:
            if run == 0 or changed:
                run += 1
                if clear:
                    print(CLEAR_SCREEN, end="")
                because = f" (changed: {', '.join(changed)})" if changed else ""
                print(f"── rtc kata --watch: run {run} at {time.strftime('%H:%M:%S')}{because}")
                code = run_once(command)
                print(f"── run {run} finished (exit status {code})", flush=True)
                armed = False
            batch = next(changes)  # an empty batch: the watcher is armed and nothing changed
            if not armed:
                print(f"── watching {watched}; save a file to re-run, Ctrl-C to stop", flush=True)
                armed = True
            changed = sorted({_shown(Path(path)) for _, path in batch})
    except KeyboardInterrupt:
        print("\n── stopped watching", flush=True)
        return 0
