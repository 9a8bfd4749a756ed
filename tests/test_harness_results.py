"""The result files: schema round trip, old versions, pyperf compatibility, no overwriting."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pyperf
import pytest

from harness.engine import results
from harness.engine.results import (
    ResultFileError,
    RunWriter,
    load_run,
    pyperf_document,
    remove_stale_staging,
    write_new_file,
)

SCHEMA1 = Path(__file__).parent / "data" / "bench-schema1.json"


def _document() -> dict:
    rtc = {"rows": [{"name": "naive", "section": "table", "wall": [0.5, 0.25]}], "notes": ["x"]}
    bench = {"name": "scene naive", "values": [0.5, 0.25], "metadata": {"width": 8, "cpu": 0.9}}
    return pyperf_document([bench], rtc)


def test_a_run_file_round_trips_and_pyperf_reads_it(tmp_path):
    writer = RunWriter(tmp_path)
    (writer.staging / "picture.png").write_bytes(b"not really a png")
    path = writer.publish(_document())
    loaded = load_run(path)
    assert loaded["rtc"]["schema_version"] == results.SCHEMA_VERSION
    assert loaded["rtc"]["rows"] == [{"name": "naive", "section": "table", "wall": [0.5, 0.25]}]
    assert loaded["rtc"]["stem"] == path.stem
    assert (tmp_path / "runs" / path.stem / "picture.png").read_bytes() == b"not really a png"
    suite = pyperf.BenchmarkSuite.load(str(path))
    bench = suite.get_benchmark("scene naive")
    assert bench.get_values() == (0.5, 0.25)
    assert bench.get_metadata()["width"] == 8


def test_a_file_written_by_schema_version_1_still_loads():
    loaded = load_run(SCHEMA1)
    names = [row["name"] for row in loaded["rtc"]["rows"]]
    assert names == ["naive", "cached"]
    assert loaded["rtc"]["machine"]["cpu_count"] >= 1


def test_an_older_version_is_migrated_when_the_schema_moves_on(tmp_path, monkeypatch):
    def add_field(data: dict) -> dict:
        data["rtc"]["added_in_2"] = len(data["rtc"]["rows"])
        return data

    monkeypatch.setattr(results, "SCHEMA_VERSION", 2)
    monkeypatch.setitem(results.MIGRATIONS, 1, add_field)
    loaded = load_run(SCHEMA1)
    assert loaded["rtc"]["schema_version"] == 2
    assert loaded["rtc"]["added_in_2"] == 2


def test_a_newer_version_or_a_foreign_file_is_a_clear_error(tmp_path):
    data = json.loads(SCHEMA1.read_text())
    data["rtc"]["schema_version"] = results.SCHEMA_VERSION + 1
    newer = tmp_path / "newer.json"
    newer.write_text(json.dumps(data))
    with pytest.raises(ResultFileError, match=r"newer\.json: schema version \d+ is newer"):
        load_run(newer)
    foreign = tmp_path / "foreign.json"
    foreign.write_text('{"benchmarks": []}')
    with pytest.raises(ResultFileError, match=r"foreign\.json: not an rtc bench result"):
        load_run(foreign)
    broken = tmp_path / "broken.json"
    broken.write_text('{"rtc": ')
    with pytest.raises(ResultFileError, match=r"broken\.json: cannot read"):
        load_run(broken)


def test_write_new_file_never_replaces(tmp_path):
    target = tmp_path / "result.json"
    write_new_file(target, "first\n")
    with pytest.raises(FileExistsError, match="never replaced"):
        write_new_file(target, "second\n")
    assert target.read_text() == "first\n"
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]  # no temporary left


def test_a_run_refuses_to_publish_over_an_existing_file(tmp_path):
    writer = RunWriter(tmp_path)
    writer.json_path.write_text("someone else's\n")
    with pytest.raises(FileExistsError, match="never replaced"):
        writer.publish(_document())
    assert writer.json_path.read_text() == "someone else's\n"


def test_two_runs_get_two_files(tmp_path):
    first = RunWriter(tmp_path).publish(_document())
    second = RunWriter(tmp_path).publish(_document())
    assert first != second
    assert results.list_runs(tmp_path) == sorted([first, second])


def test_a_dead_runs_staging_folder_is_removed_and_a_live_one_kept(tmp_path):
    runs = tmp_path / "runs"
    dead = runs / f"{results.STAGING_PREFIX}bench-x-999999999"
    dead.mkdir(parents=True)
    assert remove_stale_staging(tmp_path) == [dead]
    assert not dead.exists()
    dead.mkdir()
    alive = RunWriter(tmp_path)  # a new run cleans up too; its own folder (this pid) stays
    assert not dead.exists()
    assert remove_stale_staging(tmp_path) == []
    assert alive.staging.is_dir()
    alive.abandon()
    assert not alive.staging.exists()


def test_listing_ignores_hidden_and_foreign_files(tmp_path):
    runs = tmp_path / "runs"
    runs.mkdir()
    shutil.copy(SCHEMA1, runs / "bench-20250101T000000Z-aaaaaa.json")
    (runs / ".bench-20250101T000000Z-bbbbbb.json.tmp").write_text("partial")
    (runs / "notes.json").write_text("{}")
    assert [p.name for p in results.list_runs(tmp_path)] == ["bench-20250101T000000Z-aaaaaa.json"]
