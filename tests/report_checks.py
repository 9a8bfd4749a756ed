"""What a report page may hold, whatever the run files said (``tests/test_hostile.py`` and
the fuzzers in ``tests/test_fuzz_parsers.py``): the report's own tags, links to its headings
or to files of the results folder, pictures only as embedded PNG images; in the Markdown, no
HTML outside code spans but the report's own pictures, no link elsewhere, no heading of a
run file's making."""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path

SAFE_TAGS = {"html", "head", "meta", "title", "style", "body", "h1", "h2", "h3", "h4", "h5",
             "h6", "p", "ul", "li", "table", "tr", "th", "td", "code", "strong", "em", "a",
             "img"}  # fmt: skip
SAFE_TARGET = re.compile(r"#[\w-]*|[A-Za-z0-9._+-]+(/[A-Za-z0-9._+-]+)*")
REPORT_PICTURE = re.compile(r'<img src="[A-Za-z0-9._+/-]+" alt="[^"<>]*" width="\d+">')
ATX_HEADING = re.compile(r" {0,3}#{1,6}(\s|$)")
MARKDOWN_LINK = re.compile(r"(?<!\\)\[((?:[^\]\\]|\\.)*)\]\(([^)]*)\)")


class Tags(HTMLParser):
    """Every start tag of an HTML page with its attributes."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))


def safe_target(target: str, results: Path) -> bool:
    if not SAFE_TARGET.fullmatch(target) or ".." in target.split("/"):
        return False
    return target.startswith("#") or (results / target).resolve().is_relative_to(
        results.resolve()
    )


def check_html(page: str, results: Path) -> None:
    parser = Tags()
    parser.feed(page)
    parser.close()
    for tag, attrs in parser.tags:
        assert tag in SAFE_TAGS, tag
        assert not any(name.startswith("on") for name in attrs), attrs
        if tag == "a":
            assert set(attrs) == {"href"} and safe_target(attrs["href"] or "", results), attrs
        if tag == "img":
            assert (attrs["src"] or "").startswith("data:image/png;base64,"), attrs


def outside_code(line: str) -> str:
    """``line`` without its code spans, backslash escapes written as ``_`` (CommonMark: a
    run of backticks opens a span that the next run of the same length closes; a backslash
    before ASCII punctuation makes it plain, except inside a span)."""
    out: list[str] = []
    at = 0
    while at < len(line):
        char = line[at]
        if char == "\\" and at + 1 < len(line) and line[at + 1] in PUNCTUATION:
            out.append("_")
            at += 2
        elif char == "`":
            run = len(line[at:]) - len(line[at:].lstrip("`"))
            close = re.compile(rf"(?<!`)`{{{run}}}(?!`)").search(line, at + run)
            if close is None:  # no span: the backticks are plain
                out.append("_" * run)
                at += run
            else:
                at = close.end()
        else:
            out.append(char)
            at += 1
    return "".join(out)


PUNCTUATION = set("!\"#$%&'()*+,-./:;<=>?@[\\]^_`{|}~")


def check_markdown(text: str, results: Path, headings: int) -> None:
    """``headings``: how many headings the report made (a line break in a name made more)."""
    lines = text.splitlines()
    for line in lines:
        outside = outside_code(REPORT_PICTURE.sub("", line))
        assert "<" not in outside, line
        for _label, target in MARKDOWN_LINK.findall(outside):
            assert safe_target(target, results), line
    assert sum(bool(ATX_HEADING.match(line)) for line in lines) == headings, text
