"""Hostile input, fourth round (issue 37): nothing runs that a file smuggles in, and nothing
quoted from a file reaches the terminal raw.

- a texture named ``.png`` that holds another format Pillow knows (EPS, which it hands to
  Ghostscript; GIF, BMP) is refused as no PNG or PPM: the scene format documents only those;
- a control character in a scene's names, an unknown key, an OBJ path or a feature file is
  shown escaped in the one error line (``groundwork.escapes.printable``).
"""

from __future__ import annotations

import io
import os
import stat
from pathlib import Path

import pytest
from PIL import Image
from test_hostile import VARIANTS, obj_scene, one_line, rtc, scene, texture_scene

from groundwork.escapes import printable
from rtc.cli import main

EPS = (
    b"%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 4 4\n%%EndComments\n"
    b"(smuggled) print quit\n%%EOF\n"
)


def _other_format(kind: str) -> bytes:
    if kind == "eps":
        return EPS
    buffer = io.BytesIO()
    Image.new("RGB", (4, 4), (255, 0, 0)).save(buffer, format=kind.upper())
    return buffer.getvalue()


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("kind", ["eps", "gif", "bmp"])
def test_a_texture_of_another_format_named_png_is_never_decoded(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    variant: str, kind: str,
) -> None:  # fmt: skip
    import subprocess

    def no_program(*args: object, **kwargs: object) -> None:
        raise AssertionError(f"a program was started: {args}")

    monkeypatch.setattr(subprocess, "Popen", no_program)  # Pillow starts Ghostscript so
    (tmp_path / "t.png").write_bytes(_other_format(kind))
    path = texture_scene(tmp_path, "t.png")
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o",
                    str(tmp_path / "out.png"))  # fmt: skip
    assert "t.png is not a PNG or PPM image" in line, line
    assert not (tmp_path / "out.png").exists()


ESCAPES = ["\x1b[2J", "\x1b]0;owned\x07", "a\rb", "\u202egnp.exe", "\x9b31m"]


@pytest.mark.parametrize("text", ESCAPES, ids=[printable(t) for t in ESCAPES])
def test_printable_escapes_every_control_and_keeps_the_rest(text: str) -> None:
    shown = printable(text)
    assert shown.isprintable() and "\\" in shown
    assert printable("plain ünïcode → text") == "plain ünïcode → text"


@pytest.mark.parametrize("where", ["add", "key", "obj", "material"])
def test_a_control_character_in_a_scene_is_shown_escaped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], where: str
) -> None:
    evil = "x\x1b]0;owned\x07\x1b[2Jy"
    quoted = '"x\\e]0;owned\\a\\e[2Jy"'  # YAML's own escapes in a double-quoted string
    bodies = {
        "add": f"- add: {quoted}\n",
        "key": f"- add: sphere\n  {quoted}: 1\n",
        "material": f"- add: sphere\n  material: {quoted}\n",
    }
    path = obj_scene(tmp_path, quoted) if where == "obj" else scene(tmp_path, bodies[where])
    line = one_line(capsys, "render", str(path), "--variant", "naive", "-o",
                    str(tmp_path / "out.png"))  # fmt: skip
    assert "\x1b" not in line and "\x07" not in line, repr(line)
    assert printable(evil) in line or "\\x1b" in line, line


def test_a_control_character_in_a_feature_file_is_shown_escaped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    feature = tmp_path / "evil.feature"
    feature.write_bytes(
        b"Feature: \x1b[2Jf\n  Scenario: s\x1b]0;owned\x07\n    Given \x1b[2J is odd\n"
    )
    assert main(["kata", str(feature), "--progress", "none"]) == 1
    out, err = capsys.readouterr()
    shown = out + err
    assert "\x1b" not in shown and "\x07" not in shown, repr(shown)
    assert "s\\x1b]0;owned\\x07" in out


# ------------------------------------------------------------------------------- no hang


def test_rtc_kata_on_folders_nested_deep_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    deep = tmp_path / "deep"
    here = deep
    for _ in range(70):  # past the bound; 1,100 deep exhausted Python's stack before
        here = here / "d"
    here.mkdir(parents=True)
    (here / "x.feature").write_text("Feature: f\n", encoding="utf-8")
    line = one_line(capsys, "kata", str(deep))
    assert line == (
        f"rtc kata: {deep}: folders nested more than 64 deep under it; name the folder of "
        "the feature files itself"
    )


def test_rtc_kata_refuses_a_step_line_of_128k_characters(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    feature = tmp_path / "long.feature"
    feature.write_text("Feature: f\n  Scenario: s\n    Given " + "1" * 128_000 + "\n")
    line = one_line(capsys, "kata", str(feature))
    assert line == (
        f"rtc kata: {feature}:3: the line is 128,010 characters long; feature file lines up "
        "to 4,096 are read"
    )


@pytest.mark.parametrize("name", ["pyproject.toml", "hostile_pipe_case/tracer.py"])
def test_rtc_new_where_a_file_is_a_named_pipe_does_not_wait_on_it(
    tmp_path: Path, name: str
) -> None:
    """A real process: reading the pipe would block. A pipe as pyproject.toml registers
    nothing (one line); as the tracer it is left alone, the rest is written."""
    folder = tmp_path / "mine"
    (folder / name).parent.mkdir(parents=True)
    os.mkfifo(folder / name)
    done = rtc("new", "hostile_pipe_case", "--dir", str(folder))
    assert "Traceback" not in done.stderr
    if name == "pyproject.toml":
        assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    else:
        assert done.returncode == 0 and "left alone: hostile_pipe_case/tracer.py" in done.stdout
    assert stat.S_ISFIFO((folder / name).lstat().st_mode)
