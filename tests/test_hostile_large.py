"""Hostile input, fourth round (issue 37): input far larger than ours is refused in one line,
before it is walked.

- ``rtc report`` over a run file of more than 100,000 rows (17 MB): it cost about 15 ms a
  row (25 minutes); now the file is skipped with one line naming it and its count, and the
  other runs are reported (``harness.engine.results.MAX_ROWS``);
- geometry past floating point: a cone's max of 1e300 (naive drew NaN pixels and refused,
  wavefront drew what its overflows gave) and a torus of radius 1e300 (nothing drawn, by
  every variant) are refused by the scene file, for every variant, naming the line;
  a cone's max of 1e150 still renders, naive and wavefront alike (``scene.kinds``).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from test_hostile import one_line, scene

from harness.engine.results import MAX_ROWS
from harness.report.build import load_history
from scene.kinds import CAP_LARGEST, RADIUS_LARGEST

ROOT = Path(__file__).resolve().parent.parent
HUGE = "bench-20250102T000000000Z-bbbbbb.json"


@pytest.mark.parametrize("key", ["rows", "series"])
def test_a_run_of_more_than_100000_rows_is_skipped_in_one_line(tmp_path: Path, key: str) -> None:
    runs = tmp_path / "results" / "runs"
    runs.mkdir(parents=True)
    good = sorted((ROOT / "results" / "runs").glob("bench-*.json"))[0]  # a committed run
    shutil.copy(good, runs / good.name)
    data = json.loads(good.read_text(encoding="utf-8"))
    data["rtc"]["stem"] = HUGE.removesuffix(".json")
    one = {"section": "table", "name": "naive", "status": "skipped"}  # about 17 MB in all
    data["rtc"][key] = [dict(one, name=f"naive-{i}") for i in range(100_001)]
    (runs / HUGE).write_text(json.dumps(data), encoding="utf-8")
    assert MAX_ROWS < 100_001
    kept, problems = load_history(tmp_path / "results")  # what rtc report reads
    assert [run["stem"] for run in kept] == [good.stem]
    assert problems == [
        f"{runs / HUGE}: {key}: 100,001 of them, more than a run of this project holds "
        f"({MAX_ROWS:,})"
    ]


@pytest.mark.parametrize("variant", ["naive", "numba", "wavefront"])
@pytest.mark.parametrize(("shape", "key", "largest"), [
    ("cone\n  min: -1\n  closed: true\n  max: 1e300", "max", CAP_LARGEST),
    ("cylinder\n  min: -1e300\n  max: 1", "min", CAP_LARGEST),
    ("torus\n  major-radius: 1e300", "major-radius", RADIUS_LARGEST),
    ("torus\n  minor-radius: 1e300\n  major-radius: 1", "minor-radius", RADIUS_LARGEST),
])  # fmt: skip
def test_geometry_past_floating_point_is_refused_by_every_variant(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], variant: str, shape: str, key: str,
    largest: float,
) -> None:  # fmt: skip
    path = scene(tmp_path, f"- add: {shape}\n")
    out = tmp_path / "o.png"
    line = one_line(capsys, "render", str(path), "--variant", variant, "-o", str(out))
    assert f"{key} is too large for floating point (" in line and "e+300)" in line, line
    assert f"expected a size up to {largest:g}" in line and f"{path}:" in line, line
    assert not out.exists()


def test_a_cone_capped_at_1e150_renders_alike_in_naive_and_wavefront(tmp_path: Path) -> None:
    from PIL import Image

    from rtc.cli import main

    pictures = []
    for variant in ("naive", "wavefront"):
        for cap in ("1e150", "1e6"):
            path = scene(tmp_path, f"- add: cone\n  min: -1\n  max: {cap}\n  closed: true\n")
            out = tmp_path / f"{variant}-{cap}.png"
            assert main(["render", str(path), "--variant", variant, "-o", str(out)]) == 0
            with Image.open(out) as image:
                pictures.append(np.asarray(image, dtype=np.int64))
    assert pictures[0].any()
    assert all(np.array_equal(pictures[0], picture) for picture in pictures[1:])


@pytest.mark.parametrize("raised", [FileNotFoundError(2, "No such file or directory"),
                                    RuntimeError("cannot cache function: no locator available")])
def test_the_kernel_folder_removed_during_a_compile_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, raised: Exception
) -> None:
    """A build whose kernel folder is removed while it runs (what numba and the linker then
    raise) is a ``KernelFolderError`` naming the folder, which rtc prints as one line."""
    from compiled import KernelFolderError
    from compiled import library as compiled_library

    folder = tmp_path / "kernels"
    folder.mkdir(mode=0o700)
    monkeypatch.setattr(compiled_library, "announce", lambda *args: None)

    def build() -> None:
        shutil.rmtree(folder)
        raise raised

    def fallback(problem: str) -> None:
        raise AssertionError("no fallback for a folder that is gone")

    with pytest.raises(KernelFolderError, match=r"the kernel folder .*kernels was removed or"):
        compiled_library.load_once(
            {}, folder / "rtc_tiny_0123456789abcdef.so", build, lambda library: library,
            fallback, "a tiny kernel",
        )  # fmt: skip


def test_an_error_of_a_build_whose_folder_is_there_is_not_blamed_on_it(tmp_path: Path) -> None:
    from compiled import library as compiled_library

    def build() -> None:
        raise RuntimeError("a bug of ours")

    with pytest.raises(RuntimeError, match="a bug of ours"):
        compiled_library.load_once(
            {}, tmp_path / "rtc_tiny_0123456789abcdef.so", build, lambda library: library,
            lambda problem: None, "a tiny kernel",
        )  # fmt: skip
