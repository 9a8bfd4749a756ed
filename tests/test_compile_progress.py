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


def test_a_library_path_is_hashed_once_per_process(monkeypatch: Any, tmp_path: Path) -> None:
    """A render asks for its library's path every frame: the digest of its build key (a
    few hundred kilobytes of source) is computed the first time only, and a different key
    gets its own."""
    from compiled import records

    monkeypatch.setenv("RTC_NUMBA_KERNELS", str(tmp_path / "kernels"))
    records.platform_key()  # (its own digests, once per process)
    hashed: list[int] = []
    real = records.sha256_hex

    def counting(data: bytes) -> str:
        hashed.append(len(data))
        return real(data)

    monkeypatch.setattr(records, "sha256_hex", counting)
    source = "x = 1\n" * 1000 + str(tmp_path)  # a key no other test has asked for
    first = records.library_path("tiny_", source, "entry")
    again = records.library_path("tiny_", source, "entry")
    other = records.library_path("tiny_", source + "# changed\n", "entry")
    assert first == again != other
    assert len(hashed) == 2
