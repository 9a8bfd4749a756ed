"""The stability table, from a run's ``rtc`` section (``runfile``): as text for the terminal,
and as blocks for the harness report (``results/README.md`` and ``report.html``).

One row per case, one column per variant; a cell is ``exact``, ``ok`` with the measured
error, ``WRONG`` (with the error where there is one), ``NaN/inf`` or ``CRASH``.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from typing import Any

from harness.document.model import Block, Bullets, Heading, Para, Table
from harness.stability.model import Verdict

Run = Mapping[str, Any]
SHORT = {
    Verdict.EXACT.value: "exact",
    Verdict.WITHIN.value: "ok",
    Verdict.WRONG.value: "WRONG",
    Verdict.NONFINITE.value: "NaN/inf",
    Verdict.CRASHED.value: "CRASH",
    Verdict.UNSUPPORTED.value: "n/a",
}
LEGEND = (
    "exact: the oracle's answer (floats correctly rounded, identical pixels, the expected "
    "clear error); ok E: within the case's tolerance, off by E; WRONG E: outside it (or "
    "what is wrong where there is no number: a lost or extra hit, an unclear or no error); "
    "NaN/inf: non-finite where a finite answer is due; CRASH: an unexpected exception; "
    "n/a: the variant has not what the case needs (a path integrator) and says so. "
    "Errors are in the case's unit (its 'measure'); px, rays, points: how many were wrong."
)


def _number(value: float, unit: str) -> str:
    if unit:
        return f"{value:.0f} {unit}"
    if value == 0:
        return "0"
    return f"{value:.1e}"


def cell_text(row: Mapping[str, Any], unit: str) -> str:
    """A result's cell: the verdict in short, with its error (a count of ``unit``, if any)."""
    verdict = row["verdict"]
    text = SHORT.get(verdict, verdict)
    error = row.get("error")
    if verdict in (Verdict.WITHIN.value, Verdict.WRONG.value) and error is not None:
        text += " " + _number(float(error), unit)
    elif row.get("note"):
        text += " " + str(row["note"])
    return text


def _grid(run: Run) -> tuple[list[str], list[list[str]]]:
    variants = list(run["variants"])
    by_key = {(r["case"], r["variant"]): r for r in run["results"]}
    rows = []
    for case in run["cases"]:
        cells = []
        for variant in variants:
            row = by_key.get((case["id"], variant))
            cells.append("-" if row is None else cell_text(row, case.get("unit", "")))
        rows.append([case["id"], *cells])
    return ["case", *variants], rows


def summaries(run: Run) -> list[str]:
    """One line per variant: how many cases gave each verdict."""
    lines = []
    for variant in run["variants"]:
        counts = Counter(r["verdict"] for r in run["results"] if r["variant"] == variant)
        parts = [f"{counts.get(v.value, 0)} {v.value}" for v in Verdict]
        lines.append(f"{variant}: " + ", ".join(parts) + f" (of {sum(counts.values())})")
    return lines


def settings_line(run: Run) -> str:
    s = run["settings"]
    m = run["machine"]
    commit = (m.get("commit") or "unknown")[:10] + (" (dirty tree)" if m.get("dirty") else "")
    return (
        f"Run `{run.get('stem', '?')}` started {run['started'][:19]} UTC, took "
        f"{run['seconds']:.0f} s on `{m.get('hostname')}`, commit {commit}; renders at "
        f"{s['size'][0]}x{s['size'][1]}; cases: {s.get('cases') or 'all'}."
    )


def text_table(run: Run, details: bool = False) -> str:
    """The table for a terminal, then the summaries (and with ``details``, every cell that
    is not exact or ok, with what was seen)."""
    header, rows = _grid(run)
    widths = [max(len(str(line[i])) for line in [header, *rows]) for i in range(len(header))]
    lines = [settings_line(run).replace("`", ""), ""]
    for line in [header, *rows]:
        lines.append("  ".join(str(v).ljust(w) for v, w in zip(line, widths, strict=True)))
    lines += ["", *summaries(run), "", LEGEND]
    unavailable = run.get("unavailable") or {}
    lines += [f"not available: {name}: {why}" for name, why in unavailable.items()]
    if details:
        lines += ["", "Not exact or ok (variants that saw the same, together):"]
        lines += [f"  {case}: {', '.join(names)}: {verdict}: {detail}"
                  for case, names, verdict, detail in failures(run)]  # fmt: skip
    return "\n".join(lines)


def failures(run: Run) -> list[tuple[str, list[str], str, str]]:
    """The results that are wrong, non-finite or crashed, in table order, as (case,
    variants, verdict, detail): variants that saw exactly the same are one entry."""
    bad = (Verdict.WRONG.value, Verdict.NONFINITE.value, Verdict.CRASHED.value)
    order = {case["id"]: k for k, case in enumerate(run["cases"])}
    grouped: dict[tuple[str, str, str], list[str]] = {}
    for r in run["results"]:
        if r["verdict"] in bad:
            grouped.setdefault((r["case"], r["verdict"], r["detail"]), []).append(r["variant"])
    entries = [(case, names, verdict, detail) for (case, verdict, detail), names in grouped.items()]
    return sorted(entries, key=lambda entry: order.get(entry[0], len(order)))


def report_blocks(run: Run) -> list[Block]:
    """The stability section of the harness report."""
    header, rows = _grid(run)
    cases = Table(
        ["case", "what", "measure", "tolerance"],
        [[f"`{c['id']}`", c["title"], c["measure"], c["tolerance"]] for c in run["cases"]],
    )
    detail_rows = [
        [f"`{case}`", ", ".join(f"`{n}`" for n in names), verdict, detail]
        for case, names, verdict, detail in failures(run)
    ]
    blocks: list[Block] = [
        Heading(2, "Numerical stability"),
        Para(
            "Generated from the latest `rtc stability` run (`results/runs/stability-*.json`). "
            "Each case runs on every variant and is compared with an oracle computed exactly "
            "(rationals) or in 60-digit mpmath from the same float inputs. " + settings_line(run)
        ),
        Table(
            [f"`{h}`" if i else h for i, h in enumerate(header)],
            [[f"`{row[0]}`", *row[1:]] for row in rows],
        ),
        Para(LEGEND),
        Bullets(summaries(run)),
        Heading(3, "The cases"),
        cases,
    ]
    if detail_rows:
        blocks += [
            Heading(3, "What the variants got wrong"),
            Table(["case", "variants", "verdict", "what was seen"], detail_rows),
        ]
    unavailable = run.get("unavailable") or {}
    if unavailable:
        blocks.append(Bullets([f"`{n}` not available: {why}" for n, why in unavailable.items()]))
    return blocks
