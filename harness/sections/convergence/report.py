"""The report's "Convergence" section (``harness.sections.convergence.measure``'s entries of a
run): per path-traced scene, its converged picture, each variant's RMSE against it as samples
grow, the fitted slopes and the time to an RMSE of 0.01; the variants without a path
integrator with their one line."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from harness.document.model import Block, Bullets, Heading, Para, Picture, Table
from harness.document.runinfo import part, skip_reason
from harness.engine import figures
from harness.sections.convergence.fit import TARGET_RMSE
from harness.sections.convergence.measure import SECTION, label

Run = Mapping[str, Any]
ABOUT = (
    "Each variant that path-traces renders the scene with 1, 2, 4 ... samples per pixel (one "
    "timed render each); its RMSE against the converged picture is fitted as a power law of "
    "the samples and of the wall time (least squares on log-log axes). Every sample's pixel "
    "position (one sample: the pixel's centre, as in the book) and path numbers are "
    "independent uniform numbers (a hash of seed, pixel, "
    "sample, bounce and dimension; no stratification or jitter grid), so the slope against "
    "samples is about -1/2; stratified samples would fall faster only where the pixel's area "
    "matters (edges), not in the path's noise. The converged picture has its own seed, so "
    "its noise is independent of the others'; its RMSE against the true picture is a floor "
    "under theirs, so only points with at most a quarter of its samples are fitted. The "
    "headline is the time to an RMSE of "
    f"{TARGET_RMSE:g}, read off the time fit: extrapolated when outside the times measured."
)


def newest(runs: Sequence[Run]) -> Run | None:
    """The newest of ``runs`` (oldest first) that measured convergence, if any."""
    return next((run for run in reversed(runs) if part(run, SECTION, "truth")), None)


def headline(entry: Mapping[str, Any]) -> str:
    """The time to an RMSE of 0.01 in words, or why there is none."""
    found = (entry.get("fit") or {}).get("time_to")
    if not found:
        return "-" if entry.get("status") == "ok" else "failed"
    if found["seconds"] is None:
        return f"over {found['beyond']:.0e} s (extrapolated)"
    text = figures.seconds_text(found["seconds"])
    return f"{text} (extrapolated)" if found["extrapolated"] else text


def _slope(entry: Mapping[str, Any], key: str) -> str:
    law = (entry.get("fit") or {}).get(key)
    return "-" if not law else f"{law['slope']:+.2f}"


def _row(entry: Mapping[str, Any]) -> list[str]:
    done = [p for p in entry.get("points", []) if "wall" in p and p.get("error")]
    if entry["status"] != "ok" or not done:
        skipped = [p for p in entry.get("points", []) if p.get("skipped")]
        why = entry.get("error") or (
            f"not run: {skip_reason(skipped)}" if skipped else "no point measured"
        )
        return [f"`{label(entry)}`", "-", "-", "-", "-", "-", str(why)[:200]]
    last = done[-1]
    skipped = [str(p["samples"]) for p in entry.get("points", []) if p.get("skipped")]
    size = "x".join(map(str, last["size"]))
    return [
        f"`{label(entry)}`", size,
        ", ".join(f"{p['samples']}{'' if p.get('fitted', True) else ' (not fitted)'}"
                  for p in done),
        f"{last['error']['rmse']:.4g} in {figures.seconds_text(last['wall'])}",
        _slope(entry, "samples"), _slope(entry, "time"),
        headline(entry) + (f"; {', '.join(skipped)} spp over the budget" if skipped else ""),
    ]  # fmt: skip


def scene_blocks(run: Run, scene: str) -> list[Block]:
    """One scene's converged pictures and its table."""
    truths = [e for e in part(run, SECTION, "truth") if e["scene"] == scene]
    out: list[Block] = [Heading(3, f"`{scene}`")]
    for truth in truths:
        p = truth["points"][0] if truth.get("points") else {}
        if "wall" not in p:
            out.append(Para(f"Converged picture by `{truth['name']}` failed: {truth.get('error')}"))
            continue
        out.append(Para(
            f"Converged picture: `{truth['name']}` (the fastest per sample) at "
            f"{p['size'][0]}x{p['size'][1]} with {p['samples']} samples per pixel, seed "
            f"{truth['seed']} ({figures.seconds_text(p['wall'])})."
        ))  # fmt: skip
        if p.get("image"):
            out.append(Picture(f"runs/{p['image']}", f"{scene}, converged", 200))
    body = [_row(e) for e in part(run, SECTION) if e["scene"] == scene]
    if body:
        out.append(Table(
            ["variant", "size", "samples/pixel", "RMSE at the most", "slope vs samples",
             "slope vs time", f"time to RMSE {TARGET_RMSE:g}"],
            body, right={3, 4, 5, 6},
        ))  # fmt: skip
    return out


def blocks(run: Run, plot: str | None, context: str, runs: Sequence[Run] = ()) -> list[Block]:
    """The section: what it measures, the plot, a part per scene, the refusals."""
    entries = [*part(run, SECTION, "truth"), *part(run, SECTION)]
    if not entries:
        return []
    out: list[Block] = [Heading(2, "Convergence: path-traced error against samples and time"),
                        Para(context), Para(ABOUT)]  # fmt: skip
    if plot is not None:
        out.append(Picture(plot, "RMSE against samples and against time, log-log"))
    for scene in dict.fromkeys(e["scene"] for e in entries):
        out += scene_blocks(run, scene)
    refused = {e["name"]: e["error"] for e in part(run, SECTION, "refused")}
    if refused:
        out.append(Para("Not path-traced (each variant's own line):"))
        out.append(Bullets([f"`{name}`: {why}" for name, why in refused.items()]))
    return out


def console_lines(run: Run) -> list[str]:
    lines = []
    for entry in part(run, SECTION):
        if entry["status"] == "ok" and entry.get("fit"):
            lines.append(
                f"convergence {entry['scene']:<12} {label(entry):<24} slope "
                f"{_slope(entry, 'samples'):>6} per sample, time to RMSE {TARGET_RMSE:g}: "
                f"{headline(entry)}"
            )
    return lines
