"""Compiles say what they compile and that it happens once (issue 18, item 3)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from compiled import library, notices
from compiled.linking import BuildError


def test_a_build_is_announced_before_and_after_and_a_loaded_library_is_not(
    tmp_path: Path,
) -> None:
    heard: list[tuple[str, float | None]] = []
    remove = notices.on_compile(lambda what, seconds: heard.append((what, seconds)))
    cache: dict[str, Any] = {}
    missing = tmp_path / "missing.so"

    def build() -> None:
        raise BuildError("no compiler here")

    try:
        found = library.load_once(
            cache, missing, build, lambda _: "library", lambda why: f"fallback: {why}", "a kernel"
        )
        again = library.load_once(
            cache, missing, build, lambda _: "library", lambda why: "other", "a kernel"
        )
    finally:
        remove()
    assert found == again == "fallback: no compiler here"
    assert [what for what, _ in heard] == ["a kernel", "a kernel"]  # once, not per call
    assert heard[0][1] is None and heard[1][1] is not None and heard[1][1] >= 0
    library.load_once({}, missing, build, str, str, "after removal")
    assert len(heard) == 2  # the listener was removed
