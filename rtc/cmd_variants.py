"""``rtc variants``: list the registered variants, what each overrides, and availability."""

from __future__ import annotations

import argparse

from raytracer.api import BOOK_API
from variants.registry import registry

NAME = "variants"
HELP = "list the registered variants, what each overrides, and whether it is available"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    del parser  # no options


def _chapters(names: frozenset[str]) -> str:
    chapters = sorted({BOOK_API[name] for name in names if name in BOOK_API})
    return ", ".join(str(c) for c in chapters) if chapters else "nothing (the reference)"


def run(args: argparse.Namespace) -> int:
    del args
    for entry in registry():
        if entry.variant is None:
            print(f"{entry.name:<12} unavailable: {entry.reason}")
            continue
        v = entry.variant
        print(f"{v.name:<12} {v.summary}")
        overrides = ", ".join(sorted(v.overrides)) or "-"
        print(f"{'':<12} overrides chapters {_chapters(v.overrides)}: {overrides}")
    return 0
