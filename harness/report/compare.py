"""Two bench runs compared, row by row, and the history of each variant across runs.

A row of one run is compared with the row of the other run measured the same way: the same
section, scene (or mesh), variant, canvas size and samples per pixel. Its timed renders (the
run file keeps each one's wall time) go through the test ``pyperf compare_to`` applies:
Student's two-sample t-test with a pooled variance, two-tailed, at the 95% level; the ratio is
the mean of B over the mean of A (pyperf's). A row with one timed render on either side is not
tested: a single value has no spread to test against.

``rtc compare`` prints the table; ``rtc bench --compare-to RUN --fail-slower PCT`` fails on a
row significantly slower by more than PCT percent; the report's History plots each variant's
time per pixel across runs with the significant changes marked.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from groundwork.files import describe
from harness.engine import figures
from harness.engine.results import (
    LONGEST_SECONDS,
    ResultFileError,
    list_runs,
    load_run,
    number_problem,
    runs_dir,
)

Run = Mapping[str, Any]

ALPHA = 0.05  # two-tailed: significant when |t| is at least Student's t quantile 0.975
TEST_NAME = (
    "Student's two-sample t-test on the timed renders' wall times (pooled variance, "
    f"two-tailed, significant at p < {ALPHA:g}, i.e. 95%), as pyperf compare_to"
)
ALIASES = ("latest", "previous")


class RunChoiceError(ValueError):
    """A run that cannot be found or read, or a bad threshold: one line for the user."""


# ----------------------------------------------------------------- the test


@dataclass(frozen=True, slots=True)
class TTest:
    """Student's two-sample t-test of two samples: ``t`` > 0 when the second is slower;
    ``p`` None (not tested) when a side has one value."""

    t: float | None
    df: int
    p: float | None

    @property
    def tested(self) -> bool:
        return self.p is not None

    @property
    def significant(self) -> bool:
        return self.p is not None and self.p < ALPHA


def two_tailed_p(t: float, df: int) -> float:
    """The probability of a Student's t with ``df`` degrees of freedom beyond ``±t``: the
    regularized incomplete beta function I_{df/(df+t²)}(df/2, 1/2)."""
    if math.isinf(t):
        return 0.0
    # deferred: saves ~115 ms (mpmath) of rtc report and compare when no t-test is due
    import mpmath

    x = df / (df + t * t)
    return float(mpmath.betainc(df / 2, 0.5, 0, x, regularized=True))


def t_test(a: Sequence[float], b: Sequence[float]) -> TTest:
    """Student's two-sample t-test (pooled variance) of ``b`` against ``a``."""
    na, nb = len(a), len(b)
    df = na + nb - 2
    if na < 2 or nb < 2:
        return TTest(None, df, None)
    mean_a, mean_b = statistics.fmean(a), statistics.fmean(b)
    squares = math.fsum((x - mean_a) ** 2 for x in a) + math.fsum((x - mean_b) ** 2 for x in b)
    spread = math.sqrt(squares / df * (1 / na + 1 / nb))
    diff = mean_b - mean_a
    if spread > 0:
        return TTest(diff / spread, df, two_tailed_p(diff / spread, df))
    # every render of both sides took the same time: no spread, any difference is certain
    t = 0.0 if diff == 0 else math.copysign(math.inf, diff)
    return TTest(t, df, two_tailed_p(t, df))


# ----------------------------------------------------------------- what a run measured


@dataclass(frozen=True, slots=True)
class RowKey:
    """What a measurement is of; two runs' measurements compare when their keys are equal."""

    section: str
    scene: str
    name: str
    size: tuple[int, int]
    samples: int

    @property
    def place(self) -> tuple[str, str, str, int]:
        """The key without the size: the same variant measured, perhaps at another size."""
        return self.section, self.scene, self.name, self.samples

    @property
    def size_text(self) -> str:
        return f"{self.size[0]}x{self.size[1]}"

    def label(self) -> str:
        where = "" if self.section == "table" else f" [{self.section}]"
        return f"{self.name}{where}"


@dataclass(frozen=True, slots=True)
class Measured:
    key: RowKey
    walls: tuple[float, ...]
    error: Mapping[str, Any] | None = None  # the row's error_vs_naive
    busy: bool = False

    @property
    def mean(self) -> float:
        return statistics.fmean(self.walls)

    @property
    def pixels(self) -> int:
        return self.key.size[0] * self.key.size[1]

    @property
    def per_pixel(self) -> float:
        """Mean seconds per pixel (of its samples per pixel)."""
        return self.mean / self.pixels

    def spread_text(self) -> str:
        mean = figures.seconds_text(self.mean)
        if len(self.walls) < 2:
            return f"{mean} (1 render)"
        return f"{mean} ± {figures.seconds_text(statistics.stdev(self.walls))}"


