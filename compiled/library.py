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

The kernel folder is ``$RTC_NUMBA_KERNELS`` if set, else ``$XDG_CACHE_HOME/rtc-workbook/
numba-kernels`` (``~/.cache/...``), else a folder in the temporary directory.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import importlib.metadata
import importlib.util
import os
import platform
import shlex
import shutil
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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


def kernel_folder() -> Path:
    """Where compiled libraries (and numba's cache of generated modules) are kept; created
    if needed."""
    chosen = os.environ.get("RTC_NUMBA_KERNELS")
    if chosen:
        folder = Path(chosen)
    else:
        cache_home = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        folder = Path(cache_home) / "rtc-workbook" / "numba-kernels"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".writable"
        probe.touch()
        return folder
    except OSError:
        if chosen:
            raise RuntimeError(f"RTC_NUMBA_KERNELS={chosen!r} is not a writable folder") from None
        fallback = Path(tempfile.gettempdir()) / f"rtc-numba-kernels-{os.getuid()}"
        fallback.mkdir(parents=True, exist_ok=True)
        return fallback


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
    import sys

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


def library_path(prefix: str, *key_parts: str) -> Path:
    """Where the library whose build depends on ``key_parts`` (its source texts and C entry
    point) is kept: ``<kernel folder>/<prefix><digest>.so``."""
    key = "\n".join([*key_parts, UNREACHABLE, platform_key()])
    digest = hashlib.sha256(key.encode("utf-8")).hexdigest()[:16]
    return kernel_folder() / f"{prefix}{digest}.so"


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
    """What ``path``'s shared library holds, once per process: built first if missing
    (``build``), read by ``from_library``; without it (a ``BuildError``), ``fallback(why)``.
    A build (and the fallback, which may compile) is announced to the ``on_compile``
    listeners as ``what``."""
    key = str(path)
    with _lock:
        found = cache.get(key)
        if found is not None:
            return found
        problem = ""
        compiling = not path.is_file()
        started = time.perf_counter()
        if compiling:
            announce(what)
            try:
                build()
            except BuildError as error:
                problem = str(error)
        found = from_library(ctypes.CDLL(str(path))) if path.is_file() else fallback(problem)
        if compiling:
            announce(what, time.perf_counter() - started)
        cache[key] = found
        return found


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
        command = [
            *command_start, "-shared", "-fPIC", "-O2", "-o", str(built), str(work / "entry.c"),
            str(work / "kernel.o"), "-lm",
        ]  # fmt: skip
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=300)
        except (OSError, subprocess.SubprocessError) as error:
            raise BuildError(f"{command_start[0]} failed to run: {error}") from None
        if done.returncode != 0 or not built.is_file():
            problem = done.stderr.strip()[:500] or f"exit status {done.returncode}"
            raise BuildError(f"{command_start[0]} could not link the {what}: {problem}")
        os.replace(built, path)


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
        module = importlib.import_module(recipe.module)
        return Compiled(
            getattr(module, recipe.function),
            f"numba with its disk cache (no shared library: {problem})",
        )

    found: Compiled = load_once(_loaded, path, build, from_library, fallback, recipe.what)
    return found
