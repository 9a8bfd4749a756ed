"""The report's "Scaling" section (``harness.sections.scaling.measure``'s entries of a run): time
against pixel count per variant, throughput against the worker or thread count."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document import summary
from harness.document.model import Block, Heading, Para, Picture, Table
from harness.document.runinfo import part, rows, size_text, skip_reason
from harness.engine import figures
from harness.sections.scaling.measure import SECTION

Run = Mapping[str, Any]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured the scaling, if any."""
    return next(
        (run for run in reversed(runs) if part(run, SECTION, "sizes") or rows(run, SECTION)),
        None,
    )


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """Time against pixel count and throughput against workers or threads: the ``plot``
    (both panels) and the two tables."""
    sizes = part(run, SECTION, "sizes")
    threads = rows(run, SECTION)
    if not sizes and not threads:
        return []
    out: list[Block] = [Heading(2, "Scaling"), Para(context)]
    if plot is not None:
        out.append(Picture(plot, "time against pixel count; throughput against workers"))
    body = []
    for entry in sizes:
        for p in entry.get("points", []):
            w, h = p["size"]
            if "wall" in p:
                per_pixel = p["wall"] / (w * h)
                body.append(
                    [
                        f"`{entry['name']}`",
                        f"{w}x{h}",
                        figures.seconds_text(p["wall"]),
                        figures.per_pixel_text(per_pixel),
                        summary.point_cpu_text(entry, p),
                    ]
                )
        skipped = [p for p in entry.get("points", []) if p.get("skipped")]
        if skipped:
            sizes_text = ", ".join("x".join(map(str, p["size"])) for p in skipped)
            body.append(
                [f"`{entry['name']}`", sizes_text, "skipped: " + skip_reason(skipped), "-", "-"]
            )
    if body:
        header = ["variant", "size", "time", "time per pixel", "CPU: cores used of asked"]
        out.append(Table(header, body, right={2, 3, 4}))
        busy_points = [f"`{e['name']}` at {'x'.join(map(str, p['size']))}" for e in sizes
                       for p in e.get("points", []) if summary.point_busy(e, p)]  # fmt: skip
        if busy_points:
            out.append(Para(summary.busy_points_text(run, busy_points)))
    if threads:
        body = []
        ones = {r["group"]: r for r in threads if r["count"] == 1 and r["status"] == "ok"}
        for row in threads:
            if row["status"] != "ok":
                body.append(
                    [row["group"], str(row["count"]), f"`{row['name']}`", "failed", "-", "-", "-"]
                )
                continue
            one = ones.get(row["group"])
            gain = f"{figures.mrays(row) / figures.mrays(one):.2f}x" if one else "-"
            body.append(
                [
                    row["group"],
                    str(row["count"]),
                    f"`{row['name']}`",
                    size_text(row),
                    f"{figures.mrays(row):.3g}",
                    gain,
                    summary.cpu_text(row),
                ]
            )
        out.append(
            Table(
                [
                    "variant (option)",
                    "count",
                    "name",
                    "size",
                    "MRay/s",
                    "over 1",
                    "CPU: cores used of asked",
                ],
                body,
                right={1, 4, 5, 6},
            )
        )
        busy_threads = summary.busy_text(run, threads)
        if busy_threads:
            out.append(Para(busy_threads + " On the plot: hollow markers."))
    return out


def console_lines(run: Run) -> list[str]:
    return []
