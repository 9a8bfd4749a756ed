"""A failing test is one failure in the report, whatever its traceback holds (a pytest
plugin of the gate's: ``tests/conftest.py`` loads it).

pytest formats a failure's traceback while it makes the test's report; if formatting
raises, the session ends with an INTERNALERROR and no report (under pytest-xdist the worker
dies and its failure is lost). It does raise on a traceback entry with no line number:
pytest computes ``tb_lineno - 1``, and on Python 3.11 ``tb_lineno`` is None where the
instruction the entry points at has no line in its code's line table. So:

- before the report is made, every entry with no line number (in the exception, its cause
  and context, and an exception group's members) is given its function's first line, so
  that pytest formats it as usual;
- should formatting raise anyway, the report holds the failure as Python's own
  ``traceback`` module formats it, with one line saying why.
"""

from __future__ import annotations

import traceback
import types
from collections.abc import Generator

import pytest

NOTE = "(pytest could not format this failure's traceback: {problem!r}; Python's own format:)"


def mended(tb: types.TracebackType | None) -> types.TracebackType | None:
    """``tb``, or a copy where every entry with no line number has its function's first line
    (and no instruction offset, which would point at no line either)."""
    entries = []
    while tb is not None:
        entries.append(tb)
        tb = tb.tb_next
    if all(entry.tb_lineno is not None for entry in entries):
        return entries[0] if entries else None
    rebuilt: types.TracebackType | None = None
    for entry in reversed(entries):
        line = entry.tb_lineno
        if line is None:
            rebuilt = types.TracebackType(
                rebuilt, entry.tb_frame, -1, entry.tb_frame.f_code.co_firstlineno
            )
        else:
            rebuilt = types.TracebackType(rebuilt, entry.tb_frame, entry.tb_lasti, line)
    return rebuilt


def mend_all(error: BaseException, seen: set[int] | None = None) -> None:
    """Mend the tracebacks of ``error``, its cause, its context and a group's members."""
    seen = set() if seen is None else seen
    if id(error) in seen:
        return
    seen.add(id(error))
    error.__traceback__ = mended(error.__traceback__)
    linked = [error.__cause__, error.__context__]
    if isinstance(error, BaseExceptionGroup):
        linked.extend(error.exceptions)
    for other in linked:
        if other is not None:
            mend_all(other, seen)


def plain(error: BaseException, problem: BaseException) -> str:
    """The failure ``error`` as Python formats it, under its own last line (the report's
    summary shows the first) and a line saying why (``problem``)."""
    text = traceback.format_exception(error)
    return "".join([text[-1], NOTE.format(problem=problem), "\n", *text])


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_makereport(
    item: pytest.Item, call: pytest.CallInfo[None]
) -> Generator[None, pytest.TestReport, pytest.TestReport]:
    if call.excinfo is not None:
        error = call.excinfo.value
        before = error.__traceback__
        mend_all(error)
        if error.__traceback__ is not before and error.__traceback__ is not None:
            call.excinfo = pytest.ExceptionInfo.from_exception(error)
    try:
        return (yield)
    except Exception as problem:
        if call.excinfo is None:
            raise
        return pytest.TestReport(
            item.nodeid,
            item.location,
            {name: 1 for name in item.keywords},
            "failed",
            plain(call.excinfo.value, problem),
            call.when,
            [],
            call.duration,
            call.start,
            call.stop,
        )
