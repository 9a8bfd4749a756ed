"""Which library a build key names, and whether the file found is that library: the record
beside each library (its file, SHA-256 and build key), checked before it is loaded."""

from __future__ import annotations

import functools
import importlib.util
import json
import os
import platform
import re
import sys
from pathlib import Path

from compiled.entry import UNREACHABLE
from compiled.folder import kernel_folder, remove
from groundwork.files import new_file, read_bytes, read_text

try:  # the interpreter's own SHA-256 (hashlib would load OpenSSL's library, a few ms of every
    # render, for digests of a few hundred kilobytes at most)
    from _sha256 import sha256 as _sha256  # Python 3.11
except ImportError:  # pragma: no cover - Python 3.12 on, or a build without it
    try:
        from _sha2 import sha256 as _sha256  # Python 3.12 on
    except ImportError:
        from hashlib import sha256 as _sha256


def sha256_hex(data: bytes) -> str:
    """The SHA-256 of ``data`` in hexadecimal (as ``hashlib.sha256(data).hexdigest()``)."""
    return _sha256(data).hexdigest()


def _stat_key(package: str) -> str:
    """An installed package's identity without importing it: the hashes its installer
    recorded for the package's files, so that the same wheel installed in another
    environment (a fresh clone's ``.venv``) is the same package and the libraries built for
    it are reused; without such a record, its path, size and mtime."""
    spec = importlib.util.find_spec(package)
    record = _installed_record(package, spec.origin if spec is not None else None)
    files = sorted(
        line
        for line in record.splitlines()
        if line.startswith(f"{package}/") and "/__pycache__/" not in line
    )
    if files:
        digest = sha256_hex("\n".join(files).encode("utf-8"))
        return f"{package}: {digest}"
    if spec is None or spec.origin is None:
        return f"{package}: missing"
    stat = os.stat(spec.origin)
    return f"{package}: {spec.origin} {stat.st_size} {stat.st_mtime_ns}"


def _installed_record(package: str, origin: str | None) -> str:
    """The RECORD its installer wrote for ``package``: read from the ``.dist-info`` folder
    beside the package (one small file, where importlib.metadata would first be imported
    and scan every installed package: most of a warm render's kernel check), else found
    through importlib.metadata; "" when there is none."""
    if origin is not None:
        site = Path(origin).parent.parent
        try:
            beside = [
                name for name in os.listdir(site)
                if name.startswith(f"{package}-") and name.endswith(".dist-info")
            ]  # fmt: skip
            if len(beside) == 1:
                return read_text(site / beside[0] / "RECORD", 16 << 20)
        except (OSError, ValueError):
            pass
    import importlib.metadata  # deferred: only where the record is not beside the package

    try:
        return importlib.metadata.distribution(package).read_text("RECORD") or ""
    except importlib.metadata.PackageNotFoundError:
        return ""


@functools.lru_cache(maxsize=1)
def platform_key() -> str:
    """What machine code depends on besides its source: the CPU (model and instruction-set
    flags), the OS and Python, numba and llvmlite."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            lines = info.read().split("\n\n", 1)[0].splitlines()
        cpu = "\n".join(
            line for line in lines if line.split(":")[0].strip() in ("model name", "flags")
        )
    except OSError:  # not Linux: platform.processor() (which may run uname -p: a process)
        cpu = platform.processor()
    packages = [_stat_key(name) for name in ("numba", "llvmlite")]
    return "\n".join([cpu, platform.machine(), platform.system(), sys.version, *packages])


MAX_LIBRARY_BYTES = 256 << 20  # a render kernel is a few MB
_keys: dict[str, str] = {}  # a library's path -> its build key's SHA-256


@functools.lru_cache(maxsize=64)
def _key_digest(key_parts: tuple[str, ...]) -> str:
    """The SHA-256 of the build key of ``key_parts``, once per process (a render asks for
    its library every frame, and its key is a few hundred kilobytes of source)."""
    key = "\n".join([*key_parts, UNREACHABLE, platform_key()])
    return sha256_hex(key.encode("utf-8"))


def library_path(prefix: str, *key_parts: str) -> Path:
    """Where the library whose build depends on ``key_parts`` (its source texts and C entry
    point) is known: ``<kernel folder>/<prefix><digest>.so``, a name (the library itself is
    kept under its own digest, named by the record ``<prefix><digest>.json``: ``built``)."""
    digest = _key_digest(key_parts)
    path = kernel_folder() / f"{prefix}{digest[:16]}.so"
    _keys[str(path)] = digest
    return path


def record_path(path: Path) -> Path:
    """The record of the library known as ``path``: its file, digest and build key."""
    return path.with_suffix(".json")


def built(path: Path) -> Path | None:
    """The library file known as ``path`` if it is built and sound (``verify``), else None."""
    found, _why = verify(path)
    return found


def verify(path: Path) -> tuple[Path | None, str]:
    """The library file known as ``path`` once its record names this build key and its bytes
    have the digest recorded, with ""; else None and why not ("" when it was never built)."""
    folder = path.parent
    record = record_path(path)
    try:
        entry = json.loads(read_text(record, 1 << 16))
    except FileNotFoundError:
        older = path.exists() or path.is_symlink()  # an older version's library, or not ours
        return None, "it has no record of its digest (built by an older version?)" if older else ""
    except OSError as error:
        return None, f"its record {record.name} cannot be read ({error.strerror or error})"
    except ValueError:  # not UTF-8, not JSON
        return None, f"its record {record.name} is damaged"
    if not isinstance(entry, dict) or not all(
        isinstance(entry.get(k), str) for k in ("key", "library", "sha256")
    ):
        return None, f"its record {record.name} is damaged"
    expected = _keys.get(str(path))
    if expected is not None and entry["key"] != expected:
        return None, "its record is of another build (another kernel's library under its name)"
    name, digest = entry["library"], entry["sha256"]
    if name != f"{path.stem}-{digest[:16]}.so" or not re.fullmatch(r"[0-9a-f]{64}", digest):
        return None, f"its record {record.name} is damaged"
    library = folder / name
    try:
        data = read_bytes(library, MAX_LIBRARY_BYTES)
    except FileNotFoundError:
        return None, f"its library {name} is missing"
    except OSError as error:
        return None, f"its library {name} cannot be read ({error.strerror or error})"
    found = sha256_hex(data)
    if found != digest:
        return None, (
            f"its library {name} is not the one built (SHA-256 {found[:12]}..., "
            f"{len(data):,} bytes; recorded {digest[:12]}...)"
        )
    return library, ""


def publish(built_file: Path, path: Path) -> Path:
    """Move the freshly built library ``built_file`` into the kernel folder under its digest
    and record it as the library known as ``path`` (see the module); returns its new path."""
    data = built_file.read_bytes()
    digest = sha256_hex(data)
    library = path.parent / f"{path.stem}-{digest[:16]}.so"
    _replace(built_file, library)
    entry = {"key": _keys.get(str(path), ""), "library": library.name, "sha256": digest}
    fd, temporary = new_file(path.parent, f".{path.stem}.", ".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            json.dump(entry, out)
        _replace(Path(temporary), record_path(path))
    finally:
        Path(temporary).unlink(missing_ok=True)
    return library


def _replace(source: Path, target: Path) -> None:
    """``os.replace``, after removing a folder (or anything else) found in ``target``'s place."""
    try:
        os.replace(source, target)
    except OSError:
        remove(target)
        os.replace(source, target)
