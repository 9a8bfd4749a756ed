"""POV-Ray as a measuring stick: find it, render a ``.pov`` scene at a size with N threads,
time the whole process, read back its picture.

POV-Ray 3.7 (Debian's ``povray``) is a ray tracer in C++; the report puts it beside the project's
variants on the same machine, in the same run (``harness.sections.ladder.measure``). Nothing here
knows the scene: ``render`` takes the scene's text or its file and returns the picture and the
timings, so any section can set POV-Ray beside its own renders::

    found = povray.find()            # None: not installed (``povray.missing()`` says why)
    result = povray.render(found, scene_text, Size(640, 480), threads=2)
    result.image                     # float RGB, height x width x 3, in [0, 1]
    result.wall, result.cpu          # the whole process: start, parse, trace, write, exit
    result.parse, result.trace       # POV-Ray's own figures from its statistics

How it runs: in a fresh folder made for the render (POV-Ray's I/O restrictions let it write
only there), with ``File_Gamma=1.0`` (a PNG of the linear colours, as the book writes them:
``clamp(round(c * 255))``), no display, no anti-aliasing unless ``options`` say otherwise,
and ``+WT`` threads. A scene given as a file is read where it is (its ``#include`` files
beside it): the process's ``HOME`` is set to its folder, which POV-Ray's default I/O policy
lets it read. The executable is ``$RTC_POVRAY`` if set, else ``povray`` on the ``PATH``.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image

from groundwork.sizes import Size
from harness.instruments.usage import ProcessTimeout, wait_with_usage

ENVIRONMENT = "RTC_POVRAY"
EXECUTABLE = "povray"
NOT_INSTALLED = (
    "POV-Ray is not installed (no `povray` on the PATH; Debian and Ubuntu: "
    "`apt-get install povray`; or set RTC_POVRAY to its executable)"
)


class PovrayError(RuntimeError):
    """POV-Ray did not render: the message has its exit status and its last lines."""


@dataclass(frozen=True)
class Povray:
    """An executable that answered ``--version``: its path and its version line."""

    path: Path
    version: str


@dataclass(frozen=True)
class PovrayRender:
    """One POV-Ray process: its picture and what it took.

    image: float RGB (height, width, 3) in [0, 1], read from its 8-bit PNG; wall: seconds
    from start to exit; cpu: CPU seconds of the process (user + system); parse, trace:
    seconds POV-Ray's own statistics give for parsing the scene and tracing its rays, and
    trace_cpu the CPU seconds of its trace threads (None where it printed none); threads:
    the render threads asked for (``+WT``); peak: the process's peak resident set, bytes
    (the kernel's accounting of the child)."""

    image: np.ndarray
    size: Size
    threads: int
    wall: float
    cpu: float
    parse: float | None
    trace: float | None
    trace_cpu: float | None
    version: str
    peak: int = 0

    def as_dict(self) -> dict[str, object]:
        """The figures, for a run file (no picture)."""
        return {
            "size": [self.size.width, self.size.height],
            "threads": self.threads,
            "wall": self.wall,
            "cpu": self.cpu,
            "parse": self.parse,
            "trace": self.trace,
            "trace_cpu": self.trace_cpu,
            "version": self.version,
            "peak": self.peak,
        }


def find(executable: str | os.PathLike[str] | None = None) -> Povray | None:
    """POV-Ray, if it is there and runs: ``executable``, else ``$RTC_POVRAY``, else
    ``povray`` on the ``PATH``; None otherwise (``missing`` says why, in one line)."""
    name = executable or os.environ.get(ENVIRONMENT) or EXECUTABLE
    path = shutil.which(str(name))
    if path is None:
        return None
    version = _version(Path(path))
    return None if version is None else Povray(Path(path), version)


def missing(executable: str | os.PathLike[str] | None = None) -> str:
    """Why ``find`` found nothing, in one line."""
    if executable is not None:
        given = f"{executable}"
    elif os.environ.get(ENVIRONMENT):
        given = f"{ENVIRONMENT}={os.environ[ENVIRONMENT]}"
    else:
        return NOT_INSTALLED
    name = executable or os.environ[ENVIRONMENT]
    if shutil.which(str(name)) is None:
        return f"POV-Ray not found: {given} is not an executable"
    return f"POV-Ray at {given} does not answer --version"


def _version(path: Path) -> str | None:
    """The line of ``povray --version`` naming the version (``POV-Ray 3.7.0.10...``)."""
    try:
        done = subprocess.run(
            [str(path), "--version"], capture_output=True, text=True, timeout=30, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return None
    text = done.stdout + done.stderr
    found = re.search(r"^POV-Ray\s+\S+", text, re.MULTILINE)
    return found.group(0) if found else None


_SECONDS = r"\(\s*([0-9.]+) seconds\)"


def statistics(text: str) -> dict[str, float | None]:
    """POV-Ray's own ``Parse Time`` and ``Trace Time`` (seconds) from its statistics (the
    text it writes on stderr), and the CPU seconds its trace threads used
    (``trace_cpu``); None for one it did not print."""
    found: dict[str, float | None] = {}
    for key, label in (("parse", "Parse Time"), ("trace", "Trace Time")):
        match = re.search(rf"{label}:.*?{_SECONDS}\s*using \d+ thread\(s\) with ([0-9.]+)", text)
        if match is None:
            match = re.search(rf"{label}:.*?{_SECONDS}", text)
        found[key] = float(match.group(1)) if match else None
        if key == "trace":
            found["trace_cpu"] = float(match.group(2)) if match and match.lastindex == 2 else None
    return found


def command(
    povray: Povray, scene: Path, output: Path, size: Size, threads: int, options: Sequence[str]
) -> list[str]:
    """The command line of one render (see the module)."""
    return [
        str(povray.path),
        f"+I{scene}",
        f"+O{output}",
        "+FN",  # PNG
        f"+W{size.width}",
        f"+H{size.height}",
        f"+WT{threads}",
        "-D",  # no display
        "-A",  # no anti-aliasing: one ray per pixel, through its centre
        "-P",  # no pause at the end
        "File_Gamma=1.0",
        *options,
    ]


def render(
    povray: Povray,
    scene: str | Path,
    size: Size,
    threads: int = 1,
    options: Sequence[str] = (),
    timeout: float | None = None,
) -> PovrayRender:
    """Render ``scene`` (its text, or a ``Path`` to its file) at ``size`` with ``threads``
    render threads; ``options``: more POV-Ray options (``+A0.3``, ``Declare=N=1``), after
    ours. A ``PovrayError`` when it fails or runs over ``timeout`` seconds."""
    with tempfile.TemporaryDirectory(prefix="rtc-povray-") as work:
        folder = Path(work)
        env = dict(os.environ)
        if isinstance(scene, Path):
            source = scene.resolve()
            env["HOME"] = str(source.parent)  # read where it is, includes beside it
        else:
            source = folder / "scene.pov"
            source.write_text(scene, encoding="utf-8")
        output = folder / "image.png"
        args = command(povray, source, output, size, threads, options)
        log = folder / "povray.log"
        with log.open("w", encoding="utf-8") as err:
            started = time.perf_counter()
            process = subprocess.Popen(
                args, cwd=folder, env=env, stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL, stderr=err,
            )  # fmt: skip
            try:
                status, cpu, peak = wait_with_usage(process, timeout, started)
            except ProcessTimeout:
                raise PovrayError(f"POV-Ray ran over {timeout:g} s and was stopped") from None
            finally:
                if process.poll() is None:
                    process.kill()
                    process.wait()
            wall = time.perf_counter() - started
        text = log.read_text(encoding="utf-8", errors="replace")
        if status != 0 or not output.is_file():
            tail = " / ".join(line.strip() for line in text.splitlines()[-4:] if line.strip())
            raise PovrayError(f"POV-Ray exited with status {status}: {tail or 'no output'}")
        image = read_png(output)
    if image.shape[:2] != (size.height, size.width):
        raise PovrayError(f"POV-Ray wrote a {image.shape[1]}x{image.shape[0]} picture, not {size}")
    stats = statistics(text)
    return PovrayRender(
        image,
        size,
        threads,
        wall,
        cpu,
        stats["parse"],
        stats["trace"],
        stats["trace_cpu"],
        povray.version,
        peak,
    )


def read_png(path: Path) -> np.ndarray:
    """An 8-bit PNG as float RGB in [0, 1] (height, width, 3)."""
    with Image.open(path, formats=["PNG"]) as picture:
        rgb = np.asarray(picture.convert("RGB"), dtype=np.float64)
    return rgb / 255.0