def _walls(values: Any, where: str) -> tuple[float, ...]:
    """Timed renders' wall times, each a number of seconds above 0 (and below
    ``LONGEST_SECONDS``); a ``ValueError`` naming ``where`` for anything else: a negative,
    NaN or huge time would make a comparison that looks right and is not."""
    walls = []
    for i, value in enumerate(values):
        wall = float(value) if isinstance(value, int | float) else math.nan
        if not 0 < wall < LONGEST_SECONDS:
            raise ValueError(f"{where}[{i}] is {value!r}, not a time in seconds")
        walls.append(wall)
    return tuple(walls)


def measurements(run: Run) -> list[Measured]:
    """Every measurement of ``run`` with its timed renders: the rows (table, preset,
    threads) and the scene-size section's renders per mesh, in the run's order."""
    found: list[Measured] = []
    seen: set[RowKey] = set()

    def add(item: Measured) -> None:
        if item.walls and item.key not in seen:
            seen.add(item.key)
            found.append(item)

    for index, row in enumerate(run.get("rows") or []):
        if row.get("status") == "ok" and row.get("wall") == []:
            raise ValueError(f"rows[{index}].wall is empty: a measured row without a time")
        if row.get("status") != "ok" or not row.get("wall") or row.get("reused"):
            continue  # a reused row is another section's measurement
        w, h = row["size"]
        key = RowKey(
            str(row["section"]), str(row.get("scene", "")), str(row["name"]),
            (int(w), int(h)), int(row.get("samples") or 1),
        )  # fmt: skip
        walls = _walls(row["wall"], f"rows[{index}].wall")
        error = row.get("error_vs_naive")
        error = error if isinstance(error, Mapping) else None
        add(Measured(key, walls, error, figures.is_busy(row)))
    settings = run.get("settings") or {}
    size = settings.get("size") or [0, 0]
    for number, entry in enumerate(run.get("series") or []):
        if entry.get("section") != "scene-size":
            continue
        for at, point in enumerate(entry.get("points") or []):
            if not point.get("render"):
                continue
            key = RowKey(
                "scene-size", str(point.get("mesh", "")), str(entry["name"]),
                (int(size[0]), int(size[1])), int(settings.get("samples") or 1),
            )  # fmt: skip
            add(Measured(key, _walls(point["render"], f"series[{number}].points[{at}].render")))
    return found


# ----------------------------------------------------------------- two runs


@dataclass(frozen=True, slots=True)
class Change:
    """One measurement in both runs: B's time against A's. Measured at two sizes (the
    budget rule picks a slow variant's size per run), the ratio is per pixel, not tested."""

    a: Measured
    b: Measured
    test: TTest

    @property
    def same_size(self) -> bool:
        return self.a.key.size == self.b.key.size

    @property
    def ratio(self) -> float:
        if self.same_size:
            return self.b.mean / self.a.mean
        return self.b.per_pixel / self.a.per_pixel

    @property
    def verdict(self) -> str:
        if not self.test.tested:
            return "not tested"
        if not self.test.significant:
            return "not significant"
        return "slower" if self.ratio > 1 else "faster"

    def ratio_text(self) -> str:
        if self.ratio >= 1:
            return f"{self.ratio:.2f}x slower" if self.ratio != 1 else "same"
        return f"{1 / self.ratio:.2f}x faster"

    def test_text(self) -> str:
        if not self.same_size:
            return "- (sizes differ)"
        if self.test.t is None or self.test.p is None:
            n = min(len(self.a.walls), len(self.b.walls))
            return f"- ({n} render{'s' if n != 1 else ''})"
        p = "p < 0.001" if self.test.p < 0.001 else f"p={self.test.p:.3f}"
        return f"t={self.test.t:.2f}, {p}"


def compare_measured(a: Measured, b: Measured) -> Change:
    """``b`` against ``a``: their wall times tested when measured at one size; at two sizes
    the ratio is per pixel and untested (a fixed cost, a pool's start-up or a kernel's
    dispatch, does not scale with the pixels, so per-pixel times of two sizes differ even
    when the code did not change)."""
    if a.key.size == b.key.size:
        return Change(a, b, t_test(a.walls, b.walls))
    return Change(a, b, TTest(None, len(a.walls) + len(b.walls) - 2, None))


