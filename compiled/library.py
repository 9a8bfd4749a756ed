"""A numba ``cfunc`` as a shared library: compiled once, kept in the kernel folder, loaded
with ctypes by every later process, which then never imports numba.

Importing numba (about 0.2 s) and the first call of any cached numba function (about 0.15 s:
numba fills its typing and lowering registries even to load cached code) cost more than many
whole commands. So a compiled function is built once: numba compiles it as a C function over
raw pointers (``cfunc``), its machine code is written as a position-independent object file
(for this CPU) and the system C compiler links it, with a small C entry point, into
``<kernel folder>/<name>_<digest>.so``. The digest covers the function's source files, the C
entry point, the CPU, the OS, Python, numba and llvmlite, so any change gives a new library.
Where no C compiler works, the caller falls back to numba itself (and pays its start-up).

numba's generated wrapper keeps an error path that calls numba's runtime helpers
(``numba_do_raise`` ...), which are not in the library; the functions built here cannot
raise (no ``raise``, ``error_model="numpy"``, no bounds checks), so the path is dead, and the
library defines those names as stubs that abort with a message, should it ever run.

The kernel folder is private, since what is in it runs: ``$RTC_NUMBA_KERNELS`` if set (a
folder of this user's that no other user can write in), else ``$XDG_CACHE_HOME/rtc-workbook/
numba-kernels`` (``~/.cache/...``), made with mode 0700 (an older one is made private; one
others could write in is emptied first). Where the home folder cannot be written, the same
under ``$XDG_RUNTIME_DIR`` or the temporary directory (``rtc-numba-kernels-UID``), used only
if it is a real folder of this user's, private; if another user made it first, a new private
temporary folder for this process alone (one line says so). numba's own disk cache (the
fallback, and the generated kernel modules' entry points) is kept in it too (``numba-cache``).

Every library is checked before it is loaded. Building one writes the library under a name
holding its digest (``<prefix><key>-<sha256>.so``, written to a temporary file and renamed)
and then a record, ``<prefix><key>.json``, naming it with its SHA-256 and the build key's
(replaced atomically: a concurrent build or reader sees one record or the other, whole). A
library is loaded only if its record names this build key and its bytes have the digest
recorded; a library cut short, changed, another kernel's under this name, a record or a
library that is garbage, a folder or unreadable is built again, with one line saying so.
"""

from __future__ import annotations

import atexit
import contextlib
import ctypes
import functools
import hashlib
import importlib.metadata
import importlib.util
import json
import os
import platform
import re
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from compiled import KernelFolderError, compile_log

_lock = threading.RLock()

CompileListener = Callable[[str, float | None], object]
"""Told ``(what, None)`` when a compile starts and ``(what, seconds)`` when it ends."""
_listeners: list[CompileListener] = []


def on_compile(listener: CompileListener) -> Callable[[], None]:
    """Call ``listener`` around every compile of this process (a shared library built, or
    numba compiling where none can be built): a command line shows what is compiling and
    that it happens once. Returns a function that removes the listener."""
    _listeners.append(listener)
    return lambda: _listeners.remove(listener)


def announce(what: str, seconds: float | None = None) -> None:
    """Tell the ``on_compile`` listeners: compiling ``what`` starts (``seconds`` None), or
    took ``seconds`` (a Dask worker's compiles reach the client this way)."""
    for listener in list(_listeners):
        listener(what, seconds)


def say(line: str) -> None:
    """One line on stderr about the compiled code (a library built again, a folder made
    private), once per process for each line."""
    with _lock:
        if line in _said:
            return
        _said.add(line)
    print(f"rtc: {line}", file=sys.stderr, flush=True)


_said: set[str] = set()
_folders: dict[tuple[str, ...], Path] = {}
OURS = ("rtc_*", ".rtc_*", "rtc-numba-link-*", "numba-cache", "__pycache__", ".writable")
"""What the kernel folder holds, by name: what is removed from one others could write in."""


def kernel_folder() -> Path:
    """Where compiled libraries (and numba's cache of generated modules) are kept: a private
    folder of this user's (see the module), created if needed; a ``KernelFolderError`` when
    ``$RTC_NUMBA_KERNELS`` names one that cannot be."""
    names = ("RTC_NUMBA_KERNELS", "XDG_CACHE_HOME", "HOME", "XDG_RUNTIME_DIR", "TMPDIR")
    memo = tuple(os.environ.get(name, "") for name in names)
    with _lock:
        known = _folders.get(memo)
        if known is not None and known.is_dir():
            return known
        folder = _choose_folder()
        _folders[memo] = folder
        return folder


