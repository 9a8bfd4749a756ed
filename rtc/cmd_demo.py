"""``rtc demo N``: draw chapter N's "putting it together" picture with the reference tracer."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from groundwork.images import FORMATS, write_image
from rtc.cli import UserError, check_memory, check_output, parse_size
from rtc.demos import DEMOS

NAME = "demo"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = "chapters:\n" + "\n".join(
        f"  {d.chapter:2d}  {d.title}" + (f" (default {d.size[0]}x{d.size[1]})" if d.size else "")
        for d in DEMOS.values()
    )
    parser.add_argument("chapter", metavar="N", help="the chapter, 1 to 16 (listed below)")
    parser.add_argument(
        "-o", "--output", metavar="OUT.png",
        help="where to write the picture (.png or .ppm; default demo-chNN.png here)",
    )  # fmt: skip
    parser.add_argument(
        "--size", metavar="WxH", help="canvas size in pixels, e.g. 200x100 (default per chapter)"
    )


def parse_chapter(text: str) -> int:
    """The chapter number; an unknown one is a ``UserError`` listing the known ones."""
    known = f"{min(DEMOS)} to {max(DEMOS)}"
    try:
        chapter = int(text)
    except ValueError:
        raise UserError(f"unknown chapter {text!r}: choose {known}") from None
    if chapter not in DEMOS:
        raise UserError(f"no demo for chapter {chapter}: choose {known}")
    return chapter


def run(args: argparse.Namespace) -> int:
    chapter = parse_chapter(args.chapter)
    demo = DEMOS[chapter]
    output = Path(args.output or f"demo-ch{chapter:02d}.png")
    if output.suffix.lower() not in FORMATS:
        raise UserError(
            f"cannot write {str(output)!r}: unknown image extension {output.suffix or '(none)'}; "
            f"use {' or '.join(FORMATS)}"
        )
    if demo.size is None:
        width = height = 0
        if args.size or args.output:
            print(
                f"chapter {chapter} prints its results and draws no picture; "
                "--size and -o are ignored"
            )
    else:
        width, height = parse_size(args.size) if args.size is not None else demo.size
        output = check_output(str(output) if args.output is None else args.output)
        check_memory("naive", width, height)
    size = f" at {width}x{height}" if demo.size else ""
    print(f"chapter {chapter}: {demo.title}{size}", flush=True)
    start = time.perf_counter()
    picture = demo.draw(width, height)
    elapsed = time.perf_counter() - start
    if picture is None:
        print(f"done in {elapsed:.2f} s")
        return 0
    try:
        write_image(picture, output)
    except OSError as error:
        raise UserError(f"cannot write {str(output)!r}: {error.strerror or error}") from None
    print(f"drew {width}x{height} in {elapsed:.2f} s -> {output}")
    return 0
