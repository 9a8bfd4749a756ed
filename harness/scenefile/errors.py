"""The one error a broken scene file raises: ``file:line: what is wrong, what was expected``."""

from __future__ import annotations

from pathlib import Path


class SceneError(ValueError):
    """A mistake in a scene file (or in an OBJ file it names).

    path: the scene file; line: 1-based, or None when no single line is to blame (a missing
    camera, an unreadable file); message: what is wrong and what was expected.
    """

    def __init__(self, path: str | Path, line: int | None, message: str) -> None:
        self.path = str(path)
        self.line = line
        self.message = message
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {message}")
