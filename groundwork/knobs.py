"""The environment variables the project passes on to numba, checked before any command
runs: numba reads them when it is first imported and, for a value it cannot use, prints a
traceback of its own (``NUMBA_NUM_THREADS=0``: deep in a compile) or a warning with one in
it (a value that is no number). ``problems`` names each unusable one in a line.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

# name -> (lowest, highest or None, what it means): whole numbers numba reads with int()
WHOLE_NUMBERS = {
    "NUMBA_NUM_THREADS": (1, None, "the threads numba's kernels use; unset it to use every CPU"),
    "NUMBA_DISABLE_JIT": (0, 1, "1 runs numba's functions as plain Python, 0 compiles them"),
}


def problems(environ: Mapping[str, str] | None = None) -> list[str]:
    """One line for each variable of ``WHOLE_NUMBERS`` set to a value numba cannot use."""
    environ = os.environ if environ is None else environ
    found = []
    for name, (low, high, meaning) in WHOLE_NUMBERS.items():
        text = environ.get(name)
        if text is None or text.strip() == "":
            continue
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < low or (high is not None and value > high):
            wanted = f"{low} or {high}" if high == low + 1 else f"a whole number from {low}"
            found.append(f"{name}={text!r}: expected {wanted} ({meaning})")
    return found
