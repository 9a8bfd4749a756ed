"""The report's "Error against run time" section (``harness.sections.sweep.measure``'s entries of a
run): the ground truth, each configuration's error at each sample count, the plot with its Pareto
front."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Heading, Para, Picture, Table
from harness.document.runinfo import part, skip_reason
from harness.engine import figures
from harness.sections.sweep.measure import SECTION

Run = Mapping[str, Any]


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that ran the sweep, if any."""
    return next((run for run in reversed(runs) if part(run, SECTION, "truth")), None)


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The ground truth, the error-against-time ``plot`` and a row per point rendered."""
    truth = next(iter(part(run, SECTION, "truth")), None)
    sweeps = part(run, SECTION)
    if truth is None and not sweeps:
        return []
    out: list[Block] = [Heading(2, "Error against run time"), Para(context)]
    if truth is not None and truth.get("points") and "wall" in truth["points"][0]:
        p = truth["points"][0]
        out.append(
            Para(
                f"Ground truth: `{truth['name']}` (the fastest variant whose table picture equals "
                f"naive's) at {p['size'][0]}x{p['size'][1]} with {p['samples']} samples per pixel "
                f"({figures.seconds_text(p['wall'])}). Sample positions are a pure function of "
                "(seed, pixel, sample), so exact variants render the same pictures and differ only "
                "in time; float32 and fastmath options also differ in error. One render per point."
            )
        )
    if plot is not None:
        out.append(Picture(plot, "error against time"))
    body = []
    for entry in sweeps:
        for p in entry.get("points", []):
            if "wall" in p and p.get("error"):
                e = p["error"]
                psnr = "∞" if e["psnr"] is None else f"{e['psnr']:.1f}"
                body.append(
                    [
                        f"`{entry['name']}`",
                        str(p["samples"]),
                        figures.seconds_text(p["wall"]),
                        f"{e['rmse']:.4g}",
                        psnr,
                        f"{e['max_abs']:.3g}",
                    ]
                )
        skipped = [p for p in entry.get("points", []) if p.get("skipped")]
        if skipped:
            spp = ", ".join(str(p["samples"]) for p in skipped)
            body.append(
                [f"`{entry['name']}`", spp, "skipped: " + skip_reason(skipped), "-", "-", "-"]
            )
        if entry["status"] != "ok":
            body.append(
                [f"`{entry['name']}`", "-", "failed: " + entry.get("error", ""), "-", "-", "-"]
            )
    if body:
        out.append(
            Table(
                ["configuration", "samples/pixel", "time", "RMSE", "PSNR (dB)", "max abs error"],
                body,
                right={1, 2, 3, 4, 5},
            )
        )
    return out


def console_lines(run: Run) -> list[str]:
    return []