def _choose_folder() -> Path:
    chosen = os.environ.get("RTC_NUMBA_KERNELS")
    if chosen:
        why = _private(Path(chosen), tighten=False)
        if why:
            raise KernelFolderError(
                f"RTC_NUMBA_KERNELS={chosen!r}: {why}; name a folder of your own that no "
                "other user can write in (it is made if missing)"
            )
        return Path(chosen)
    cache_home = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    candidates = [Path(cache_home) / "rtc-workbook" / "numba-kernels"]
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if runtime:
        candidates.append(Path(runtime) / "rtc-numba-kernels")
    candidates.append(Path(tempfile.gettempdir()) / f"rtc-numba-kernels-{os.geteuid()}")
    reasons = []
    for folder in candidates:
        why = _private(folder, tighten=True)
        if not why:
            return folder
        reasons.append(f"{folder}: {why}")
    fresh = Path(tempfile.mkdtemp(prefix="rtc-numba-kernels-"))  # 0700, a new random name
    atexit.register(shutil.rmtree, fresh, ignore_errors=True)
    os.environ["RTC_NUMBA_KERNELS"] = str(fresh)  # this process's workers share it
    say(
        f"no private folder for compiled code ({'; '.join(reasons)}): using {fresh} for this "
        "process alone, so its code is compiled again next time"
    )
    return fresh


def _private(folder: Path, *, tighten: bool) -> str:
    """Why ``folder`` cannot hold compiled code, or "": made if missing (mode 0700); it must
    be a folder (not a link to one) of this user's that no other user can write in. With
    ``tighten``, one of ours that others can read is made private, and one others could
    write in is emptied of what we keep there first (it could hold anything)."""
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        with contextlib.suppress(FileExistsError):
            folder.mkdir(mode=0o700)
        info = folder.lstat()
    except OSError as error:
        return f"cannot make it ({error.strerror or error})"
    if stat.S_ISLNK(info.st_mode):
        return "it is a symbolic link, not a folder"
    if not stat.S_ISDIR(info.st_mode):
        return "it is not a folder"
    if info.st_uid != os.geteuid():
        return f"it belongs to another user (uid {info.st_uid})"
    mode = stat.S_IMODE(info.st_mode)
    if mode & 0o022:
        if not tighten:
            return f"other users can write in it (mode {mode:o})"
        _empty(folder)
        say(f"the kernel folder {folder} was writable by other users (mode {mode:o}): emptied")
    if mode & 0o077 and tighten:
        try:
            os.chmod(folder, 0o700)
        except OSError as error:
            return f"cannot make it private ({error.strerror or error})"
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".rtc-write-check-"):
            pass
    except OSError as error:
        return f"cannot write in it ({error.strerror or error})"
    return ""


def _empty(folder: Path) -> None:
    """Remove what this project keeps in ``folder`` (``OURS``), whatever it has become."""
    for pattern in OURS:
        for path in folder.glob(pattern):
            _remove(path)


def _remove(path: Path) -> None:
    """Remove ``path``, a file, a link or a folder (what was found where a file belongs)."""
    with contextlib.suppress(OSError):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)


NUMBA_CACHE_SET = "_RTC_NUMBA_CACHE_DIR"
"""Where ``private_numba_cache`` pointed ``NUMBA_CACHE_DIR`` (inherited by child processes):
a value equal to it is ours to move along with the kernel folder, any other the user's."""


def private_numba_cache() -> None:
    """Keep numba's disk cache in the kernel folder (``numba-cache``), before numba compiles
    or loads anything of ours: never a folder another user can write in (its files are
    pickles: loading one runs what it says). A ``NUMBA_CACHE_DIR`` the user set is kept. A
    damaged file in numba's cache is a miss, compiled again with one line
    (``_damaged_cache_is_a_miss``)."""
    given = os.environ.get("NUMBA_CACHE_DIR")
    if not given or given == os.environ.get(NUMBA_CACHE_SET):
        folder = kernel_folder() / "numba-cache"
        with contextlib.suppress(FileExistsError):
            folder.mkdir(mode=0o700)
        os.environ["NUMBA_CACHE_DIR"] = os.environ[NUMBA_CACHE_SET] = str(folder)  # numba
        config = sys.modules.get("numba.core.config")  # reads it when it is imported; if
        if config is not None:  # it is already, what it decorates from now on uses this
            config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
    _damaged_cache_is_a_miss()
    compile_log.watch_numba()


