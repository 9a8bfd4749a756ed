"""The kernel folder: where compiled libraries and numba's own disk cache are kept, a private
folder of this user's, since what is in it runs (see ``compiled.library`` for the rules)."""

from __future__ import annotations

import atexit
import contextlib
import os
import stat
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from compiled import KernelFolderError, compile_log
from compiled.notices import say
from groundwork.files import check_can_write

_lock = threading.Lock()

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
            compile_log.folder_in_use = str(known)
            return known
        folder = _choose_folder()
        _folders[memo] = folder
        compile_log.folder_in_use = str(folder)
        return folder


def _xdg(name: str) -> str | None:
    """An XDG base folder from the environment; None when unset or relative (the XDG rules
    say a relative path is invalid and is to be ignored)."""
    value = os.environ.get(name)
    return value if value and os.path.isabs(value) else None


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
    reasons = []
    for folder in _candidates():
        why = _private(folder, tighten=True)
        if not why:
            return folder
        reasons.append(f"{folder}: {why}")
    import shutil  # deferred, as in remove
    import tempfile

    fresh = Path(tempfile.mkdtemp(prefix="rtc-numba-kernels-"))  # 0700, a new random name
    atexit.register(shutil.rmtree, fresh, ignore_errors=True)
    os.environ["RTC_NUMBA_KERNELS"] = str(fresh)  # this process's workers share it
    say(
        f"no private folder for compiled code ({'; '.join(reasons)}): using {fresh} for this "
        "process alone, so its code is compiled again next time"
    )
    return fresh


def _candidates() -> Iterator[Path]:
    """The folders tried in turn for the kernels: the user's cache, the runtime folder, the
    system's temporary folder (tempfile, with random and shutil, imported only then)."""
    cache_home = _xdg("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    yield Path(cache_home) / "rtc-workbook" / "numba-kernels"
    runtime = _xdg("XDG_RUNTIME_DIR")
    if runtime:
        yield Path(runtime) / "rtc-numba-kernels"
    import tempfile

    yield Path(tempfile.gettempdir()) / f"rtc-numba-kernels-{os.geteuid()}"


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
        check_can_write(folder, ".rtc-write-check-")
    except OSError as error:
        return f"cannot write in it ({error.strerror or error})"
    return ""


def _empty(folder: Path) -> None:
    """Remove what this project keeps in ``folder`` (``OURS``), whatever it has become."""
    for pattern in OURS:
        for path in folder.glob(pattern):
            remove(path)


def remove(path: Path) -> None:
    """Remove ``path``, a file, a link or a folder (what was found where a file belongs)."""
    import shutil  # deferred: ~10 ms of every render's imports, for an error's clean-up

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
    # deferred: saves ~760 ms (numba) of every process that loads a built library
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