@dataclass(frozen=True, slots=True)
class Comparison:
    a: Run
    b: Run
    changes: list[Change]
    only_a: list[Measured] = field(default_factory=list)
    only_b: list[Measured] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def with_verdict(self, verdict: str) -> list[Change]:
        return [c for c in self.changes if c.verdict == verdict]


SETTINGS_COMPARED = ("depth", "seed", "epsilon")


def _setting_notes(a: Run, b: Run) -> list[str]:
    notes = []
    sa, sb = a.get("settings") or {}, b.get("settings") or {}
    for key in SETTINGS_COMPARED:
        if sa.get(key) != sb.get(key):
            notes.append(f"the runs differ in {key}: {sa.get(key)} (A) against {sb.get(key)} (B)")
    ma, mb = a.get("machine") or {}, b.get("machine") or {}
    machine_a = (ma.get("hostname"), ma.get("cpu_model"), ma.get("cores_available"))
    machine_b = (mb.get("hostname"), mb.get("cpu_model"), mb.get("cores_available"))
    if machine_a != machine_b:
        notes.append(
            f"measured on different machines ({ma.get('hostname')}, {ma.get('cpu_model')}, "
            f"{ma.get('cores_available')} cores against {mb.get('hostname')}, "
            f"{mb.get('cpu_model')}, {mb.get('cores_available')} cores): the times compare "
            "the machines as much as the code"
        )
    return notes


def compare_runs(a: Run, b: Run) -> Comparison:
    """Every measurement of ``b`` matched with ``a``'s (in ``b``'s order): the same key, or
    the same variant measured at another size (compared per pixel)."""
    in_a = {m.key: m for m in measurements(a)}
    places_a: dict[tuple[str, str, str, int], Measured] = {}
    for m in in_a.values():
        places_a.setdefault(m.key.place, m)
    changes: list[Change] = []
    only_b: list[Measured] = []
    matched: set[RowKey] = set()
    for m in measurements(b):
        other = in_a.get(m.key) or places_a.get(m.key.place)
        if other is None or other.key in matched:
            only_b.append(m)
            continue
        changes.append(compare_measured(other, m))
        matched.add(other.key)
    only_a = [m for key, m in in_a.items() if key not in matched]
    return Comparison(a, b, changes, only_a, only_b, _setting_notes(a, b))


def slower_than(comparison: Comparison, percent: float) -> list[Change]:
    """The gate: the changes significantly slower by more than ``percent`` percent (only
    rows measured at one size in both runs are tested)."""
    limit = 1 + percent / 100
    return [c for c in comparison.changes if c.verdict == "slower" and c.ratio > limit]


def gate_line(change: Change, percent: float, base: Run) -> str:
    k = change.a.key
    return (
        f"{k.label()} ({k.scene}, {k.size_text}, {k.samples} spp): "
        f"{change.ratio:.2f}x the time of run {base.get('stem')} ({change.a.spread_text()} -> "
        f"{change.b.spread_text()}; {change.test_text()}), over the {percent:g}% allowed"
    )


# ----------------------------------------------------------------- the printed table


def run_line(label: str, run: Run) -> str:
    m = run.get("machine") or {}
    commit = (m.get("commit") or "unknown")[:8] + (" dirty" if m.get("dirty") else "")
    started = str(run.get("started", ""))[:16].replace("T", " ")
    mode = ((run.get("settings") or {}).get("mode") or {}).get("name", "?")
    return (
        f"{label} = {run.get('stem')} (commit {commit}, {started} UTC, {mode}, {m.get('hostname')})"
    )


def _psnr(error: Mapping[str, Any]) -> str:
    return "∞" if error.get("psnr") is None else f"{error['psnr']:.1f}"


def error_text(change: Change) -> str:
    """The picture's PSNR against naive's in A and in B, where both runs measured it at the
    same comparison size (RMSE = 10^(-PSNR/20) for colours in [0, 1])."""
    ea, eb = change.a.error, change.b.error
    if change.a.key.name == "naive":
        return "(the reference)"
    if not ea or not eb:
        return "-"
    if ea.get("size") != eb.get("size"):
        return f"at {ea.get('size')} / {eb.get('size')}: not compared"
    if ea.get("rmse") == eb.get("rmse"):
        return f"{_psnr(ea)} dB (same)"
    return f"{_psnr(ea)} -> {_psnr(eb)} dB"


VERDICT_ORDER = {"slower": 0, "faster": 1, "not significant": 2, "not tested": 3}


def _size_text(change: Change) -> str:
    a, b = change.a.key, change.b.key
    spp = f" {a.samples}spp" if a.samples != 1 else ""
    if change.same_size:
        return a.size_text + spp
    return f"{a.size_text} / {b.size_text}{spp}"


