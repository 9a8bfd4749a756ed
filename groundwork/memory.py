"""How much memory this process may still use, to refuse work that cannot fit before it starts.

A canvas of 16384x16384 pixels in the book's tracer is some 40 GB of ``Color`` values, and a
huge texture is as bad: without a check the process runs until Python raises ``MemoryError``
(or the kernel's out-of-memory killer ends it). ``available`` is the least of what bounds
this process: the machine's available memory and free swap (/proc/meminfo, else
``psutil``), this process's address-space limit (``ulimit -v``, less what it already
maps), and its control group's memory limit (less what the group already uses). ``check``
compares an estimate with it and raises ``NotEnoughMemory``, one line naming what was
asked, the estimate and what is left; ``render_bytes`` estimates what a render of a size
needs.
"""

from __future__ import annotations

import re
import resource
from pathlib import Path

from groundwork.files import size_text

_CGROUP_V2 = ("/sys/fs/cgroup", "memory.max", "memory.current")
_CGROUP_V1 = ("/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes")


class NotEnoughMemory(MemoryError):
    """Work refused before it starts: the message names it, its estimate and what is left."""


class Room:  # a plain class: a dataclass or NamedTuple would import most of rtc --help's time
    """``left`` bytes may still be allocated; ``bound`` says what limits it."""

    __slots__ = ("bound", "left")

    def __init__(self, left: int, bound: str) -> None:
        self.left = left
        self.bound = bound

    def text(self) -> str:
        return f"{size_text(self.left)} {self.bound}"


def _read_number(path: Path) -> int | None:
    try:
        text = path.read_text(encoding="ascii").strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _cgroup() -> Room | None:
    """What this process's control group still allows, if it sets a limit."""
    try:
        lines = Path("/proc/self/cgroup").read_text(encoding="utf-8").splitlines()
    except OSError:
        return None
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        number, controllers, group = parts
        if number == "0" and not controllers:
            root, limit_name, usage_name = _CGROUP_V2
        elif "memory" in controllers.split(","):
            root, limit_name, usage_name = _CGROUP_V1
        else:
            continue
        for folder in (Path(root) / group.lstrip("/"), Path(root)):  # as seen from inside
            limit = _read_number(folder / limit_name)
            usage = _read_number(folder / usage_name)
            if limit is not None and usage is not None and limit < 1 << 60:
                return Room(max(limit - usage, 0), "left under the control group's limit")
    return None


def _meminfo() -> tuple[int, int] | None:
    """The machine's available memory and free swap in bytes, from Linux's /proc/meminfo
    (what psutil reads there, without importing it); None elsewhere."""
    try:
        text = Path("/proc/meminfo").read_text(encoding="ascii")
    except (OSError, ValueError):
        return None
    fields = dict(re.findall(r"^(MemAvailable|SwapFree):\s+(\d+) kB$", text, re.MULTILINE))
    if len(fields) != 2:  # a kernel older than 3.14 has no MemAvailable: psutil estimates
        return None
    return int(fields["MemAvailable"]) * 1024, int(fields["SwapFree"]) * 1024


def _mapped() -> int:
    """The bytes this process maps (its virtual size), from /proc/self/statm, else psutil."""
    try:
        pages = int(Path("/proc/self/statm").read_text(encoding="ascii").split()[0])
    except (OSError, ValueError, IndexError):
        import psutil  # deferred: only where /proc is not (see _machine)

        return int(psutil.Process().memory_info().vms)
    return pages * resource.getpagesize()


def _machine() -> Room:
    """The machine's available memory and free swap: read from /proc on Linux, through
    ``psutil`` elsewhere (imported only there: it costs ~10 ms of every render's start)."""
    found = _meminfo()
    if found is None:
        import psutil

        found = psutil.virtual_memory().available, psutil.swap_memory().free
    return Room(found[0] + found[1], "available on this machine")


def available() -> Room:
    """The least of what bounds this process's memory (see the module)."""
    rooms = [_machine()]
    for which, name in ((resource.RLIMIT_AS, "address-space"), (resource.RLIMIT_DATA, "data")):
        soft, _hard = resource.getrlimit(which)
        if soft != resource.RLIM_INFINITY:
            used = _mapped() if which == resource.RLIMIT_AS else 0
            rooms.append(
                Room(max(soft - used, 0),
                     f"left under this process's {name} limit of {size_text(soft)}")
            )  # fmt: skip
    group = _cgroup()
    if group is not None:
        rooms.append(group)
    return min(rooms, key=lambda room: room.left)


def check(needed: float, what: str) -> None:
    """A ``NotEnoughMemory`` naming ``what`` (``a 16384x16384 canvas for naive``) unless
    about ``needed`` bytes fit in what is ``available``."""
    room = available()
    if needed > room.left:
        raise NotEnoughMemory(f"{what} needs about {size_text(needed)} of memory; {room.text()}")


# What one pixel of a render costs at the peak (the canvas, and the image written from it),
# measured: a canvas of ``Color`` values (the book's tracer and the variants built on it,
# a learner's) about 140 bytes a pixel once every pixel holds its own color; numba's arrays
# about 60; wavefront's passes about 175. Rounded up.
BYTES_PER_PIXEL = {"numba": 80, "wavefront": 200}
DEFAULT_BYTES_PER_PIXEL = 160


def render_bytes(variant: str, width: int, height: int) -> int:
    """About how much memory a ``width`` x ``height`` render with ``variant`` (a registry
    name, wrappers included: the costliest part counts) needs."""
    names = re.findall(r"[A-Za-z_][A-Za-z0-9_]*(?=\[|:|$)", variant) or [variant]
    per_pixel = max(BYTES_PER_PIXEL.get(name, DEFAULT_BYTES_PER_PIXEL) for name in names)
    return per_pixel * width * height
