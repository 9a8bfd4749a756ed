"""Reading a file a user names (only a regular file, never more than a bound), and writing
a file atomically (a reader sees the whole file or none).

A scene, an OBJ model, a texture, a run file or a feature file is read whole. A named pipe
(FIFO) would block the reader until something writes to it, ``/dev/zero`` never ends, and a
folder or a device is no file at all: ``read_bytes`` opens without waiting (``O_NONBLOCK``),
looks at what it opened (``fstat``) and refuses anything but a regular file, then reads at
most ``limit`` bytes. Its refusals are ``OSError``s whose ``strerror`` is one line saying
what is wrong (``a named pipe (FIFO), not a regular file``; ``the file is 70 MB; files up to
64 MB are read``), so a caller's ``except OSError`` names the file and prints it as it prints
"No such file or directory".

``write_atomically`` writes to a temporary file in the same folder and renames it over the
target; ``write_new`` does the same but never replaces a file that exists (results, a
learner's files). Neither writes through a symbolic link nor over anything but a regular
file: a link (``out.png -> elsewhere.png``) is refused in one line (``OSError``) rather than
replaced by a file or followed out of where the command writes, and so is a named pipe. A
file written again keeps its permissions (a private 0600 picture stays private); a new one
gets 0666 less the umask, as ``open`` would give it.
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


def umask() -> int:
    """The process's umask, read without changing it where Linux shows it (``/proc``);
    elsewhere set and restored at once."""
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    old = os.umask(0o022)
    os.umask(old)
    return old


def writable_target(path: Path) -> int | None:
    """The permissions of the regular file at ``path`` (None: nothing there); an ``OSError``
    when ``path`` is a symbolic link or not a regular file (never written through or over)."""
    try:
        info = os.lstat(path)
    except (FileNotFoundError, NotADirectoryError):  # nothing there; its folder says why
        return None
    if stat.S_ISLNK(info.st_mode):
        why = "it is a symbolic link; name the file itself (links are not written through)"
        raise OSError(errno.ELOOP, why, str(path))
    problem = not_regular(info.st_mode)
    if problem is not None:
        raise OSError(problem.errno, problem.strerror, str(path))
    return stat.S_IMODE(info.st_mode)


def resolved(path: Path) -> Path:
    """``path`` made absolute with its links followed; an ``OSError`` (``ELOOP``) for a loop
    of symbolic links, which ``Path.resolve`` reports as a ``RuntimeError``."""
    try:
        return path.resolve()
    except RuntimeError:
        raise OSError(errno.ELOOP, "it is a loop of symbolic links", str(path)) from None


_NEW_FILE = (
    os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
)
_NAME_ATTEMPTS = 100  # random names tried before giving up (each taken: someone else's)


def new_file(folder: str | os.PathLike[str], prefix: str, suffix: str = "") -> tuple[int, str]:
    """A file made by this call alone in ``folder``, under a random name (``prefix``, 12 hex
    digits, ``suffix``), mode 0600, open for writing: its descriptor and absolute path.
    ``tempfile.mkstemp``'s contract, without importing tempfile (and its random and shutil)
    on every render's path."""
    for _ in range(_NAME_ATTEMPTS):
        name = os.path.abspath(os.path.join(folder, f"{prefix}{os.urandom(6).hex()}{suffix}"))
        try:
            return os.open(name, _NEW_FILE, 0o600), name
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, "no unused name for a temporary file", str(folder))


def check_can_write(folder: str | os.PathLike[str], prefix: str) -> None:
    """An ``OSError`` unless files can be made in ``folder`` (read-only, full, not ours):
    a file is made there and removed (without a name, where the system allows it)."""
    unnamed = getattr(os, "O_TMPFILE", 0)
    if unnamed:
        try:
            os.close(os.open(folder, unnamed | os.O_WRONLY | getattr(os, "O_CLOEXEC", 0), 0o600))
            return
        except OSError as error:  # a file system without unnamed files: a named one below
            if error.errno not in (errno.EISDIR, errno.EOPNOTSUPP, errno.EINVAL):
                raise
    fd, name = new_file(folder, prefix)
    os.close(fd)
    os.unlink(name)


def _temporary_beside(path: Path, data: bytes, mode: int, sync: bool) -> str:
    """A temporary file in ``path``'s folder holding ``data`` with permissions ``mode``."""
    fd, temporary = new_file(path.parent, f".{path.name}.", ".tmp")
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(data)
            if sync:
                out.flush()
                os.fsync(out.fileno())
        os.chmod(temporary, mode)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return temporary


def _data(data: bytes | str) -> bytes:
    return data.encode("utf-8") if isinstance(data, str) else data


def write_atomically(path: str | os.PathLike[str], data: bytes | str) -> Path:
    """Write ``data`` (text as UTF-8) to ``path`` through a temporary file in the same folder,
    renamed over it: a reader sees the old file or the new one, whole; returns the path.
    An existing file keeps its permissions; a link or a pipe there is an ``OSError``."""
    target = Path(path)
    mode = writable_target(target)
    if mode is None:
        mode = 0o666 & ~umask()
    temporary = _temporary_beside(target, _data(data), mode, sync=False)
    try:
        os.replace(temporary, target)
    finally:
        Path(temporary).unlink(missing_ok=True)
    return target


def write_new(path: str | os.PathLike[str], data: bytes | str, *, sync: bool = False) -> bool:
    """Write ``data`` to ``path`` atomically unless a file is there: True if written, False
    when ``path`` exists (or appears meanwhile; it is never replaced). ``sync``: on disk
    before it is named."""
    target = Path(path)
    if os.path.lexists(target):
        return False
    temporary = _temporary_beside(target, _data(data), 0o666 & ~umask(), sync)
    try:
        try:
            os.link(temporary, target)  # atomic, and never replaces a file
        except FileExistsError:
            return False
        except OSError:  # a file system without hard links: check, then rename
            if os.path.lexists(target):
                return False
            os.replace(temporary, target)
    finally:
        Path(temporary).unlink(missing_ok=True)
    return True


PROJECT = Path(__file__).resolve().parents[1]


def recorded_path(text: str) -> str:
    """How a run file names a file or folder: relative to the project when inside it (a run
    file is committed and read on other machines), else only its name after ``.../``: a
    run records no path of the machine it ran on. A relative path is kept as written."""
    path = Path(text)
    if not path.is_absolute():
        return path.as_posix()
    try:
        return path.resolve().relative_to(PROJECT).as_posix()
    except (ValueError, OSError, RuntimeError):
        return f".../{path.name}"