def _damaged_cache_is_a_miss() -> None:
    """numba reads its cache's index and data files with ``pickle`` and lets whatever a
    damaged file raises through (a traceback on every run until the file is deleted). Here
    such a file is a miss instead: the function is compiled again and the file rewritten,
    with one line saying so. (numba's ``IndexDataCacheFile``; left alone if it changes.)"""
    from numba.core import caching

    files: Any = getattr(caching, "IndexDataCacheFile", None)
    if files is None or getattr(files, "_rtc_checked", False):
        return
    load_index, load_data = getattr(files, "_load_index", None), getattr(files, "_load_data", None)
    if load_index is None or load_data is None:
        return

    def checked_index(self: Any) -> Any:
        try:
            return load_index(self)
        except Exception as error:  # an unpickling error of any kind
            where = self._index_path
            say(f"numba's cache file {where} is damaged ({error!r:.80}): compiling again")
            return {}

    def checked_data(self: Any, name: str) -> Any:
        try:
            return load_data(self, name)
        except OSError:
            raise
        except Exception as error:  # numba takes an OSError for a missing file: a miss
            say(f"numba's cache file {name} is damaged ({error!r:.80}): compiling again")
            raise OSError(f"damaged: {name}") from None

    files._load_index = checked_index
    files._load_data = checked_data
    files._rtc_checked = True


def _stat_key(package: str) -> str:
    """An installed package's identity without importing it: the hashes its installer
    recorded for the package's files, so that the same wheel installed in another
    environment (a fresh clone's ``.venv``) is the same package and the libraries built for
    it are reused; without such a record, its path, size and mtime."""
    try:
        record = importlib.metadata.distribution(package).read_text("RECORD") or ""
    except importlib.metadata.PackageNotFoundError:
        record = ""
    files = sorted(
        line
        for line in record.splitlines()
        if line.startswith(f"{package}/") and "/__pycache__/" not in line
    )
    if files:
        digest = hashlib.sha256("\n".join(files).encode("utf-8")).hexdigest()
        return f"{package}: {digest}"
    spec = importlib.util.find_spec(package)
    if spec is None or spec.origin is None:
        return f"{package}: missing"
    stat = os.stat(spec.origin)
    return f"{package}: {spec.origin} {stat.st_size} {stat.st_mtime_ns}"


@functools.lru_cache(maxsize=1)
def platform_key() -> str:
    """What machine code depends on besides its source: the CPU (model and instruction-set
    flags), the OS and Python, numba and llvmlite."""
    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            lines = info.read().split("\n\n", 1)[0].splitlines()
        cpu = "\n".join(
            line for line in lines if line.split(":")[0].strip() in ("model name", "flags")
        )
    except OSError:
        pass
    packages = [_stat_key(name) for name in ("numba", "llvmlite")]
    return "\n".join([cpu, platform.machine(), platform.system(), sys.version, *packages])


MAX_LIBRARY_BYTES = 256 << 20  # a render kernel is a few MB
_keys: dict[str, str] = {}  # a library's path -> its build key's SHA-256


def library_path(prefix: str, *key_parts: str) -> Path:
    """Where the library whose build depends on ``key_parts`` (its source texts and C entry
    point) is known: ``<kernel folder>/<prefix><digest>.so``, a name (the library itself is
    kept under its own digest, named by the record ``<prefix><digest>.json``: ``built``)."""
    key = "\n".join([*key_parts, UNREACHABLE, platform_key()])
    digest = hashlib.sha256(key.encode("utf-8")).hexdigest()
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
    from scene.files import read_bytes, read_text  # (scene's package imports this module)

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
    found = hashlib.sha256(data).hexdigest()
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
    digest = hashlib.sha256(data).hexdigest()
    library = path.parent / f"{path.stem}-{digest[:16]}.so"
    _replace(built_file, library)
    entry = {"key": _keys.get(str(path), ""), "library": library.name, "sha256": digest}
    fd, temporary = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent)
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
        _remove(target)
        os.replace(source, target)


class BuildError(RuntimeError):
    """A shared library could not be built (no C compiler, a link error ...)."""


