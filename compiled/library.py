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

import ctypes
import importlib
import importlib.util
import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

from compiled import KernelFolderError, compile_log
from compiled.build_lock import one_builder
from compiled.entry import entry_stub
from compiled.folder import NUMBA_CACHE_SET, private_numba_cache
from compiled.linking import BuildError, compiler, link
from compiled.notices import announce, say
from compiled.records import library_path, verify

_lock = threading.RLock()


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
        try:
            found = _load_or_build(path, build, from_library, fallback, what)
        except (OSError, RuntimeError) as error:  # numba's "no locator available" is one
            if path.parent.is_dir() and _numba_cache_is_there():
                raise
            raise KernelFolderError(
                f"the kernel folder {path.parent} was removed or emptied while {what} was "
                f"being loaded or compiled ({type(error).__name__}); nothing was kept: run the "
                "command again"
            ) from None
        cache[key] = found
        return found


def _numba_cache_is_there() -> bool:
    """Whether numba's disk cache folder, when it is ours (``private_numba_cache``), is
    still there."""
    folder = os.environ.get(NUMBA_CACHE_SET)
    return folder is None or Path(folder).is_dir()


def _load_or_build(
    path: Path,
    build: Callable[[], None],
    from_library: Callable[[ctypes.CDLL], Any],
    fallback: Callable[[str], Any],
    what: str,
) -> Any:
    """``load_once``'s work, under its lock: the library checked, built when missing, loaded
    (or the fallback)."""
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
    return found


# ------------------------------------------------------ one function, one library


class Compiled(NamedTuple):  # a record nothing changes: no dataclass made at every start
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
