"""``harness.instruments.povray``: finding POV-Ray, one render as a whole process (its picture, its
timings, its own statistics), a clean 'not installed', and the reference scene's ``.pov``
version against the project's picture when POV-Ray is installed."""

from __future__ import annotations

import math
import stat
import sys
from pathlib import Path

import numpy as np
import pytest

from groundwork.sizes import Size
from harness.instruments import povray
from harness.instruments.imagediff import image_error

STATISTICS = """\
Parser Time
  Parse Time:       0 hours  0 minutes  0 seconds (0.012 seconds)
              using 1 thread(s) with 0.011 CPU-seconds total
Render Time:
  Photon Time:      No photons
  Radiosity Time:   No radiosity
  Trace Time:       0 hours  0 minutes  1 seconds (1.250 seconds)
              using 2 thread(s) with 2.400 CPU-seconds total
POV-Ray finished
"""

FAKE = f"""#!{sys.executable}
# A stand-in for povray: answers --version; renders a flat picture whose colour says
# whether HOME was the scene's folder (red) or not (blue); 'fail' in the scene fails.
import os, sys
from pathlib import Path
from PIL import Image
args = sys.argv[1:]
if args == ["--version"]:
    print("POV-Ray 3.7.0.fake\\n\\nThis is a fake", file=sys.stderr)
    sys.exit(0)
opts = {{a[1:3] if a.startswith("+WT") else a[1]: a[3:] if a.startswith("+WT") else a[2:]
        for a in args if a.startswith("+")}}
assert opts["WT"].isdigit()
scene = Path(opts["I"])
if "fail" in scene.read_text():
    print("Parse Error: fail found\\nFatal error in parser: Cannot parse input.", file=sys.stderr)
    sys.exit(1)
home = Path(os.environ.get("HOME", "")).resolve() == scene.parent.resolve()
colour = (255, 0, 0) if home else (0, 0, 255)
Image.new("RGB", (int(opts["W"]), int(opts["H"])), colour).save(Path.cwd() / opts["O"])
sys.stderr.write({STATISTICS!r})
"""


@pytest.fixture
def fake(tmp_path: Path) -> povray.Povray:
    path = tmp_path / "bin" / "povray"
    path.parent.mkdir()
    path.write_text(FAKE)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    found = povray.find(path)
    assert found is not None
    return found


def test_its_own_statistics_are_read_from_what_it_prints():
    found = povray.statistics(STATISTICS)
    assert found == {"parse": 0.012, "trace": 1.25, "trace_cpu": 2.4}
    assert povray.statistics("nothing") == {"parse": None, "trace": None, "trace_cpu": None}


def test_a_render_returns_the_picture_and_the_timings_of_the_whole_process(fake):
    assert fake.version == "POV-Ray 3.7.0.fake"
    done = povray.render(fake, "// a scene given as text\n", Size(8, 6), threads=2)
    assert done.image.shape == (6, 8, 3)
    assert np.allclose(done.image[0, 0], [0, 0, 1])  # text: HOME left alone
    assert done.trace == 1.25 and done.parse == 0.012 and done.trace_cpu == 2.4
    assert done.wall > 0 and done.cpu >= 0 and done.threads == 2
    assert done.as_dict()["size"] == [8, 6]


def test_a_scene_file_is_read_where_it_is(fake, tmp_path):
    scene = tmp_path / "scenes" / "mine.pov"
    scene.parent.mkdir()
    scene.write_text("// beside its includes\n")
    done = povray.render(fake, scene, Size(4, 3))
    assert np.allclose(done.image[0, 0], [1, 0, 0])  # HOME was the scene's folder
    assert not list(scene.parent.glob("*.png"))  # the picture went to a folder of its own


def test_a_failed_render_says_why_in_one_line(fake):
    with pytest.raises(povray.PovrayError, match=r"status 1: .*Cannot parse input"):
        povray.render(fake, "fail\n", Size(4, 3))


def test_not_installed_is_said_cleanly(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.delenv(povray.ENVIRONMENT, raising=False)
    assert povray.find() is None
    assert "not installed" in povray.missing()
    monkeypatch.setenv(povray.ENVIRONMENT, str(tmp_path / "nowhere"))
    assert povray.find() is None
    assert povray.missing().startswith("POV-Ray not found: RTC_POVRAY=")


REAL = povray.find()
SCENES = Path(__file__).resolve().parent.parent / "scenes"


@pytest.mark.skipif(REAL is None, reason=povray.NOT_INSTALLED)
def test_the_pov_version_of_the_reference_scene_draws_the_projects_picture():
    """POV-Ray's picture of ``reference.pov`` against prealloc's (naive's picture) at 64x48:
    the same scene (PSNR over 25 dB), apart where the two models differ (the glass)."""
    from harness.instruments.imagediff import canvas_array
    from harness.scenery.presets import build_scene, resolve_scene
    from variants.registry import load_variant

    assert REAL is not None
    size = Size(64, 48)
    variant = load_variant("prealloc")
    camera, world = build_scene(resolve_scene("reference"), variant, size)
    ours = canvas_array(variant.api["render"](camera, world), variant.api.get("pixel_at"))
    theirs = povray.render(REAL, SCENES / "reference.pov", size).image
    error = image_error(theirs, ours)
    assert error.psnr > 25, error
    assert not math.isinf(error.psnr)  # the glass differs: a real comparison, not a copy