def load_once(
    cache: dict[str, Any],
    path: Path,
    build: Callable[[], None],
    from_library: Callable[[ctypes.CDLL], Any],
    fallback: Callable[[str], Any],
    what: str,
) -> Any:
    """What the shared library known as ``path`` holds, once per process: checked first
    (``verify``), built if missing or unsound (``build``, one line saying why for a library
    that was there), read by ``from_library``; without it (a ``BuildError``, or a library
    the system cannot load), ``fallback(why)``. A build (and the fallback, which may
    compile) is announced to the ``on_compile`` listeners as ``what``."""
    key = str(path)
    with _lock:
        found = cache.get(key)
        if found is not None:
            return found
        problem = ""
        library, why = verify(path)
        compiling = False
        started = time.perf_counter()
        if library is None:
            with one_builder(path, what):  # another process's build of it: waited for
                library, why = verify(path)
                compiling = library is None
                if compiling:
                    if why:
                        say(f"{what} in {path.parent}: {why}: building it again")
                    announce(what)
                    try:
                        with compile_log.timed("library", what):
                            build()
                    except BuildError as error:
                        problem = str(error)
                    else:
                        library, why = verify(path)
                        problem = why or ("" if library is not None else "it was not written")
        loaded = None
        if library is not None:
            try:
                loaded = ctypes.CDLL(str(library))
            except OSError as error:  # a folder mounted noexec ...
                problem = f"the system cannot load {library}: {error}"
        found = from_library(loaded) if loaded is not None else fallback(problem)
        if compiling:
            announce(what, time.perf_counter() - started)
        cache[key] = found
        return found


@contextlib.contextmanager
def one_builder(path: Path, what: str) -> Iterator[None]:
    """Hold the lock of the library known as ``path`` (``.<name>.lock`` beside it, an
    ``flock``): the processes that need a library that is not built yet (the test workers of
    one run, a bench's children) build it one at a time, and the ones that waited then find
    it built. The lock goes with the process that holds it, however it ends. Where no lock
    can be had (no ``fcntl``, a lock file that cannot be made), each builds it as before."""
    try:
        import fcntl
    except ImportError:  # not a POSIX system
        yield
        return
    lock = path.parent / f".{path.stem}.lock"
    try:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o600)
    except OSError:
        yield
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:  # another process builds it: wait
            started = time.time(), time.perf_counter(), time.process_time()
            fcntl.flock(fd, fcntl.LOCK_EX)
            waited, cpu = time.perf_counter() - started[1], time.process_time() - started[2]
            compile_log.record("wait", what, waited, cpu, started[0])
        yield
    finally:
        os.close(fd)  # releases the lock


UNREACHABLE = """
static void unreachable(const char *name) {
    fprintf(stderr, "rtc: compiled code reached %s (an exception inside a kernel, which "
                    "cannot raise): this is a bug\\n", name);
    abort();
}
"""


def entry_stub(name: str, returns: str, parameters: Sequence[tuple[str, str]], about: str) -> str:
    """The C entry point ``name`` that calls a compiled ``cfunc`` (``ENTRY_SYMBOL``) with
    ``parameters`` ((C type, name) pairs); ``about`` names the function in its comment."""
    declared = ", ".join(f"{kind} {arg}" for kind, arg in parameters)
    passed = ", ".join(arg for _, arg in parameters)
    return (
        f"/* Generated by compiled.library: the C entry point of {about}, and stubs for numba\n"
        "   runtime helpers that only numba's (dead) error path calls. Do not edit. */\n"
        "#include <stdint.h>\n#include <stdio.h>\n#include <stdlib.h>\n\n"
        f'extern {returns} numba_entry({declared}) __asm__("ENTRY_SYMBOL");\n\n'
        f"{returns} {name}({declared}) {{\n    return numba_entry({passed});\n}}\n"
    )


def compiler() -> list[str]:
    """The C compiler: ``$CC``, else ``cc`` or ``gcc``; a ``BuildError`` when none."""
    found = (
        shlex.split(os.environ.get("CC", ""))
        or [found for found in (shutil.which("cc"), shutil.which("gcc")) if found][:1]
    )
    if not found:
        raise BuildError("no C compiler (cc, gcc or $CC) found")
    return found


def link(entry: Any, stub: str, path: Path, what: str) -> None:
    """Link a compiled ``cfunc`` ``entry`` with the C ``stub`` (which calls it as
    ``ENTRY_SYMBOL``) into the shared library ``path``; ``what`` names it in errors."""
    command_start = compiler()
    try:
        obj, helpers = _object_code(entry)
    except Exception as error:  # numba's internals moved: fall back to numba's own cache
        raise BuildError(f"cannot take the compiled {what} out of numba: {error!r}") from None
    runtime = [name for name in helpers if not name.startswith("numba_")]
    if runtime:
        raise BuildError(f"the compiled {what} calls numba's runtime ({', '.join(runtime)})")
    source = (
        stub.replace("ENTRY_SYMBOL", entry.native_name)
        + UNREACHABLE
        + "".join(f'void {name}(void) {{ unreachable("{name}"); }}\n' for name in helpers)
    )
    with tempfile.TemporaryDirectory(prefix="rtc-numba-link-", dir=path.parent) as folder:
        work = Path(folder)
        (work / "kernel.o").write_bytes(obj)
        (work / "entry.c").write_text(source, encoding="utf-8")
        built = work / path.name
        command = [  # names relative to the work folder: each build gives the same bytes
            *command_start, "-shared", "-fPIC", "-O2", "-o", built.name, "entry.c", "kernel.o",
            "-lm",
        ]  # fmt: skip
        try:
            done = subprocess.run(
                command, capture_output=True, text=True, timeout=300, cwd=work
            )
        except (OSError, subprocess.SubprocessError) as error:
            raise BuildError(f"{command_start[0]} failed to run: {error}") from None
        if done.returncode != 0 or not built.is_file():
            problem = done.stderr.strip()[:500] or f"exit status {done.returncode}"
            raise BuildError(f"{command_start[0]} could not link the {what}: {problem}")
        publish(built, path)


