"""The measurement history: one JSON file per bench run in ``results/runs/``, never replaced.

Layout of ``results/``::

    runs/bench-<UTC time>-<random>.json   one per run (pyperf-compatible, plus "rtc")
    runs/bench-<UTC time>-<random>/       that run's images (PNG)
    README.md, report.html, report/       written by ``rtc report`` from the runs

A run file is a pyperf ``BenchmarkSuite`` (``python -m pyperf show FILE`` and ``compare_to``
read it: one benchmark per measured row, its values the wall times of the repeats, in seconds)
with one more top-level key, ``"rtc"``, holding our schema: ``schema_version``, ``machine``,
``settings`` and the rows, series and chapter progress (see ``harness.engine.bench``).

Reading for the report: ``check_run`` checks the fields the report uses (a missing or
wrong-typed field, a NaN or infinite number anywhere) and names the first one wrong, so that
one damaged file is skipped with a warning instead of stopping the report.

Writing: images go to a hidden staging folder, which is renamed into place when the run
completes, and the JSON is written to a temporary file and hard-linked to its final name (a
link never replaces an existing file) before the temporary name is removed. A run killed at
any moment leaves no result file; a killed run's hidden staging folder is removed by the next
run. A run holds a lock (``fcntl.flock``) on a file beside its staging folder for as long as
it writes there: the kernel lets go of it when the process ends however it ends, so the next
run tells a dead run's folder from a living one's even from another PID namespace (two
containers sharing the results folder), where a process id says nothing.
"""

from __future__ import annotations

import fcntl
import io
import json
import math
import os
import secrets
import shutil
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from groundwork.files import read_text, write_new
from harness.engine.sharing import pid_alive

SCHEMA_VERSION = 2
MAX_RUN_FILE_BYTES = 64 << 20  # a run file is a few hundred kB; more is no run file of ours
LONGEST_SECONDS = 1e9  # a timed render of more seconds (some 30 years) is no measurement
LARGEST_NUMBER = 1e15  # nothing a run measures (bytes, rays, seconds) comes near it
NOT_MEASURED = (".seed",)  # numbers that are names, not measurements: any size is right
RUNS = "runs"
STAGING_PREFIX = ".staging-"
LOCK_SUFFIX = ".lock"  # beside a staging folder: held (flock) by the run that writes it

RENAMED_SECTIONS = {
    "truth": ("sweep", "truth"),
    "sizes": ("scaling", "sizes"),
    "threads": ("scaling", "threads"),
    "light-truth": ("light-samples", "truth"),
    "bonus-picture": ("light-samples", "picture"),
}
"""Schema 1's names of rows and series entries that were not ``rtc bench --sections``
names -> the section (as the command line names it) and the part of it, in schema 2."""


def _sections_named_as_the_command_line(data: dict[str, Any]) -> dict[str, Any]:
    """Schema 1 -> 2: every row and series entry's ``section`` is a ``--sections`` name,
    with a ``part`` where the section writes several kinds (``RENAMED_SECTIONS``)."""
    rtc = data["rtc"]
    for key in ("rows", "series"):
        items = rtc.get(key)
        for item in items if isinstance(items, list) else []:
            section = item.get("section") if isinstance(item, dict) else None
            if isinstance(section, str) and section in RENAMED_SECTIONS:  # damaged: left as is
                item["section"], item["part"] = RENAMED_SECTIONS[section]
    return data


# version -> function turning a file of that version into the next version's shape
MIGRATIONS: dict[int, Callable[[dict[str, Any]], dict[str, Any]]] = {
    1: _sections_named_as_the_command_line,
}


class ResultFileError(ValueError):
    """A result file that cannot be read: the message names the file and what is wrong.

    One line, whatever the file holds: a line break in it (a key read from the file) is
    written as an escape."""

    def __init__(self, message: str) -> None:
        super().__init__(message.translate({ord(c): repr(c)[1:-1] for c in _LINE_BREAKS}))


_LINE_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"  # where str.splitlines breaks


def runs_dir(results: Path) -> Path:
    return results / RUNS


def new_stem(now: datetime | None = None, prefix: str = "bench-") -> str:
    """A fresh run name that sorts by start time, to the millisecond (two short runs can
    start within one second): ``bench-20250101T120000123Z-1a2b3c``."""
    now = now or datetime.now(UTC)
    stamp = now.strftime("%Y%m%dT%H%M%S") + f"{now.microsecond // 1000:03d}Z"
    return f"{prefix}{stamp}-{secrets.token_hex(3)}"

    return True


