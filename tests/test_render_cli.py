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
        (
            ["--depth", "-1"],
            "rtc render: bad option --depth: depth must be a whole number 0 to 100",
        ),
        (["--depth", "101"], "rtc render: bad option --depth: depth must be a whole number 0 to"),
        (["--epsilon", "0"], "rtc render: bad option --epsilon: epsilon must be a number between"),
        (["--samples", "0"], "rtc render: bad option --samples: samples must be a whole number 1"),
        (["--samples", "2000000"], "rtc render: bad option --samples: samples must be a whole"),
        (
            ["--integrator", "photon"],
            "rtc render: bad option --integrator 'photon': expected whitted or path",
        ),
        (["--roulette", "-1"], "rtc render: bad option --roulette: roulette must be a whole"),
        (["--seed", "-1"], "rtc render: bad option --seed: seed must be a whole number 0 to"),
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


FURNACE = Path(__file__).resolve().parent.parent / "scenes" / "furnace.yml"


def test_a_path_traced_render_takes_the_scene_files_settings_and_the_flags_win(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # furnace.yml says integrator path, 4 samples: its sphere vanishes in the sky
    output = tmp_path / "furnace.png"
    status, out, _ = render(capsys, str(FURNACE), "-o", str(output), "--size", "6x5")
    assert status == 0
    assert "(path tracing: depth 5, 4 samples per pixel, seed 0, roulette off" in out
    assert set(read_png(output)[2]) == {128}  # 0.5 everywhere: the sky
    # the flags win: the book's integrator ignores the sky (black), more samples, a seed
    status, out, _ = render(
        capsys, str(FURNACE), "-o", str(tmp_path / "whitted.png"), "--size", "6x5",
        "--integrator", "whitted", "--samples", "2",
    )  # fmt: skip
    assert status == 0 and "(depth 5, epsilon 0.0001, 2 samples per pixel)" in out
    assert set(read_png(tmp_path / "whitted.png")[2]) == {0}
    status, out, _ = render(
        capsys, str(FURNACE), "-o", str(tmp_path / "again.png"), "--size", "6x5",
        "--depth", "2", "--seed", "9", "--roulette", "1",
    )  # fmt: skip
    assert status == 0
    assert "(path tracing: depth 2, 4 samples per pixel, seed 9, roulette from bounce 1" in out


def test_the_integrator_flag_path_traces_a_scene_without_a_render_item(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    output = tmp_path / "tiny.png"
    status, out, _ = render(
        capsys, str(tiny), "-o", str(output), "--integrator", "path", "--seed", "3"
    )
    assert status == 0 and "path tracing" in out
    variant = load_variant("naive")
    scene = load_scene(tiny, variant.api)
    settings = RenderSettings(integrator="path", seed=3)
    expected = canvas_to_rgb8(variant.api["render"](scene.camera, scene.world, settings))
    assert read_png(output)[2] == expected
    whitted = canvas_to_rgb8(variant.api["render"](scene.camera, scene.world, RenderSettings()))
    assert expected != whitted


def test_a_long_path_traced_render_says_so_before_it_starts(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from rtc import cmd_render

    ticks = iter(range(0, 10**6, 20))  # every look at the clock: 20 s later
    monkeypatch.setattr(cmd_render, "_clock", lambda: float(next(ticks)))
    status, _, err = render(
        capsys, str(tiny), "-o", str(tmp_path / "out.png"), "--integrator", "path",
        "--samples", "3", "--progress", "none",
    )  # fmt: skip
    assert status == 0
    first = err.splitlines()[0]
    assert first.startswith("rtc render: naive will take about ")
    assert "path-traced render (3 rays per pixel, up to 6 hits each; timed on 1 pixel)" in first
    assert first.endswith("or --variant numba (compiled)")
    # the book's integrator: no probe, no such line before it starts
    ticks = iter(range(0, 10**6, 20))
    status, _, err = render(capsys, str(tiny), "-o", str(tmp_path / "w.png"), "--progress", "none")
    assert status == 0 and "path-traced" not in err


def test_a_variant_without_a_tracer_refuses_the_path_integrator_in_one_line(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # a learner's tracer answers through its API alone: its render() knows no integrator
    from rtc import cmd_render
    from variants import registry

    own = registry.Variant("own", "a learner's", load_variant("naive").api)
    monkeypatch.setattr(cmd_render, "load_variant", lambda name: own)
    output = tmp_path / "out.png"
    line = one_line_error(
        capsys, str(tiny), "-o", str(output), "--variant", "own", "--integrator", "path"
    )
    assert line.startswith("rtc render: own renders with a render() of its own, which takes no")
    assert not output.exists()
