"""``rtc variants``: list the registered variants, the Tracer steps and book names each
overrides, and availability."""

from __future__ import annotations

import argparse
import textwrap
from collections import defaultdict

from groundwork.escapes import printable
from raytracer.api import BOOK_API
from variants.registry import Variant, registry

NAME = "variants"
INDENT = " " * 13
WIDTH = 100


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = (
        "Name variants as NAME, NAME[opt=value,flag] or NAME[...]:INNER, e.g. "
        "pooled[workers=2]:cached, with --variant (rtc kata, rtc render, pytest)."
    )
    parser.add_argument(
        "--markdown",
        action="store_true",
        help="print the project's own variants as a Markdown table (name, what it changes, the "
        "Tracer steps it overrides), as the README shows it",
    )


def markdown_table() -> str:
    """The project's own available variants, one row each: the name to use, what it changes,
    the ``Tracer`` steps it overrides (the README's table, checked against this by a test)."""
    lines = [
        "| variant | what it changes | the `Tracer` steps it overrides |",
        "| --- | --- | --- |",
    ]
    for entry in registry():
        v = entry.variant
        if v is None:
            continue
        steps = ", ".join(f"`{step}`" for step in v.steps) if v.tracer is not None else ""
        lines.append(f"| `{v.name}` | {v.summary} | {steps or 'none'} |")
    return "\n".join(lines)


def overrides_by_chapter(names: frozenset[str]) -> str:
    """``"ch 5: sphere; ch 9: plane, test_shape"`` (names outside the book API last)."""
    chapters: dict[int | None, list[str]] = defaultdict(list)
    for name in sorted(names):
        chapters[BOOK_API.get(name)].append(name)
    parts = [
        f"ch {chapter}: {', '.join(chapters[chapter])}"
        for chapter in sorted(c for c in chapters if c is not None)
    ]
    if None in chapters:
        parts.append(f"not in the book: {', '.join(chapters[None])}")
    return "; ".join(parts)


def _wrapped(text: str) -> list[str]:
    return textwrap.wrap(
        text, WIDTH, initial_indent=INDENT, subsequent_indent=INDENT + "  ", break_on_hyphens=False
    )


def _parts_wrapped(head: str, parts: list[str]) -> list[str]:
    """``head`` then the parts joined by "; ", breaking lines between parts."""
    lines = [head]
    for number, part in enumerate(parts):
        text = part + (";" if number < len(parts) - 1 else "")
        if lines[-1] != head and len(INDENT) + len(lines[-1]) + 1 + len(text) > WIDTH:
            lines.append("  " + text)
        else:
            lines[-1] += ("" if lines[-1] == head else " ") + text
    return [INDENT + line for line in lines]


def _standalone(v: Variant) -> list[str]:
    """A tracer that does not build on the reference (``rtc new``): what is written, what
    is still a stub, what is not defined."""
    # deferred: saves ~7 ms of rtc --help (variants.learner)
    from variants.learner import stub_names

    if v.overrides:
        lines = _parts_wrapped("written ", overrides_by_chapter(v.overrides).split("; "))
    else:
        lines = _wrapped("written: nothing yet")
    stubs = stub_names(v.api)
    if stubs:
        first = stubs[0]
        lines += _wrapped(f"stubs to write: {len(stubs)}, the first {first} (ch {BOOK_API[first]})")
    absent = [name for name in BOOK_API if name not in v.api]
    if absent:
        lines += _wrapped(f"not defined (undefined in rtc kata): {', '.join(absent)}")
    return lines


def describe(entry_name: str, v: Variant) -> list[str]:
    """The lines for one available variant."""
    lines = [f"{entry_name:<12} available   {v.summary}"]
    if v.name != entry_name:
        lines += _wrapped(f"default name: {v.name}")
    if v.tracer is not None:
        lines += _wrapped(f"tracer steps: {', '.join(v.steps) or 'none, the reference Tracer'}")
    if v.base is None and v.name != "naive":  # builds on nothing: e.g. a learner's own
        lines += _standalone(v)
    elif v.overrides:
        lines += _parts_wrapped("overrides ", overrides_by_chapter(v.overrides).split("; "))
        lines += _wrapped("inherits every other book name from the reference")
    elif v.name == "naive":
        lines += _wrapped("is the reference: every book name is its own")
    else:
        lines += _wrapped("overrides nothing: every book name is the reference's")
    lines += _wrapped(f"options: {v.usage}")
    return lines


def run(args: argparse.Namespace) -> int:
    if args.markdown:
        print(markdown_table())
        return 0
    for entry in registry(everything=True):
        if entry.variant is None:
            print(f"{entry.name:<12} unavailable {printable(entry.reason or '')}")
            continue
        print("\n".join(describe(entry.name, entry.variant)))
    return 0
