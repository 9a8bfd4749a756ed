"""``rtc render``: a scene file to an image; user mistakes are one line on stderr, status 2."""

from __future__ import annotations

from pathlib import Path

import pytest

from groundwork.images import read_png
from raytracer.camera import RenderSettings
from raytracer.canvas import canvas_to_rgb8
from rtc.cli import main
from scene import load_scene
from variants.registry import load_variant

TINY = """\
- add: camera
  width: 8
  height: 6
  field-of-view: 1.0
  from: [0, 1, -4]
  to: [0, 0.5, 0]
  up: [0, 1, 0]
- add: light
  at: [-4, 4, -4]
  intensity: [1, 1, 1]
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[1, 1, 1], [0.2, 0.2, 0.2]]
- add: sphere
  transform:
    - [translate, 0, 1, 0]
  material:
    color: [1, 0.2, 0.2]
    reflective: 0.3
"""


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.yml"
    path.write_text(TINY, encoding="utf-8")
    return path


def render(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    status = main(["render", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_a_tiny_render_writes_the_variants_picture_as_a_png(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from rtc import cmd_render

    monkeypatch.setattr(cmd_render, "_clock", lambda: 0.0)  # a render within the second
    output = tmp_path / "tiny.png"
    status, out, err = render(capsys, str(tiny), "-o", str(output))
    assert status == 0 and err == ""  # no progress for a render within a second
    width, height, rgb = read_png(output)
    assert (width, height) == (8, 6)
    variant = load_variant("naive")
    scene = load_scene(tiny, variant.api)
    expected = canvas_to_rgb8(variant.api["render"](scene.camera, scene.world, RenderSettings()))
    assert rgb == expected
    assert len(set(zip(rgb[0::3], rgb[1::3], rgb[2::3], strict=True))) > 2  # not one flat color
    assert f"-> {output}" in out and " s " in out.splitlines()[-1]


def test_size_depth_and_epsilon_reach_the_render(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "small.ppm"
    status, out, _ = render(
        capsys, str(tiny), "-o", str(output), "--size", "4x3", "--depth", "0",
        "--epsilon", "0.001",
    )  # fmt: skip
    assert status == 0
    assert output.read_text().startswith("P3\n4 3\n255\n")
    assert "at 4x3 with naive (depth 0, epsilon 0.001, 1 sample per pixel)" in out
    variant = load_variant("naive")
    scene = load_scene(tiny, variant.api).resized(4, 3)
    canvas = variant.api["render"](
        scene.camera, scene.world, RenderSettings(depth=0, epsilon=0.001)
    )
    assert output.read_text() == variant.api["canvas_to_ppm"](canvas)


def one_line_error(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    status, _, err = render(capsys, *args)
    assert status == 2
    lines = err.splitlines()
    assert len(lines) == 1, err
    return lines[0]


def test_a_broken_scene_is_one_line_on_stderr_with_the_file_and_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = tmp_path / "broken.yml"
    broken.write_text(TINY + "- add: cube\n  transform:\n    - [scale, 2, 2]\n", encoding="utf-8")
    line = one_line_error(capsys, str(broken), "-o", str(tmp_path / "out.png"))
    assert line == (
        f"rtc render: {broken}:24: the cube at line 22: transform entry: 'scale' takes 3 "
        "numbers (x, y, z), got 2"
    )
    assert not (tmp_path / "out.png").exists()


def test_bad_yaml_is_one_line_too(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    broken = tmp_path / "broken.yml"
    broken.write_text("- add: sphere\n   material: x\n  shadow: false\n", encoding="utf-8")
    line = one_line_error(capsys, str(broken), "-o", str(tmp_path / "out.png"))
    assert line.startswith(f"rtc render: {broken}:2: invalid YAML: mapping values are not allowed")


@pytest.mark.parametrize(
    ("options", "text"),
    [
        (["--variant", "nosuch"], "rtc render: --variant: unknown variant 'nosuch'"),
        (["--size", "0x10"], "rtc render: bad --size '0x10': width and height must be 1 to 16384"),
        (["--size", "20000x10"], "rtc render: bad --size '20000x10': width and height must be"),
        (["--size=-3x4"], "rtc render: bad --size '-3x4': expected WIDTHxHEIGHT"),
        (["--size", "big"], "rtc render: bad --size 'big': expected WIDTHxHEIGHT"),
        (["--depth", "-1"], "rtc render: bad option: depth must be a whole number 0 to 100"),
        (["--epsilon", "0"], "rtc render: bad option: epsilon must be a number between 0 and 1"),
        (["--samples", "0"], "rtc render: bad option: samples must be a whole number 1 to"),
    ],
)
def test_bad_options_are_one_line(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], options: list[str], text: str
) -> None:
    line = one_line_error(capsys, str(tiny), "-o", str(tmp_path / "out.png"), *options)
    assert line.startswith(text)


def test_bad_outputs_are_one_line(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    line = one_line_error(capsys, str(tiny), "-o", str(tmp_path / "out.jpg"))
    assert line == (
        f"rtc render: cannot write '{tmp_path / 'out.jpg'}': unknown image extension .jpg; "
        "use .png or .ppm"
    )
    line = one_line_error(capsys, str(tiny), "-o", str(tmp_path / "no" / "out.png"))
    assert line == (
        f"rtc render: cannot write '{tmp_path / 'no' / 'out.png'}': no folder '{tmp_path / 'no'}'"
    )


def test_a_missing_scene_file_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    line = one_line_error(capsys, str(tmp_path / "none.yml"), "-o", str(tmp_path / "out.png"))
    assert line == (
        f"rtc render: {tmp_path / 'none.yml'}: cannot read the scene file: No such file or "
        "directory"
    )


def test_a_crashed_worker_is_an_error_naming_the_variant_and_scene(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A pooled render whose worker dies ends with a message, status 2 and no image."""
    import dataclasses

    from rtc import cmd_render
    from variants.pooled import RenderWorkerError

    def crashed(*_: object) -> None:
        raise RenderWorkerError("worker 1 (pid 4242) died with exit code -9 (killed by SIGKILL)")

    pooled = load_variant("pooled[workers=1]")
    broken = dataclasses.replace(pooled, api={**pooled.api, "render": crashed})
    monkeypatch.setattr(cmd_render, "load_variant", lambda _name: broken)
    output = tmp_path / "out.png"
    line = one_line_error(capsys, str(tiny), "--variant", "pooled[workers=1]", "-o", str(output))
    assert line == (
        f"rtc render: pooled[workers=1]:naive could not render {tiny}: worker 1 (pid 4242) "
        "died with exit code -9 (killed by SIGKILL)"
    )
    assert not output.exists()


def test_explain_asks_the_variants_tracer(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``--explain`` prints ``tracer.explain(world)``; a variant without a tracer (a
    learner's) has nothing to explain."""
    import dataclasses

    from rtc import cmd_render

    output = tmp_path / "out.png"
    status, out, _ = render(
        capsys, str(tiny), "--variant", "robust", "--explain", "-o", str(output)
    )
    assert status == 0
    assert "RobustTracer: the book's pipeline in Python, one pixel at a time; 2 objects" in out
    learner = dataclasses.replace(load_variant("naive"), name="mine", tracer=None)
    monkeypatch.setattr(cmd_render, "load_variant", lambda _name: learner)
    status, out, _ = render(capsys, str(tiny), "--variant", "mine", "--explain", "-o", str(output))
    assert status == 0 and "mine: nothing to explain" in out
