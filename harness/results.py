"""The measurement history: one JSON file per bench run in ``results/runs/``, never replaced.

Layout of ``results/``::

    runs/bench-<UTC time>-<random>.json   one per run (pyperf-compatible, plus "rtc")
    runs/bench-<UTC time>-<random>/       that run's images (PNG)
    README.md, report.html, report/       written by ``rtc report`` from the runs

A run file is a pyperf ``BenchmarkSuite`` (``python -m pyperf show FILE`` and ``compare_to``
read it: one benchmark per measured row, its values the wall times of the repeats, in seconds)
with one more top-level key, ``"rtc"``, holding our schema: ``schema_version``, ``machine``,
``settings`` and the rows, series and chapter progress (see ``harness.bench``).

Writing: images go to a hidden staging folder, which is renamed into place when the run
completes, and the JSON is written to a temporary file and hard-linked to its final name (a
link never replaces an existing file) before the temporary name is removed. A run killed at
any moment leaves no result file; a killed run's hidden staging folder is removed by the next
run.
"""

from __future__ import annotations

import io
import json
import os
import secrets
import shutil
import tempfile
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

SCHEMA_VERSION = 1
RUNS = "runs"
STAGING_PREFIX = ".staging-"

# version -> function turning a file of that version into the next version's shape
MIGRATIONS: dict[int, Callable[[dict[str, Any]], dict[str, Any]]] = {}


class ResultFileError(ValueError):
    """A result file that cannot be read: the message names the file and what is wrong."""


def runs_dir(results: Path) -> Path:
    return results / RUNS


def new_stem(now: datetime | None = None, prefix: str = "bench-") -> str:
    """A fresh run name that sorts by start time, to the millisecond (two short runs can
    start within one second): ``bench-20250101T120000123Z-1a2b3c``."""
    now = now or datetime.now(UTC)
    stamp = now.strftime("%Y%m%dT%H%M%S") + f"{now.microsecond // 1000:03d}Z"
    return f"{prefix}{stamp}-{secrets.token_hex(3)}"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_staging(results: Path) -> list[Path]:
    """Remove staging folders left by killed runs (their process is gone); returns them."""
    removed: list[Path] = []
    folder = runs_dir(results)
    if not folder.is_dir():
        return removed
    for entry in folder.glob(f"{STAGING_PREFIX}*"):
        try:
            pid = int(entry.name.rsplit("-", 1)[1])
        except (IndexError, ValueError):
            continue
        if pid != os.getpid() and not _pid_alive(pid):
            shutil.rmtree(entry, ignore_errors=True)
            removed.append(entry)
    return removed


class RunWriter:
    """Stages one run's images, then publishes images and JSON together (see the module)."""

    def __init__(self, results: Path) -> None:
        self.results = results
        folder = runs_dir(results)
        folder.mkdir(parents=True, exist_ok=True)
        remove_stale_staging(results)
        while True:
            self.stem = new_stem()
            if not (folder / f"{self.stem}.json").exists() and not (folder / self.stem).exists():
                break
        self.staging = folder / f"{STAGING_PREFIX}{self.stem}-{os.getpid()}"
        self.staging.mkdir()

    @property
    def json_path(self) -> Path:
        return runs_dir(self.results) / f"{self.stem}.json"

    @property
    def images_path(self) -> Path:
        return runs_dir(self.results) / self.stem

    def publish(self, document: dict[str, Any]) -> Path:
        """Move the images into place, then write the JSON; refuses to replace anything."""
        if self.json_path.exists() or self.images_path.exists():
            raise FileExistsError(f"{self.json_path} already exists; results are never replaced")
        os.rename(self.staging, self.images_path)
        write_new_file(self.json_path, json.dumps(document, indent=1, sort_keys=False) + "\n")
        return self.json_path

    def abandon(self) -> None:
        shutil.rmtree(self.staging, ignore_errors=True)


def write_new_file(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically; a ``FileExistsError`` if ``path`` exists."""
    fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(temporary, 0o644)
        try:
            os.link(temporary, path)  # atomic, and never replaces an existing file
        except FileExistsError:
            raise FileExistsError(f"{path} already exists; results are never replaced") from None
        except OSError:  # a file system without hard links: check, then rename
            if path.exists():
                raise FileExistsError(
                    f"{path} already exists; results are never replaced"
                ) from None
            os.replace(temporary, path)
    finally:
        Path(temporary).unlink(missing_ok=True)


def pyperf_document(benchmarks: list[dict[str, Any]], rtc: dict[str, Any]) -> dict[str, Any]:
    """The run file: a pyperf suite of ``benchmarks`` plus our ``rtc`` section.

    benchmarks: ``{"name": ..., "values": [seconds, ...], "metadata": {...}}`` each;
    metadata values must be str, int or float (pyperf's rule).
    """
    import pyperf

    suite = None
    for bench in benchmarks:
        metadata = {"name": bench["name"], "unit": "second", **bench.get("metadata", {})}
        metadata = {k: v for k, v in metadata.items() if v is not None and v != ""}
        run = pyperf.Run(bench["values"], metadata=metadata, collect_metadata=False)
        benchmark = pyperf.Benchmark([run])
        if suite is None:
            suite = pyperf.BenchmarkSuite([benchmark])
        else:
            suite.add_benchmark(benchmark)
    if suite is None:
        data: dict[str, Any] = {"version": "1.0", "benchmarks": [], "metadata": {}}
    else:
        buffer = io.StringIO()
        suite.dump(buffer, compact=False)
        data = json.loads(buffer.getvalue())
    data["rtc"] = {"schema_version": SCHEMA_VERSION, **rtc}
    return data


def upgrade(data: dict[str, Any], source: str) -> dict[str, Any]:
    """``data`` brought to the current schema through ``MIGRATIONS``; errors name ``source``."""
    rtc = data.get("rtc")
    if not isinstance(rtc, dict):
        raise ResultFileError(f"{source}: not an rtc bench result (no 'rtc' section)")
    version = rtc.get("schema_version")
    if not isinstance(version, int) or version < 1:
        raise ResultFileError(f"{source}: bad schema_version {version!r}")
    if version > SCHEMA_VERSION:
        raise ResultFileError(
            f"{source}: schema version {version} is newer than this harness reads "
            f"({SCHEMA_VERSION}); update the project"
        )
    while version < SCHEMA_VERSION:
        if version not in MIGRATIONS:
            raise ResultFileError(f"{source}: no migration from schema version {version}")
        data = MIGRATIONS[version](data)
        version += 1
        data["rtc"]["schema_version"] = version
    return data


def load_run(path: Path) -> dict[str, Any]:
    """One run file, upgraded to the current schema; ``ResultFileError`` if unreadable."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ResultFileError(f"{path}: cannot read the result file: {error}") from None
    if not isinstance(data, dict):
        raise ResultFileError(f"{path}: expected a JSON object")
    data = upgrade(data, str(path))
    data["rtc"].setdefault("stem", path.stem)
    return data


def list_runs(results: Path) -> list[Path]:
    """Every run file under ``results/runs``, oldest first (their names sort by time)."""
    folder = runs_dir(results)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.glob("bench-*.json") if not p.name.startswith("."))