def _aligned(header: list[str], body: list[list[str]], right: set[int]) -> list[str]:
    widths = [max(len(r[i]) for r in [header, *body]) for i in range(len(header))]
    lines = []
    for r in [header, ["-" * w for w in widths], *body]:
        cells = [c.rjust(widths[i]) if i in right else c.ljust(widths[i]) for i, c in enumerate(r)]
        lines.append("  ".join(cells).rstrip())
    return lines


def in_words(comparison: Comparison) -> str:
    """Which run is faster, in a sentence: the geometric mean of B's time over A's across
    the measurements both runs made (per pixel where their sizes differ), and how many
    changes were significant each way."""
    ratios = [c.ratio for c in comparison.changes if c.ratio > 0 and math.isfinite(c.ratio)]
    if not ratios:
        return "Neither run is faster: they measured nothing in common."
    mean = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
    a, b = (f"{label} ({run.get('stem')})" for label, run in (("A", comparison.a),
                                                              ("B", comparison.b)))  # fmt: skip
    counts = (
        f"{len(comparison.with_verdict('faster'))} significantly faster in B, "
        f"{len(comparison.with_verdict('slower'))} significantly slower in B"
    )
    over = f"over the {len(ratios)} measurement{'s' * (len(ratios) != 1)} both made"
    if abs(mean - 1) < 0.005:
        return f"Neither run is faster: B's times are A's, geometric mean {over} ({counts})."
    faster, slower = (b, a) if mean < 1 else (a, b)
    factor = 1 / mean if mean < 1 else mean
    return (
        f"{faster} is faster than {slower}: {factor:.2f}x, the geometric mean {over} "
        f"({counts})."
    )


def table_lines(comparison: Comparison) -> list[str]:
    """The comparison as a plain-text table, slower first, then the totals and the notes;
    first which run is faster, in words."""
    lines = [
        run_line("A", comparison.a),
        run_line("B", comparison.b),
        in_words(comparison),
        f"Test: {TEST_NAME}. B against A: B's mean time over A's, in words (B 1.50x slower: "
        "B took 1.5 times as long).",
    ]
    lines += [f"Note: {note}." for note in comparison.notes]
    header = ["variant", "scene", "size (A / B)", "A: mean ± sd", "B: mean ± sd", "B against A",
              "t-test", "verdict", "PSNR vs naive (A -> B)"]  # fmt: skip
    body = []
    for c in sorted(comparison.changes, key=lambda c: VERDICT_ORDER[c.verdict]):
        marks = ("" if c.same_size else " *") + (" (busy)" if c.a.busy or c.b.busy else "")
        body.append([c.a.key.label(), c.a.key.scene, _size_text(c), c.a.spread_text(),
                     c.b.spread_text(), _b_text(c), c.test_text(), c.verdict + marks,
                     error_text(c)])  # fmt: skip
    if body:
        lines += _aligned(header, body, {3, 4, 5})
    else:
        lines.append("No measurement in common (the same section, scene, variant and samples).")
    counts = {v: len(comparison.with_verdict(v)) for v in VERDICT_ORDER}
    lines.append(
        f"{len(comparison.changes)} compared: {counts['slower']} slower, {counts['faster']} "
        f"faster, {counts['not significant']} not significant, {counts['not tested']} not "
        "tested (measured at two sizes, or one timed render on a side)."
    )
    if any(not c.same_size for c in comparison.changes):
        lines.append(
            "*: measured at two sizes (another --size, or the budget rule sizing a slow "
            "variant per run; --budget 0 and one --size avoid it): B against A is per pixel, not "
            "tested, since a fixed cost (a pool's start-up, a frame's preparation) does not "
            "scale with the pixels."
        )
    if any(c.a.busy or c.b.busy for c in comparison.changes):
        lines.append(
            f"(busy): a side got under {figures.BUSY_SHARE:.0%} of the cores it asked for; "
            "its time says as much about the machine's load as about the code."
        )
    for label, items in (("A", comparison.only_a), ("B", comparison.only_b)):
        if items:
            names = ", ".join(f"{m.key.label()} ({m.key.scene})" for m in items[:12])
            more = f" and {len(items) - 12} more" if len(items) > 12 else ""
            lines.append(f"Only in {label}: {names}{more}.")
    return lines


def _b_text(change: Change) -> str:
    text = change.ratio_text()
    return text if text == "same" else f"B {text}"


