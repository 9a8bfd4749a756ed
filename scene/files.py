"""Reading a file a user names: only a regular file, and never more than a bound.

A scene, an OBJ model, a texture, a run file or a feature file is read whole. A named pipe
(FIFO) would block the reader until something writes to it, ``/dev/zero`` never ends, and a
folder or a device is no file at all: ``read_bytes`` opens without waiting (``O_NONBLOCK``),
looks at what it opened (``fstat``) and refuses anything but a regular file, then reads at
most ``limit`` bytes. Its refusals are ``OSError``s whose ``strerror`` is one line saying
what is wrong (``a named pipe (FIFO), not a regular file``; ``the file is 70 MB; files up to
64 MB are read``), so a caller's ``except OSError`` names the file and prints it as it prints
"No such file or directory".
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

_KINDS = (
    (stat.S_ISDIR, "a folder", errno.EISDIR),
    (stat.S_ISFIFO, "a named pipe (FIFO)", errno.EINVAL),
    (stat.S_ISCHR, "a character device", errno.EINVAL),
    (stat.S_ISBLK, "a block device", errno.EINVAL),
    (stat.S_ISSOCK, "a socket", errno.EINVAL),
)


def size_text(size: float) -> str:
    """A number of bytes for a message: ``70 MB``, ``1.5 GB``, ``812 bytes`` (binary units)."""
    for unit, scale in (("TB", 1 << 40), ("GB", 1 << 30), ("MB", 1 << 20), ("kB", 1 << 10)):
        if size >= scale:
            value = size / scale
            return f"{value:.3g} {unit}" if value < 100 else f"{value:.0f} {unit}"
    return f"{size:.0f} bytes"


def not_regular(mode: int) -> OSError | None:
    """Why a file of ``mode`` (``st_mode``) is no file to read, as an ``OSError``; None for
    a regular file."""
    if stat.S_ISREG(mode):
        return None
    for test, kind, number in _KINDS:
        if test(mode):
            return OSError(number, f"it is {kind}, not a regular file")
    return OSError(errno.EINVAL, "it is not a regular file")


def check_regular(path: str | os.PathLike[str]) -> None:
    """An ``OSError`` unless ``path`` is a regular file (links followed); for a file that
    another library opens itself."""
    problem = not_regular(os.stat(path).st_mode)
    if problem is not None:
        raise problem


def read_bytes(path: str | os.PathLike[str], limit: int) -> bytes:
    """The whole of the regular file ``path``, at most ``limit`` bytes; an ``OSError`` (see
    the module) for anything else, never a wait."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        info = os.fstat(fd)
        problem = not_regular(info.st_mode) or (
            _too_big(info.st_size, limit) if info.st_size > limit else None
        )
    except BaseException:
        os.close(fd)
        raise
    if problem is not None:
        os.close(fd)
        raise problem
    with open(fd, "rb", buffering=0, closefd=True) as file:  # a read allocates what it returns
        parts: list[bytes] = []
        total = 0
        step = info.st_size + 1  # the whole file at once, and a byte more to see its end
        while total <= limit:  # a file that grows, or one of /proc (its size says 0)
            chunk = file.read(step)
            if not chunk:
                break
            parts.append(chunk)
            total += len(chunk)
            step = min(1 << 20, limit + 1 - total)
    if total > limit:
        raise OSError(errno.EFBIG, f"the file holds more than {size_text(limit)}, the most read")
    return parts[0] if len(parts) == 1 else b"".join(parts)


def read_text(path: str | os.PathLike[str], limit: int, encoding: str = "utf-8") -> str:
    """``read_bytes`` decoded (a ``UnicodeDecodeError`` for text that is not ``encoding``)."""
    return read_bytes(path, limit).decode(encoding)


def _too_big(size: int, limit: int) -> OSError:
    return OSError(
        errno.EFBIG, f"the file is {size_text(size)}; files up to {size_text(limit)} are read"
    )


def describe(path: Path) -> str | None:
    """What ``path`` is when it is not a regular file (``a named pipe (FIFO)``), None for a
    regular file or a path that does not exist."""
    try:
        mode = path.stat().st_mode
    except OSError:
        return None
    problem = not_regular(mode)
    return None if problem is None else problem.strerror
