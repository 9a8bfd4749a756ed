"""Hostile input, fourth round (issue 37), the worker pools: what flooded the terminal with
worker tracebacks, or blamed the wrong thing, is one line naming what is wrong (exit 2).

- Dask with a malformed ``DASK_CONFIG`` file (Dask reads it as it is imported);
- a worker memory fraction that is no number (a starting worker died with ``MemoryError``,
  its traceback logged once per restart);
- ``ulimit -n 16`` under a local Dask cluster (its monitors raised ``EMFILE`` in a loop);
- ``ulimit -n 10`` under pooled (blamed on pickling the world).

Each runs ``rtc render`` in a fresh process, as a user would: its stderr is the verdict.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
from pathlib import Path

import pytest
from holding import HANG_SECONDS
from test_hostile import scene

from variants import dask_cluster, pooled

ROOT = Path(__file__).resolve().parent.parent


def render(
    tmp_path: Path, variant: str, env: dict[str, str] | None = None, files: int | None = None
) -> tuple[int, str, Path]:
    """``rtc render`` of a small scene through ``variant`` in a fresh process, with ``env``
    added and at most ``files`` open files (``ulimit -n``): its status, stderr and output."""
    path = scene(tmp_path, "- add: sphere\n")
    out = tmp_path / "out.png"

    def limit() -> None:
        if files is not None:
            resource.setrlimit(resource.RLIMIT_NOFILE, (files, files))

    done = subprocess.run(
        [sys.executable, "-m", "rtc.cli", "render", str(path), "--variant", variant,
         "-o", str(out), "--progress", "none"],
        cwd=ROOT, capture_output=True, text=True, timeout=HANG_SECONDS, preexec_fn=limit,
        env={**os.environ, **(env or {})},
    )  # fmt: skip
    return done.returncode, done.stderr, out


def the_line(stderr: str) -> str:
    """stderr's one error line (the render's first line, naming the scene, aside)."""
    lines = [line for line in stderr.splitlines() if not line.startswith("rendering ")]
    assert len(lines) == 1, stderr
    assert "Traceback" not in stderr, stderr
    return lines[0]


def test_a_malformed_dask_config_file_is_one_line_naming_it(tmp_path: Path) -> None:
    config = tmp_path / "dask.yaml"
    config.write_text("distributed:\n  worker: [unclosed\n", encoding="utf-8")
    status, stderr, out = render(tmp_path, "dask", {"DASK_CONFIG": str(config)})
    line = the_line(stderr)
    assert status == 2 and not out.exists()
    assert line.startswith("rtc render: --variant: variant 'dask' is not available here"), line
    assert str(config) in line and "malformed" in line and "line 2, column 11" in line, line


def test_a_garbage_dask_memory_target_is_one_line_naming_the_setting(tmp_path: Path) -> None:
    variable = "DASK_DISTRIBUTED__WORKER__MEMORY__TARGET"
    status, stderr, out = render(tmp_path, "dask[workers=1]", {variable: "garbage"})
    line = the_line(stderr)
    assert status == 2 and not out.exists()
    assert "distributed.worker.memory.target is 'garbage'" in line and variable in line, line


def test_a_dask_cluster_past_the_open_file_limit_is_one_line(tmp_path: Path) -> None:
    status, stderr, out = render(tmp_path, "dask[workers=2]", files=16)
    line = the_line(stderr)
    assert status == 2 and not out.exists()
    assert "may open only 16 files (ulimit -n)" in line, line


def test_pooled_past_the_open_file_limit_blames_the_limit_not_pickling(tmp_path: Path) -> None:
    status, stderr, out = render(tmp_path, "pooled[workers=2]", files=10)
    line = the_line(stderr)
    assert status == 2 and not out.exists()
    assert "too many open files (this process may open 10: ulimit -n)" in line, line
    assert "pickle" not in line


class Config:
    """A stand-in for ``dask.config``: ``get`` from a dict."""

    def __init__(self, values: dict[str, object]) -> None:
        self.values = values

    def get(self, key: str, default: object = None) -> object:
        return self.values.get(key, default)


@pytest.mark.parametrize("value", ["garbage", -0.5, 1.5, True, [0.6]])
def test_an_unusable_memory_fraction_is_named(value: object) -> None:
    problem = dask_cluster.memory_settings_problem(
        Config({"distributed.worker.memory.spill": value})
    )
    assert problem is not None and "distributed.worker.memory.spill is" in problem
    assert "DASK_DISTRIBUTED__WORKER__MEMORY__SPILL" in problem


@pytest.mark.parametrize("value", [None, False, 0, 0.6, 1])
def test_a_usable_memory_fraction_passes(value: object) -> None:
    assert dask_cluster.memory_settings_problem(
        Config({f"distributed.worker.memory.{key}": value for key in ("target", "pause")})
    ) is None


def test_a_start_problem_other_than_the_file_limit_is_named_as_it_is() -> None:
    error = OSError(12, "Cannot allocate memory")
    assert pooled.start_problem(error) == "OSError: Cannot allocate memory"
