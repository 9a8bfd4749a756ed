"""The CPU seconds each test costs, to see where the suite's time goes on a shared machine.

Wall times (``--durations``) stretch with whatever else the machine runs; CPU seconds do
not. With ``RTC_TEST_CPU_LOG`` set to a file, every test appends one JSON line to it: its
id, the CPU seconds of the process that ran it (setup and teardown included) and of the
child processes it waited for (the pools' workers, ``rtc`` runs), and its wall seconds.
``python tests/cpu_seconds.py FILE`` sums a log up: the total, by module, the slowest tests.
Without ``RTC_TEST_CPU_LOG`` nothing is recorded (conftest.py loads this plugin).
"""

from __future__ import annotations

import json
import os
import resource
import sys
import time
from collections import Counter
from collections.abc import Iterator
from typing import Any

import pytest

ENVIRONMENT = "RTC_TEST_CPU_LOG"


def _cpu() -> tuple[float, float]:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None) -> Iterator[None]:
    # out of the environment while the test runs: a pytest the test starts (``rtc kata``'s)
    # would log its own tests as this worker's; its CPU is this test's ``children``
    path = os.environ.pop(ENVIRONMENT, None)
    if not path:
        yield
        return
    (own, children), wall = _cpu(), time.perf_counter()
    try:
        yield
    finally:
        os.environ[ENVIRONMENT] = path
    (own_after, children_after) = _cpu()
    line = {
        "test": item.nodeid,
        "cpu": round(own_after - own, 3),
        "children": round(children_after - children, 3),
        "wall": round(time.perf_counter() - wall, 3),
        # which worker process ran it (pytest-xdist's ``gw0``; "main" without) and when it
        # ended: a worker still busy after the others ended is the run's tail
        "worker": os.environ.get("PYTEST_XDIST_WORKER", "main"),
        "ended": round(time.time(), 2),
    }
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
    try:  # one short line appended in one write: the workers' lines never mix
        os.write(fd, (json.dumps(line) + "\n").encode("utf-8"))
    finally:
        os.close(fd)


def summary(lines: list[dict[str, Any]], top: int = 30) -> list[str]:
    """A log's figures, as lines of text."""

    def cost(line: dict[str, Any]) -> float:
        return float(line["cpu"] + line["children"])

    total = sum(cost(line) for line in lines)
    modules: Counter[str] = Counter()
    for line in lines:
        modules[line["test"].split("::")[0]] += cost(line)
    out = [f"{len(lines)} tests, {total:,.0f} CPU seconds (their processes and children)"]
    out.append("by module:")
    out += [f"  {seconds:8.1f}  {module}" for module, seconds in modules.most_common(15)]
    out.append(f"the {top} costliest tests:")
    slowest = sorted(lines, key=cost, reverse=True)[:top]
    out += [f"  {cost(line):8.1f}  {line['test']}" for line in slowest]
    return out + _tail(lines)


def _tail(lines: list[dict[str, Any]]) -> list[str]:
    """When each worker ran its last test, after the first to end (a log with ``ended``)."""
    ends: dict[str, dict[str, Any]] = {}
    for line in lines:
        if "ended" in line and line["ended"] >= ends.get(line["worker"], line)["ended"]:
            ends[line["worker"]] = line
    if len(ends) < 2:
        return []
    first = min(line["ended"] for line in ends.values())
    out = ["each worker's last test, seconds after the first worker's last:"]
    for worker, line in sorted(ends.items(), key=lambda item: item[1]["ended"]):
        out.append(f"  {line['ended'] - first:8.1f}  {worker}  {line['test']}")
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python tests/cpu_seconds.py LOG")
    with open(sys.argv[1], encoding="utf-8") as log:
        print("\n".join(summary([json.loads(line) for line in log if line.strip()])))
