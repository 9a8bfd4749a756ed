"""What a profile is read into: cProfile's entries as rows labelled by file and function
(``collect``, ``summarize``) and the one-sentence finding of an entry (``findings``)."""

from __future__ import annotations

import cProfile
import gc
import sysconfig
import types
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from harness.engine.figures import seconds_text

CONSTRUCTORS = ("__init__", "__new__", "__post_init__")
ROOT = Path(__file__).resolve().parents[3]  # the project: labels are relative to it
STDLIB = Path(sysconfig.get_paths()["stdlib"]).resolve()

Row = dict[str, Any]


# ---------------------------------------------------------------------------- labels


def short_file(filename: str) -> str:
    """``filename`` relative to the project, the standard library or site-packages."""
    if filename in ("~", "") or filename.startswith("<"):
        return filename
    path = Path(filename)
    for base in (ROOT, STDLIB):
        try:
            return path.resolve().relative_to(base).as_posix()
        except ValueError:
            continue
    parts = path.parts
    if "site-packages" in parts:
        return "/".join(parts[parts.index("site-packages") + 1 :])
    return filename


def label(func: tuple[str, int, str]) -> str:
    """pstats' key ``(file, line, name)`` as ``file:line name`` (a built-in: its name)."""
    filename, line, name = func
    if filename == "~":
        return name
    return f"{short_file(filename)}:{line} {name}"


# ---------------------------------------------------------------------------- figures


Key = tuple[str, int, str]  # pstats' key of a function: (file, first line, name)


def _code_name(code: Any) -> str:
    """A code object's qualified name; for code that ``dataclasses`` generates (file
    ``<string>``, every class's ``__init__`` on line 2), its function's ``__qualname__``
    (``Tuple.__init__``), found among the code's referrers."""
    if code.co_filename == "<string>":
        for referrer in gc.get_referrers(code):
            if isinstance(referrer, types.FunctionType):
                return str(referrer.__qualname__)
    return str(getattr(code, "co_qualname", code.co_name))


def collect(profile: cProfile.Profile) -> dict[Key, tuple[Any, ...]]:
    """The profile as pstats' table ``{key: (cc, nc, tt, ct, callers)}`` (as
    ``Profile.snapshot_stats`` builds it), but keyed by qualified names: pstats keys a
    function by (file, line, name), under which every dataclass's generated ``__init__``
    is the same ``<string>:2 __init__``, and keeps one of them: the others' calls and time
    vanish from its figures. Functions with one key are added up."""
    entries = profile.getstats()
    keys: dict[int, Key] = {}
    for entry in entries:
        code = entry.code
        keys[id(code)] = (
            ("~", 0, code)
            if isinstance(code, str)
            else (code.co_filename, code.co_firstlineno, _code_name(code))
        )
    table: dict[Key, list[Any]] = {}
    for entry in entries:
        key = keys[id(entry.code)]
        nc, cc = entry.callcount, entry.callcount - entry.reccallcount
        row = table.setdefault(key, [0, 0, 0.0, 0.0, {}])
        row[0] += cc
        row[1] += nc
        row[2] += entry.inlinetime
        row[3] += entry.totaltime
    for entry in entries:
        caller = keys[id(entry.code)]
        for sub in entry.calls or ():
            callee = keys.get(id(sub.code))
            if callee is None:
                continue
            edges = table[callee][4]
            nc, cc = sub.callcount, sub.callcount - sub.reccallcount
            before = edges.get(caller, (0, 0, 0.0, 0.0))  # (nc, cc, tt, ct), as pstats has it
            edges[caller] = (
                before[0] + nc, before[1] + cc, before[2] + sub.inlinetime,
                before[3] + sub.totaltime,
            )  # fmt: skip
    return {key: tuple(row) for key, row in table.items()}


def _calls(nc: int, cc: int) -> str:
    """Calls as pstats prints them: ``total/primitive`` when some were recursive."""
    return str(nc) if nc == cc else f"{nc}/{cc}"


def _row(func: tuple[str, int, str], figures: tuple[Any, ...]) -> Row:
    cc, nc, tt, ct = figures[:4]
    return {"function": label(func), "calls": _calls(nc, cc), "own": tt, "cum": ct}


def _constructor_seconds(stats: Mapping[Any, Any]) -> float:
    """Own time in ``__init__``/``__new__``/``__post_init__`` plus what the built-ins they
    call directly (``object.__setattr__`` of a frozen dataclass ...) spent on their behalf."""

    def constructor(key: Key) -> bool:
        return key[0] != "~" and key[2].rsplit(".", 1)[-1] in CONSTRUCTORS

    total = 0.0
    for func, (_, _, tt, _, callers) in stats.items():
        if constructor(func):
            total += tt
        elif func[0] == "~":
            total += sum(edge[2] for caller, edge in callers.items() if constructor(caller))
    return total