def _lock_path(staging: Path) -> Path:
    return staging.with_name(staging.name + LOCK_SUFFIX)


def _hold_lock(path: Path) -> int | None:
    """A descriptor holding ``path``'s exclusive lock (``fcntl.flock``), made if missing;
    None when another process holds it (it is alive, wherever it runs)."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    except BaseException:
        os.close(fd)
        raise
    return fd


def _abandoned(staging: Path) -> bool:
    """Whether the run that made ``staging`` is over: its lock file is held by no process
    (a lock dies with its process, in any PID namespace or container sharing the folder);
    for a staging folder of a version without lock files, its process id is gone."""
    lock = _lock_path(staging)
    if lock.exists():
        fd = _hold_lock(lock)
        if fd is None:
            return False
        os.close(fd)
        return True
    try:
        pid = int(staging.name.rsplit("-", 1)[1])
    except (IndexError, ValueError):
        return False
    return pid != os.getpid() and not pid_alive(pid)


def remove_stale_staging(results: Path) -> list[Path]:
    """Remove staging folders left by killed runs (no process holds their lock); returns
    them."""
    removed: list[Path] = []
    folder = runs_dir(results)
    if not folder.is_dir():
        return removed
    for entry in folder.glob(f"{STAGING_PREFIX}*"):
        if entry.name.endswith(LOCK_SUFFIX) or not _abandoned(entry):
            continue
        shutil.rmtree(entry, ignore_errors=True)
        _lock_path(entry).unlink(missing_ok=True)
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
        self._lock = _hold_lock(_lock_path(self.staging))  # first: the folder is never unheld
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
        try:
            write_new_file(self.json_path, json.dumps(document, indent=1, sort_keys=False) + "\n")
        except BaseException:  # a full disk: no run's images without their run file
            shutil.rmtree(self.images_path, ignore_errors=True)
            raise
        finally:
            self._release()
        return self.json_path

    def abandon(self) -> None:
        shutil.rmtree(self.staging, ignore_errors=True)
        self._release()

    def _release(self) -> None:
        """Remove the staging folder's lock file, then let go of the lock."""
        if self._lock is not None:
            _lock_path(self.staging).unlink(missing_ok=True)
            os.close(self._lock)
            self._lock = None