def _object_code(entry: Any) -> tuple[bytes, list[str]]:
    """The position-independent machine code of a compiled ``cfunc`` (numba's optimized,
    linked LLVM module, for this CPU), and the numba runtime functions it declares."""
    import llvmlite.binding as llvm

    module = entry._library._final_module
    target = llvm.Target.from_triple(llvm.get_process_triple())
    machine = target.create_target_machine(
        cpu=llvm.get_host_cpu_name(),
        features=llvm.get_host_cpu_features().flatten(),
        opt=3,
        reloc="pic",
        codemodel="default",
    )
    helpers = sorted(
        f.name
        for f in module.functions
        if f.is_declaration and f.name.startswith(("numba_", "NRT_"))
    )
    return machine.emit_object(module), helpers


# ------------------------------------------------------ one function, one library


@dataclass(frozen=True)
class Compiled:
    """A compiled function as a Python function over numpy arrays and numbers; ``origin``
    says where it came from (a shared library, or numba), ``keep`` holds what must stay
    alive while it is used."""

    function: Any
    origin: str
    keep: Any = None


C_TYPES = {
    "int64_t": ctypes.c_int64,
    "double": ctypes.c_double,
}


@dataclass(frozen=True)
class Recipe:
    """How to build and load one compiled function.

    name: the library's exported C name (and its file's prefix); module: the self-contained
    Python module holding it (imported only to build it, or to fall back); function: the
    ``njit`` function there (called with arrays when there is no library); make_entry: the
    module's function giving the ``cfunc`` (``make_entry(cache)``); parameters: the C
    parameters, (type, name) pairs: ``int64_t``, ``double`` or a pointer type (``...*``,
    given a numpy array); returns: the C return type; what: how messages name it.
    """

    name: str
    module: str
    function: str
    parameters: tuple[tuple[str, str], ...]
    what: str
    returns: str = "int64_t"
    make_entry: str = "make_entry"

    def stub(self) -> str:
        return entry_stub(self.name, self.returns, self.parameters, self.what)

    def path(self) -> Path:
        spec = importlib.util.find_spec(self.module)
        if spec is None or spec.origin is None:
            raise ImportError(f"cannot find {self.module}")
        source = Path(spec.origin).read_text(encoding="utf-8")
        return library_path(f"rtc_{self.name}_", source, self.stub(), self.name)


_loaded: dict[str, Compiled] = {}


def load(recipe: Recipe) -> Compiled:
    """``recipe``'s function: from its shared library (built first if missing), else
    numba's ``njit`` function with its disk cache. Once per process."""
    path = recipe.path()

    def build() -> None:
        compiler()
        private_numba_cache()
        module = importlib.import_module(recipe.module)
        entry = getattr(module, recipe.make_entry)(False)
        link(entry, recipe.stub(), path, recipe.what)

    def from_library(library: ctypes.CDLL) -> Compiled:
        entry = getattr(library, recipe.name)
        entry.restype = C_TYPES[recipe.returns]
        entry.argtypes = [
            ctypes.c_void_p if kind.endswith("*") else C_TYPES[kind]
            for kind, _ in recipe.parameters
        ]

        def through_ctypes(*arguments: Any) -> Any:
            return entry(*[a.ctypes.data if hasattr(a, "ctypes") else a for a in arguments])

        return Compiled(through_ctypes, f"shared library {path}", library)

    def fallback(problem: str) -> Compiled:
        private_numba_cache()
        module = importlib.import_module(recipe.module)
        return Compiled(
            getattr(module, recipe.function),
            f"numba with its disk cache (no shared library: {problem})",
        )

    found: Compiled = load_once(_loaded, path, build, from_library, fallback, recipe.what)
    return found
