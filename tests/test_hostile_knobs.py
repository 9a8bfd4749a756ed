"""Hostile input, fourth round (issue 37): what gave a traceback is one line.

- numba's environment variables the project passes on, set to values numba cannot use
  (``NUMBA_NUM_THREADS=0``, negative, garbage; ``NUMBA_DISABLE_JIT`` not 0 or 1), for every
  command, before numba reads them (``groundwork.knobs``);
- a light too far for floating point (its shadow rays' lengths overflow), an OBJ or texture
  path that is a loop of symbolic links, a plain PPM whose header claims 10^12 pixels;
- a wrong message set right: a run file of a future schema names its version.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from test_hostile import VARIANTS, one_line, scene, texture_scene

from groundwork import knobs


@pytest.mark.parametrize(("name", "value"), [
    ("NUMBA_NUM_THREADS", "0"), ("NUMBA_NUM_THREADS", "-3"), ("NUMBA_NUM_THREADS", "many"),
    ("NUMBA_DISABLE_JIT", "2"), ("NUMBA_DISABLE_JIT", "yes"),
])  # fmt: skip
@pytest.mark.parametrize("command", [["variants"], ["render", "{scene}", "--variant", "numba"]])
def test_a_numba_setting_it_cannot_use_is_one_line_for_every_command(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    name: str, value: str, command: list[str],
) -> None:  # fmt: skip
    monkeypatch.setenv(name, value)
    path = scene(tmp_path, "- add: sphere\n")
    argv = [str(path) if part == "{scene}" else part for part in command]
    line = one_line(capsys, *argv, "-o", str(tmp_path / "o.png")) if "render" in argv else (
        one_line(capsys, *argv)
    )
    assert line.startswith(f"rtc {argv[0]}: {name}={value!r}: expected"), line
    assert not (tmp_path / "o.png").exists()


@pytest.mark.parametrize(("name", "value"), [
    ("NUMBA_NUM_THREADS", "1"), ("NUMBA_NUM_THREADS", "64"), ("NUMBA_DISABLE_JIT", "0"),
    ("NUMBA_DISABLE_JIT", "1"), ("NUMBA_NUM_THREADS", ""),
])  # fmt: skip
def test_a_usable_numba_setting_is_passed_on(name: str, value: str) -> None:
    assert knobs.problems({name: value}) == []


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_light_too_far_for_floating_point_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    path = scene(tmp_path, "- add: sphere\n")
    path.write_text(path.read_text().replace("[-10, 10, -10]", "[1e300, 1e300, -1e300]"))
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o",
                    str(tmp_path / "o.png"))  # fmt: skip
    assert "the light's at is too far for floating point" in line and ":9:" in line, line


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("what", ["obj", "texture"])
def test_a_path_that_is_a_loop_of_links_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str, what: str
) -> None:
    name = "loop.obj" if what == "obj" else "loop.png"
    (tmp_path / name).symlink_to(tmp_path / f"other-{name}")
    (tmp_path / f"other-{name}").symlink_to(tmp_path / name)
    if what == "obj":
        path = scene(tmp_path, f"- add: obj\n  file: {name}\n")
    else:
        path = texture_scene(tmp_path, name)
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o",
                    str(tmp_path / "o.png"))  # fmt: skip
    assert f"{name}: it is a loop of symbolic links" in line, line


@pytest.mark.parametrize("variant", VARIANTS)
def test_a_plain_ppm_claiming_a_huge_size_is_refused_by_its_header(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str
) -> None:
    (tmp_path / "big.ppm").write_bytes(b"P3\n# made up\n1000000 1000000\n255\n0 0 0\n")
    path = texture_scene(tmp_path, "big.ppm")
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o",
                    str(tmp_path / "o.png"))  # fmt: skip
    assert "is 1000000x1000000 = 1,000,000,000,000 pixels; textures up to" in line, line