def gate(base: Run, new: Run, percent: float | None) -> tuple[list[str], list[str]]:
    """``rtc bench --compare-to``: the comparison's lines, and one line per variant that
    fails ``--fail-slower percent`` (none when ``percent`` is None)."""
    comparison = compare_runs(base, new)
    lines = ["", f"Compared with {base.get('stem')}:", *table_lines(comparison)]
    if percent is None:
        return lines, []
    failing = [gate_line(c, percent, base) for c in slower_than(comparison, percent)]
    tested = [c for c in comparison.changes if c.test.tested]
    lines.append(
        f"Gate: {len(failing)} of {len(tested)} tested variants significantly slower by more "
        f"than {percent:g}%."
    )
    return lines, failing


# ----------------------------------------------------------------- choosing runs


def parse_percent(text: str) -> float:
    """``25%`` or ``25`` -> 25.0; a ``ValueError`` naming the text otherwise."""
    stripped = text.strip().removesuffix("%").strip()
    try:
        value = float(stripped)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"{text!r}: expected a percentage of 0 or more, such as 25%")
    return value


def resolve_run(spec: str, results: Path) -> Path:
    """A run file from ``spec``: a path, a run's stem (``bench-2026...``, in
    ``results/runs/``), ``latest`` or ``previous`` (the newest and the one before it)."""
    if spec in ALIASES:
        runs = list_runs(results)
        index = ALIASES.index(spec)
        if len(runs) <= index:
            raise RunChoiceError(
                f"{spec}: {runs_dir(results)} holds {len(runs)} run file"
                f"{'s' if len(runs) != 1 else ''}; run `rtc bench` first"
            )
        return runs[-1 - index]
    path = Path(spec)
    if path.is_file():
        return path
    odd = describe(path)  # a named pipe, a device: no run file, and never waited on
    if odd is not None:
        raise RunChoiceError(f"{spec}: {odd}")
    stem = spec.removesuffix(".json")
    candidate = runs_dir(results) / f"{stem}.json"
    if "/" not in spec and candidate.is_file():
        return candidate
    raise RunChoiceError(
        f"{spec}: no such run file (give a path, a run's name in {runs_dir(results)}, "
        "latest or previous)"
    )


def load(spec: str, results: Path) -> dict[str, Any]:
    """The ``rtc`` section of the run ``spec`` names; ``RunChoiceError`` if it cannot."""
    path = resolve_run(spec, results)
    try:
        run = load_run(path)["rtc"]
    except ResultFileError as error:
        raise RunChoiceError(str(error)) from None
    if run.get("kind") or not isinstance(run.get("rows"), list):
        kind = f"a {run['kind']} run" if run.get("kind") else "no rows"
        raise RunChoiceError(f"{path}: not a bench run ({kind}); rtc compare reads rtc bench's")
    try:
        why = number_problem(run, "")  # NaN, infinity, 1e300: no measurement
    except RecursionError:
        why = "values nested too deep to check"
    if why is not None:
        raise RunChoiceError(f"{path}: {why}")
    try:
        measurements(run)
    except (KeyError, TypeError, ValueError, IndexError) as error:
        raise RunChoiceError(
            f"{path}: a row the comparison cannot read ({type(error).__name__}: {error})"
        ) from None
    return run


# ----------------------------------------------------------------- history


@dataclass(frozen=True, slots=True)
class HistoryPoint:
    """One run's measurement of a variant; ``change`` against the variant's previous point,
    from run ``previous`` (None for the first point, or when the previous one was measured at
    another size)."""

    run: int  # index into the runs
    measured: Measured
    change: Change | None
    previous: int | None = None


@dataclass(frozen=True, slots=True)
class HistorySeries:
    scene: str
    name: str
    samples: int
    points: list[HistoryPoint]


def history(runs: Sequence[Run]) -> list[HistorySeries]:
    """Each table variant (scene, name, samples) across ``runs`` (oldest first), with every
    point tested against the variant's previous one where both were measured at one size."""
    series: dict[tuple[str, str, int], list[HistoryPoint]] = {}
    for index, run in enumerate(runs):
        for m in measurements(run):
            if m.key.section != "table":
                continue
            points = series.setdefault((m.key.scene, m.key.name, m.key.samples), [])
            before = points[-1] if points else None
            if before is not None and before.measured.key == m.key:
                change = compare_measured(before.measured, m)
                points.append(HistoryPoint(index, m, change, before.run))
            else:
                points.append(HistoryPoint(index, m, None))
    return [HistorySeries(s, n, k, p) for (s, n, k), p in series.items()]


def commit_label(run: Run) -> str:
    """A run's short commit, ``*`` when the tree was dirty."""
    m = run.get("machine") or {}
    return (m.get("commit") or "unknown")[:7] + ("*" if m.get("dirty") else "")