def _hot_chain(stats: Mapping[Any, Any]) -> tuple[str, float] | None:
    """From the function with the most own time (a built-in: from its heaviest caller), up
    through its heaviest caller while that caller is in the same file: the function at the
    top of that chain and its cumulative seconds (what it and its callees cost)."""
    if not stats:
        return None
    current = max(stats, key=lambda f: stats[f][2])
    if current[0] == "~":
        callers = stats[current][4]
        known = [c for c in callers if c in stats]
        if not known:
            return label(current), float(stats[current][3])
        current = max(known, key=lambda c: callers[c][3])
    seen = {current}
    while True:
        callers = stats[current][4]
        same_file = [c for c in callers if c[0] == current[0] and c not in seen and c in stats]
        if not same_file:
            break
        heaviest = max(same_file, key=lambda c: callers[c][3])
        seen.add(heaviest)
        current = heaviest
    return label(current), float(stats[current][3])


def summarize(table: Mapping[Key, tuple[Any, ...]], top: int) -> dict[str, Any]:
    """What a cProfile run shows (``collect``'s table): totals, the ``top`` functions by
    own and by cumulative time, and the figures ``findings`` reads (the hot chain, the
    constructors, how spread the time is)."""
    total = float(sum(row[2] for row in table.values()))
    by_own = sorted(table.items(), key=lambda item: item[1][2], reverse=True)
    by_cum = sorted(table.items(), key=lambda item: item[1][3], reverse=True)
    covered, half = 0.0, 0
    for _, figures in by_own:
        if covered >= total / 2:
            break
        covered += figures[2]
        half += 1
    hot = _hot_chain(table)
    return {
        "total": total,
        "calls": int(sum(row[1] for row in table.values())),
        "functions": len(table),
        "top_own": [_row(f, v) for f, v in by_own[:top]],
        "top_cum": [_row(f, v) for f, v in by_cum[:top]],
        "hot": None if hot is None else {"function": hot[0], "cum": hot[1]},
        "constructors": _constructor_seconds(table),
        "half": half,
    }


def _share(part: float, whole: float) -> str:
    return f"{100 * part / whole:.0f}%" if whole > 0 else "-"


def _function_name(text: str) -> str:
    """``raytracer/matrices.py:139 inverse`` -> ```inverse()` (raytracer/matrices.py)``."""
    where, _, name = text.partition(" ")
    if not name:
        return f"`{text}`"
    file = where.rsplit(":", 1)[0]
    return f"`{name}()` ({'written by dataclasses' if file == '<string>' else file})"


STAGE_NAMES = {
    "load": "load (scene file)",
    "prepare": "prepare",
    "pack": "pack (world to arrays, hierarchy)",
    "compile": "compile or cache load",
    "trace": "trace (render_into)",
    "render": "render (the API's render)",
    "encode": "encode (PNG)",
}


def findings(entry: Mapping[str, Any]) -> str:
    """One sentence read off a profile's figures: for a profiled render, where its time
    went (the hot chain, constructors, how spread the time is, calls per pixel); for a
    compiled one, its stages."""
    name = entry.get("name", "?")
    profile = entry.get("cprofile")
    if profile and profile.get("total"):
        total = profile["total"]
        parts: list[str] = []
        hot = profile.get("hot")
        if hot:
            parts.append(
                f"{_share(hot['cum'], total)} of the render in {_function_name(hot['function'])} "
                "and its callees"
            )
        top_own = profile.get("top_own") or []
        if top_own:
            first = top_own[0]
            parts.append(
                f"the top function by own time, `{first['function']}`, holds "
                f"{_share(first['own'], total)}, and {profile['half']} of "
                f"{profile['functions']} functions make{'s' if profile['half'] == 1 else ''} up "
                "half of it"
            )
        built = _share(profile["constructors"], total)
        parts.append(f"{built} building objects (`__init__`, `__new__`)")
        pixels = entry.get("pixels") or 0
        if pixels:
            parts.append(f"{profile['calls'] / pixels:,.0f} function calls per pixel")
        return f"{name}: " + "; ".join(parts) + "."
    stages = entry.get("stages")
    if stages:
        wall = entry.get("wall") or sum(stages.values())
        order = sorted(stages.items(), key=lambda item: item[1], reverse=True)
        spelled = ", ".join(f"{STAGE_NAMES.get(k, k)} {_share(v, wall)}" for k, v in order)
        text = f"{name}: of {seconds_text(wall)}, {spelled}"
        if "trace_again" in entry and "trace" in stages:
            text += f"; a second trace took {seconds_text(entry['trace_again'])}"
        if entry.get("kernels"):
            text += f"; compiled code {entry['kernels']}"
        return text + "."
    return f"{name}: no figures ({entry.get('error', 'not measured')})."
