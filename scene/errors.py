"""The one error a broken scene file raises: ``file:line: what is wrong, what was expected``."""

from __future__ import annotations

from pathlib import Path

# every character str.splitlines breaks at, written as an escape: a name read from the file
# (a multi-line YAML scalar) must not break the one-line message
_LINE_BREAKS = {ord(c): repr(c)[1:-1] for c in "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"}


class SceneError(ValueError):
    """A mistake in a scene file (or in an OBJ file it names).

    path: the scene file; line: 1-based, or None when no single line is to blame (a missing
    camera, an unreadable file); message: what is wrong and what was expected.
    """

    def __init__(self, path: str | Path, line: int | None, message: str) -> None:
        self.path = str(path)
        self.line = line
        self.message = message.translate(_LINE_BREAKS)  # one line, whatever the file holds
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {self.message}")
