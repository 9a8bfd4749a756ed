"""A bench's measuring jobs as tasks on a Dask cluster (issue 17): ``rtc bench --sweep-on
CLUSTER`` runs the error sweep's configurations there, all submitted at once.

CLUSTER is spelled as the ``dask`` variant's options: ``dask[workers=N]`` starts a local
cluster of N single-threaded workers for the section, ``dask[scheduler=tcp://HOST:8786]``
uses a running one (each machine with this project installed). A task runs the same
measuring process a job runs here (``harness.engine.jobs.run_in_child``: a fresh process on the
worker's machine, in a temporary folder there) and returns its result with its pictures'
bytes, which land in the job's folder here: nothing else changes downstream. The workers'
timings are their machines': jobs that run side by side on one machine share it, and each
point's CPU share says what it got.
"""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from harness.engine.jobs import JobOutcome, run_in_child
from variants.registry import parse_variant_name

Job = tuple[Path, dict[str, Any]]  # the job's folder here, the job


def cluster_options(text: str) -> tuple[int, str | None, int]:
    """(workers, scheduler, timeout) of a ``dask[...]`` spelling; ``ValueError`` naming
    what is wrong (the registry's ``VariantError`` is one)."""
    # deferred: saves ~70 ms (dask's variant) of rtc bench without --sweep-on
    from variants.dask_cluster import NAME, cluster_settings

    spec = parse_variant_name(text)
    if spec.name != NAME or spec.inner is not None:
        raise ValueError(
            f"{text!r} is not a cluster: give dask[workers=N] or dask[scheduler=tcp://HOST:8786]"
        )
    workers, scheduler, _tile, timeout = cluster_settings(dict(spec.options))
    return workers, scheduler, timeout


def _run_there(job: dict[str, Any]) -> tuple[dict[str, Any] | int, dict[str, bytes]]:
    """On a worker: the job in a fresh measuring process, in a temporary folder; its
    result (or exit code) and the bytes of the pictures it saved."""
    scratch = Path(tempfile.mkdtemp(prefix="rtc-job-"))
    try:
        folder = scratch / "job"
        result = run_in_child("harness.engine.child", folder, job, job.get("threads"))
        return result, {path.name: path.read_bytes() for path in folder.glob("*.npy")}
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


@contextmanager
def cluster_jobs(text: str) -> Iterator[Any]:
    """A runner of jobs on the cluster ``text`` names: ``run(jobs) -> [JobOutcome]``."""
    # deferred: saves ~70 ms (dask's variant) of rtc bench without --sweep-on
    from variants.dask_cluster import connected

    workers, scheduler, timeout = cluster_options(text)
    with connected(scheduler, workers, timeout) as client:

        def run(jobs: list[Job]) -> list[JobOutcome]:
            futures = [client.submit(_run_there, job, pure=False) for _, job in jobs]
            try:
                return [
                    _outcome(folder, job, future)
                    for (folder, job), future in zip(jobs, futures, strict=True)
                ]
            finally:
                client.cancel(futures)

        yield run


def _outcome(folder: Path, job: dict[str, Any], future: Any) -> JobOutcome:
    folder.mkdir(parents=True)
    try:
        result, files = future.result()
    except Exception as error:  # the task failed or kept killing its workers
        text = str(error).strip().splitlines()
        reason = f"{type(error).__name__}: {text[0]}" if text else type(error).__name__
        return JobOutcome(folder, {"variant": job["variant"], "error": f"on the cluster: {reason}"})
    for name, data in files.items():
        (folder / name).write_bytes(data)
    if isinstance(result, int):
        result = {"variant": job["variant"], "error": f"the measuring process exited with {result}"}
    return JobOutcome(folder, result)
