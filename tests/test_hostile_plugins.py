"""Hostile input, fourth round (issue 37): a learner's plug-in cannot take a command down.

A variant package installed beside the project's (an ``rtc.variants`` entry point) whose
import hangs, raises, exits (``SystemExit`` of any status, ``os._exit``) or interrupts is
one line naming its package, for ``rtc render --variant`` (exit 2) and ``rtc variants``
(listed as unavailable), while the project's own variants still list and render.
"""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from test_hostile import one_line, scene

from raytracer.canvas import Canvas, canvas
from raytracer.colors import Color
from rtc.cli import main
from variants import registry
from variants.naive import variant as naive_variant
from variants.registry import Variant

PACKAGE = "hostile_plugin_pkg"
GOOD = """
from variants.naive import variant as _naive


def variant():
    return _naive()
"""
IMPORTS = {
    "sleeps": ("import time\ntime.sleep(3600)\n", "took more than 2 s"),
    "raises": ("raise RuntimeError('boom at import')\n", "raised RuntimeError: boom at import"),
    "exits 0": ("raise SystemExit(0)\n", "raised SystemExit: 0"),
    "exits 3": ("import sys\nsys.exit(3)\n", "raised SystemExit: 3"),
    "os._exit": ("import os\nos._exit(0)\n", "ended the process (status 0)"),
    "interrupts": ("raise KeyboardInterrupt\n", "raised KeyboardInterrupt"),
    "escapes": ("raise ValueError('\\x1b]0;owned\\x07')\n", "ValueError: \\x1b]0;owned\\x07"),
}


def install(site: Path, body: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A package ``PACKAGE`` with ``body`` at import, registered as the variant ``hostile``
    (its metadata as ``pip install`` leaves it), on this process's path."""
    package = site / PACKAGE
    package.mkdir(parents=True)
    (package / "__init__.py").write_text(body + GOOD, encoding="utf-8")
    dist = site / f"{PACKAGE}-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {PACKAGE}\nVersion: 1.0\n", encoding="utf-8"
    )
    (dist / "entry_points.txt").write_text(
        f"[{registry.GROUP}]\nhostile = {PACKAGE}:variant\n", encoding="utf-8"
    )
    monkeypatch.syspath_prepend(str(site))
    # the bound a sleeping import reaches for certain; every other has all the time it needs
    monkeypatch.setattr(registry, "IMPORT_SECONDS", 2 if "sleep" in body else 600)
    importlib.invalidate_caches()


@pytest.fixture
def forget_package() -> object:
    yield None
    sys.modules.pop(PACKAGE, None)


@pytest.mark.parametrize("case", sorted(IMPORTS))
def test_a_plugin_whose_import_fails_is_one_line_naming_its_package(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    case: str, forget_package: object,
) -> None:  # fmt: skip
    body, words = IMPORTS[case]
    install(tmp_path / "site", body, monkeypatch)
    path = scene(tmp_path, "- add: sphere\n")
    line = one_line(capsys, "render", str(path), "--variant", "hostile", "-o",
                    str(tmp_path / "out.png"))  # fmt: skip
    assert f"importing its package {PACKAGE!r}" in line and words in line, line
    assert "\x1b" not in line
    assert not (tmp_path / "out.png").exists()
    assert main(["variants"]) == 0
    out = capsys.readouterr().out
    listed = [text for text in out.splitlines() if text.startswith("hostile ")]
    assert len(listed) == 1 and "unavailable" in listed[0] and PACKAGE in listed[0]
    assert any(text.startswith("naive ") and "available" in text for text in out.splitlines())
    assert main(["render", str(path), "--variant", "naive", "-o", str(tmp_path / "n.png")]) == 0
    capsys.readouterr()
    assert (tmp_path / "n.png").is_file()


def test_a_plugin_that_imports_cleanly_renders(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    forget_package: object,
) -> None:  # fmt: skip
    install(tmp_path / "site", "", monkeypatch)
    path = scene(tmp_path, "- add: sphere\n")
    assert main(["render", str(path), "--variant", "hostile", "-o",
                 str(tmp_path / "out.png")]) == 0  # fmt: skip
    capsys.readouterr()
    assert (tmp_path / "out.png").is_file()


# ------------------------------------------------------------ a learner's render, checked


def _nan_canvas(camera: Any) -> Any:
    return Canvas(camera.hsize, camera.vsize, [Color(math.nan, 0, 0)] * 192)


def _recursing(camera: Any) -> Any:
    return _recursing(camera)


RENDERS = {
    "nan": (_nan_canvas, "returned 192 pixels that are not finite numbers (NaN or infinite), "
                         "the first at x=0, y=0"),
    "infinite": (lambda c: Canvas(c.hsize, c.vsize, [Color(0, math.inf, 0)] * 192),
                 "returned 192 pixels that are not finite numbers"),
    "3x2": (lambda c: canvas(3, 2), "returned a 3x2 canvas for a 16x12 camera"),
    "none": (lambda c: None, "returned NoneType, not a canvas"),
    "recursion": (_recursing, "recursed past Python's limit"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(RENDERS))
def test_a_learners_render_that_returns_no_picture_is_one_line_naming_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    case: str,
) -> None:  # fmt: skip
    make, words = RENDERS[case]

    def render(camera: Any, world: Any, *rest: Any) -> Any:
        return make(camera)

    learner = Variant("learners", "a learner's own", {**naive_variant().api, "render": render})
    real = registry._entry_points()
    fake = SimpleNamespace(
        name="learners", value="learners_pkg:variant", load=lambda: lambda: learner
    )
    monkeypatch.setattr(registry, "_entry_points", lambda: {**real, "learners": fake})
    path = scene(tmp_path, "- add: sphere\n").read_text(encoding="utf-8")
    sized = tmp_path / "sized.yml"
    sized.write_text(path.replace("width: 8", "width: 16").replace("height: 6", "height: 12"))
    out = tmp_path / "out.png"
    line = one_line(capsys, "render", str(sized), "--variant", "learners", "-o", str(out))
    assert line.startswith("rtc render: learners") and words in line, line
    assert not out.exists()