def write_new_file(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically; a ``FileExistsError`` if ``path`` exists."""
    if not write_new(path, text, sync=True):
        raise FileExistsError(f"{path} already exists; results are never replaced")


def pyperf_document(benchmarks: list[dict[str, Any]], rtc: dict[str, Any]) -> dict[str, Any]:
    """The run file: a pyperf suite of ``benchmarks`` plus our ``rtc`` section.

    benchmarks: ``{"name": ..., "values": [seconds, ...], "metadata": {...}}`` each;
    metadata values must be str, int or float (pyperf's rule).
    """
    # deferred: saves ~170 ms (pyperf) of every command that reads runs and writes none
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
        data = json.loads(read_text(path, MAX_RUN_FILE_BYTES))
    except OSError as error:  # a named pipe, a device, a file too large ...
        raise ResultFileError(
            f"{path}: cannot read the result file: {error.strerror or error}"
        ) from None
    except (ValueError, RecursionError) as error:  # ValueError: JSON's, UTF-8's, and
        # an integer of thousands of digits; RecursionError: arrays nested thousands deep
        raise ResultFileError(f"{path}: cannot read the result file: {error}") from None
    if not isinstance(data, dict):
        raise ResultFileError(f"{path}: expected a JSON object")
    data = upgrade(data, str(path))
    data["rtc"].setdefault("stem", path.stem)
    return data


# ------------------------------------------------------------------ checking a run's fields

# A spec is a dict of field specs ("?key": optional, may also be absent); a field spec is a
# type, None (the value may be null), a tuple of alternatives, a one-item list (a list of
# that), a dict (a nested spec), or one of the names below.
Spec = Any
NUMBER = "number"  # an int or float, not a bool
SIZE = "size"  # [width, height], whole numbers of at least 1
TIMES = "times"  # a non-empty list of numbers above 0 (seconds), below LONGEST_SECONDS

MACHINE: Spec = {
    "hostname": str, "cpu_model": str, "cpu_count": int, "cores_available": int,
    "python": str, "?load_average": ([NUMBER], None), "?commit": (str, None),
    "?dirty": (bool, None), "?numpy": (str, None), "?numba": (str, None),
}  # fmt: skip
SETTINGS: Spec = {
    "size": SIZE, "samples": int, "depth": int, "seed": int, "repeat": int,
    "budget": (NUMBER, None), "threads": (int, None), "?epsilon": (NUMBER, None),
    "scene": {"name": str}, "?preset": str,
    "mode": {"name": str, "?preset_size": SIZE, "?side_repeat": int},
}  # fmt: skip
ROW: Spec = {"section": str, "name": str, "status": str, "?error": str, "?part": str}
ROW_OK: Spec = {
    "size": SIZE, "samples": int, "wall": TIMES, "cpu": [NUMBER], "?cores": int,
    "?reduced": bool, "?budget_note": (str, None), "?compare_size": SIZE,
    "?image": (str, None), "?compare_image": (str, None), "?heatmap": (str, None),
    "?warmup": {"?first": NUMBER, "?second": NUMBER},
    "?speedup": ({"value": NUMBER, "basis": str}, None),
    "?error_vs_naive": ({"max_abs": NUMBER, "mean_abs": NUMBER, "rmse": NUMBER,
                         "psnr": (NUMBER, None), "pixels_over_one_step": int,
                         "pixels": int}, None),
    "?allocations": ({"count": (int, None), "bytes": (int, None), "method": str}, None),
    "?peak_memory": ({"main": NUMBER, "?workers": (NUMBER, None)}, None),
    "?rays": ({"total": int}, None), "?group": str, "?count": int,
}  # fmt: skip
POINT: Spec = {
    "?size": SIZE, "?samples": int, "?wall": NUMBER, "?cpu": (NUMBER, [NUMBER]),
    "?skipped": str, "?image": (str, None),
}  # fmt: skip
SERIES: Spec = {"section": str, "name": str, "?status": str, "?part": str, "?points": [POINT]}
RUN: Spec = {
    "stem": str, "started": str, "seconds": NUMBER, "machine": MACHINE,
    "settings": SETTINGS, "rows": [ROW], "series": [SERIES], "compare_size": SIZE,
    "?notes": [str], "?kata": (dict, None), "?unavailable": (dict, None),
    "?heat_full_scale": NUMBER, "?heat_scale": {"kind": str, "low": NUMBER, "high": NUMBER},
    "?load": (dict, None), "?shared": (str, None),
}  # fmt: skip


def _kind(spec: Spec) -> str:
    """What ``spec`` expects, in words, for an error message."""
    if spec is None:
        return "null"
    if isinstance(spec, tuple):
        return " or ".join(_kind(s) for s in spec)
    if isinstance(spec, list):
        return f"a list of {_kind(spec[0])}s" if not isinstance(spec[0], dict) else "a list"
    if isinstance(spec, dict):
        return "an object"
    words = {
        NUMBER: "a number", SIZE: "[width, height]",
        TIMES: f"a list of seconds above 0 and below {LONGEST_SECONDS:g}",
    }  # fmt: skip
    if isinstance(spec, str):
        return words[spec]
    return {str: "text", int: "a whole number", bool: "true or false", dict: "an object",
            list: "a list"}.get(spec, spec.__name__)  # fmt: skip


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _fits(value: Any, spec: Spec, where: str) -> str | None:
    """Why ``value`` does not fit ``spec`` (naming the field ``where``), or None."""
    if isinstance(spec, tuple):
        reasons = [_fits(value, s, where) for s in spec]
        if any(r is None for r in reasons):
            return None
        deeper = [r for r, s in zip(reasons, spec, strict=True) if _shape_matches(value, s)]
        return deeper[0] if deeper else f"{where}: expected {_kind(spec)}, got {_got(value)}"
    if spec is None:
        return None if value is None else f"{where}: expected null, got {_got(value)}"
    if isinstance(spec, dict):
        if not isinstance(value, dict):
            return f"{where}: expected an object, got {_got(value)}"
        for key, field in spec.items():
            name = key.lstrip("?")
            inner = f"{where}.{name}" if where else name
            if name not in value:
                if key.startswith("?"):
                    continue
                return f"{inner}: missing"
            why = _fits(value[name], field, inner)
            if why:
                return why
        return None
    if isinstance(spec, list):
        if not isinstance(value, list):
            return f"{where}: expected {_kind(spec)}, got {_got(value)}"
        for i, item in enumerate(value):
            why = _fits(item, spec[0], f"{where}[{i}]")
            if why:
                return why
        return None
    if spec == NUMBER:
        ok = _is_number(value)
    elif spec == SIZE:
        ok = isinstance(value, list) and len(value) == 2
        ok = ok and all(type(v) is int and v >= 1 for v in value)
    elif spec == TIMES:
        ok = isinstance(value, list) and bool(value)
        ok = ok and all(_is_number(v) and 0 < v < LONGEST_SECONDS for v in value)
    elif spec is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, spec)
    return None if ok else f"{where}: expected {_kind(spec)}, got {_got(value)}"


def _shape_matches(value: Any, spec: Spec) -> bool:
    """Whether ``value`` has ``spec``'s outer shape (so its deeper error is the one to
    report among alternatives)."""
    return (isinstance(spec, dict) and isinstance(value, dict)) or (
        isinstance(spec, list) and isinstance(value, list)
    )


def _got(value: Any) -> str:
    text = json.dumps(value, allow_nan=True)
    return text if len(text) <= 40 else text[:37] + "..."


def number_problem(value: Any, where: str) -> str | None:
    """The first NaN, infinite or huge number in ``value`` (a JSON tree), named, or None:
    arithmetic on 1e300 overflows where a measurement never would."""
    if isinstance(value, float) and not math.isfinite(value):
        return f"{where}: {value} is not a measurement"
    if _is_number(value) and abs(value) > LARGEST_NUMBER and not where.endswith(NOT_MEASURED):
        digits = len(str(abs(value)))
        shown = f"{value:.3g}" if isinstance(value, float) else f"a number of {digits} digits"
        return f"{where}: {shown} is not a measurement (above {LARGEST_NUMBER:g})"
    if isinstance(value, dict):
        items: Any = ((f"{where}.{k}" if where else str(k), v) for k, v in value.items())
    elif isinstance(value, list):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for inner, item in items:
        why = number_problem(item, inner)
        if why:
            return why
    return None


def _plain_name(text: str) -> bool:
    """Whether ``text`` names a file and nothing more: no folder (``../``), no hidden
    file, no control character (a run's stem is shown and linked by the report)."""
    plain = all(c.isascii() and (c.isalnum() or c in "._-") for c in text)
    return plain and bool(text) and text[0] != "."


# A run of ours holds tens of rows and series (a full bench some hundreds); a file with more
# is refused before its rows are walked, so that the report's time stays bounded.
MAX_ROWS = 10_000


def _too_many(rtc: Any) -> str | None:
    """Why ``rtc``'s rows or series are too many to be a run of ours, else None."""
    if not isinstance(rtc, dict):
        return None
    for key in ("rows", "series"):
        items = rtc.get(key)
        if isinstance(items, list) and len(items) > MAX_ROWS:
            return (
                f"{key}: {len(items):,} of them, more than a run of this project holds "
                f"({MAX_ROWS:,})"
            )
    series = rtc.get("series")
    points = sum(
        len(entry["points"])
        for entry in (series if isinstance(series, list) else [])
        if isinstance(entry, dict) and isinstance(entry.get("points"), list)
    )
    if points > MAX_ROWS:
        return f"series: {points:,} points, more than a run of this project holds ({MAX_ROWS:,})"
    return None


def check_run(rtc: Any, source: str) -> None:
    """A ``ResultFileError`` naming ``source`` and the first field the report cannot use
    (missing, of the wrong type, or a NaN or infinite number: ``rows[2].wall[0]``); None
    when the run's ``rtc`` section is fit for the report."""
    try:
        why = _too_many(rtc) or _fits(rtc, RUN, "") or number_problem(rtc, "")
    except RecursionError:  # lists or objects nested hundreds deep: no run file has them
        why = "values nested too deep to check"
    if why is None and not _plain_name(rtc["stem"]):
        why = f"stem: expected a plain name (letters, digits, '.', '-', '_'), got {rtc['stem']!r}"
    if why is None:
        for i, row in enumerate(rtc["rows"]):
            if row["status"] == "ok":
                why = _fits(row, ROW_OK, f"rows[{i}]")
                if why:
                    break
    if why:
        raise ResultFileError(f"{source}: {why}")


def list_runs(results: Path) -> list[Path]:
    """Every run file under ``results/runs``, oldest first (their names sort by time)."""
    folder = runs_dir(results)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.glob("bench-*.json") if not p.name.startswith("."))
