"""Make "it is still rendering" certain: the ``held`` variant (``tests/held_variant.py``)
installed for the processes a test starts, and the test's hand on it.

``Hold(folder)`` writes, under ``folder``, a site folder with the module and its metadata
(an entry point in ``rtc.variants``, as ``pip install`` leaves one) and a hold folder;
``hold.env`` is the environment that sees both. A process started with it renders
``--variant held`` (or ``pooled:held``, a bench of ``held`` ...) up to its first region and
waits there: ``hold.reached()`` waits until as many processes as asked have got there, and
``hold.release()`` lets them all go on. Nothing depends on how fast the machine is: a render
that is held cannot finish before the test does what it means to do during it.
"""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

from held_variant import HOLD_VARIABLE, REACHED_PREFIX, RELEASE

MODULE = Path(__file__).with_name("held_variant.py")
DIST = "rtc_test_held-0.dist-info"
# A hang guard only, never a speed limit: what a test waits for takes seconds on a quiet
# machine, but a cold numba compile on a machine with ten processes a core has taken minutes.
# Every test's subprocess waits at most this long (pytest-timeout's per-test guard, an hour,
# is the last resort).
HANG_SECONDS = 1800.0


class Hold:
    def __init__(self, folder: Path) -> None:
        self.site = folder / "site"
        self.folder = folder / "hold"
        dist = self.site / DIST
        dist.mkdir(parents=True)
        self.folder.mkdir()
        shutil.copy(MODULE, self.site / MODULE.name)
        (dist / "METADATA").write_text(
            "Metadata-Version: 2.1\nName: rtc-test-held\nVersion: 0\n", encoding="utf-8"
        )
        (dist / "entry_points.txt").write_text(
            f"[rtc.variants]\nheld = {MODULE.stem}:variant\n", encoding="utf-8"
        )
        paths = [str(self.site), os.environ.get("PYTHONPATH", "")]
        self.env = {
            **os.environ,
            "PYTHONPATH": os.pathsep.join(p for p in paths if p),
            HOLD_VARIABLE: str(self.folder),
        }

    def reached(self, count: int = 1, seconds: float = HANG_SECONDS) -> list[int]:
        """The pids of the processes held so far, once there are ``count`` of them."""
        deadline = time.monotonic() + seconds
        while True:
            pids = sorted(
                int(path.name[len(REACHED_PREFIX) :])
                for path in self.folder.glob(f"{REACHED_PREFIX}*")
            )
            if len(pids) >= count:
                return pids
            if time.monotonic() > deadline:
                raise AssertionError(
                    f"hang guard: {len(pids)} of {count} processes reached the hold in "
                    f"{seconds:g} s"
                )
            time.sleep(0.02)

    def release(self) -> None:
        (self.folder / RELEASE).touch()
