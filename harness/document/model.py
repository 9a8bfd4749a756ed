"""A tiny document model written out as Markdown and as one self-contained HTML page, each
by a Jinja2 template (``templates/``) whose environment escapes every value it prints.

Text uses three inline marks, the same in both outputs: ```code```, ``**bold**`` and
``[text](path)``, a link (a path relative to the results folder, or ``#anchor``: a heading of
the same page, ``anchor(heading text)``, as GitHub names it). Images are paths relative to the
results folder: linked from the Markdown, inlined (base64) in the HTML.
"""

from __future__ import annotations

import base64
import html
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import jinja2
from markupsafe import Markup

from groundwork.files import read_bytes


@dataclass
class Heading:
    level: int
    text: str


@dataclass
class Para:
    text: str


@dataclass
class Bullets:
    items: list[str]


@dataclass
class Table:
    header: list[str]
    rows: list[list[str]]
    right: set[int] = field(default_factory=set)  # columns aligned right (numbers)
    compact: bool = False  # HTML: a smaller font (a table that must fit the first screen)


@dataclass
class Picture:
    """One image: ``path`` relative to the results folder; ``width`` in CSS pixels."""

    path: str
    alt: str
    width: int | None = None


@dataclass
class Gallery:
    """Rows of captioned pictures shown side by side: [(caption, [Picture, ...]), ...]."""

    header: list[str]
    rows: list[tuple[str, list[Picture | None]]]


Block = Heading | Para | Bullets | Table | Picture | Gallery


def anchor(text: str) -> str:
    """A heading's anchor as GitHub makes it from its text (lower case, punctuation but
    hyphens dropped, spaces as hyphens); the HTML page gives its headings the same ids, so
    ``[text](#anchor)`` links work in both."""
    plain = re.sub(r"[`*]", "", text).strip().lower()
    plain = re.sub(r"[^\w\- ]", "", plain)
    return plain.replace(" ", "-")


MAX_PICTURE_BYTES = 64 * 1024 * 1024  # a larger file in the results folder is no plot of ours
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_SAFE_PATH = re.compile(r"[A-Za-z0-9._+-]+(/[A-Za-z0-9._+-]+)*")
_SAFE_ANCHOR = re.compile(r"#[\w-]*")
_MARKS = re.compile(
    r"`(?P<code>[^`]+)`"
    r"|\[(?P<label>[^\]]+)\]\((?P<target>[^)\s]+)\)"
    r"|\*\*(?P<bold>[^*]+)\*\*"
)
# CommonMark: a backslash before ASCII punctuation makes it a plain character. Text from a
# run file must not open a link (``[``), close one, start a code span or escape our escapes.
_MD_PUNCTUATION = {ord(c): "\\" + c for c in "\\[]`"}


def _inside(folder: Path | None, relative: str) -> bool:
    """Whether ``relative`` is a plain relative path (letters, digits, ``._+-``, no ``..``)
    that stays inside ``folder`` once links are followed (``folder`` None: the spelling
    alone)."""
    if not _SAFE_PATH.fullmatch(relative) or ".." in relative.split("/"):
        return False
    if folder is None:
        return True
    try:
        return (folder / relative).resolve().is_relative_to(folder.resolve())
    except (OSError, RuntimeError):  # a symbolic link loop
        return False


def _safe_target(folder: Path | None, target: str) -> bool:
    """A link may go to a heading of the page (``#anchor``) or a file of the results folder."""
    return bool(_SAFE_ANCHOR.fullmatch(target)) or _inside(folder, target)


@dataclass(frozen=True)
class Span:
    """A piece of text with its mark: ``kind`` is ``text``, ``code``, ``bold`` (``inner``
    holds its spans) or ``link`` (``inner`` its label, ``target`` a checked target)."""

    kind: str
    text: str = ""
    inner: tuple[Span, ...] = ()
    target: str = ""


def spans(text: str, folder: Path | None) -> list[Span]:
    """``text`` read as its inline marks; a link that leaves the results folder is kept as
    its label followed by its target in parentheses, as plain text."""
    out: list[Span] = []
    at = 0
    for match in _MARKS.finditer(text):
        if match.start() > at:
            out.append(Span("text", text[at : match.start()]))
        at = match.end()
        if match["code"] is not None:
            out.append(Span("code", match["code"]))
        elif match["bold"] is not None:
            out.append(Span("bold", inner=tuple(spans(match["bold"], folder))))
        elif _safe_target(folder, match["target"]):
            label = tuple(spans(match["label"], folder))
            out.append(Span("link", inner=label, target=match["target"]))
        else:
            out += [*spans(match["label"], folder), Span("text", f" ({match['target']})")]
    if at < len(text):
        out.append(Span("text", text[at:]))
    return out


def _png_data(folder: Path, relative: str) -> bytes | str:
    """The bytes of the PNG ``relative`` names in ``folder``, or why it is not shown: only a
    regular file inside the results folder (links followed), of a bounded size, that is a
    PNG, is embedded."""
    if not _inside(folder, relative):
        return "not a file of the results folder"
    try:
        data = read_bytes(folder / relative, MAX_PICTURE_BYTES)
    except FileNotFoundError:
        return "missing"
    except OSError as error:
        return f"cannot be read: {error.strerror or error}"
    if not data.startswith(PNG_SIGNATURE):
        return "not a PNG image"
    return data


def _embedded(folder: Path, picture: Picture) -> tuple[str, str]:
    """(the picture as a ``data:`` address, "") or ("", why it is not shown)."""
    data = _png_data(folder, picture.path)
    if isinstance(data, str):
        return "", data
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii"), ""


# -------------------------------------------------------------- the Markdown's escaping


def _one_line(text: str) -> str:
    """``text`` with every line break a space: a name read from a run file cannot start a
    heading or a new block of the Markdown (in a paragraph a line break is a space anyway)."""
    return " ".join(text.splitlines())


def _md_text(value: object) -> str:
    """The Markdown environment's escaping (its ``finalize``): a value printed as it is
    becomes plain text, on one line, with HTML's special characters as entities (GitHub's
    Markdown shows ``&lt;`` as ``<``) and CommonMark's link and code characters after a
    backslash. A value the template marked ``Markup`` is Markdown already."""
    if isinstance(value, Markup):
        return value
    return html.escape(_one_line(str(value)), quote=False).translate(_MD_PUNCTUATION)


_BLOCK_START = re.compile(r"(#{1,6}|[-+*]|\d{1,9}(?=[.)]))(?=[.)]?(\s|$))")


def _md_block(rendered: str) -> Markup:
    """A paragraph's, a heading's or a list item's Markdown, which must not start another
    block: a leading ``#`` (a heading), ``-``, ``+``, ``*`` or ``1.`` (a list) from a name is
    escaped, and leading blanks (code) dropped."""
    rendered = str(rendered).lstrip()
    match = _BLOCK_START.match(rendered)
    if match is None:
        return Markup(rendered)
    end = match.end(1)
    if rendered[:end].isdigit():  # 1. or 1): the dot or parenthesis makes the list
        return Markup(f"{rendered[:end]}\\{rendered[end:]}")
    return Markup("\\" + rendered)


def _md_cell(rendered: str) -> Markup:
    """A table cell's Markdown: a ``|`` inside (even in code) would end the cell."""
    return Markup(str(rendered).replace("|", "\\|"))


def _md_code(code: str) -> Markup:
    """A code span's text: on one line, nothing escaped (a backslash is plain in code)."""
    return Markup(_one_line(code))


def _md_attribute(text: str) -> Markup:
    """The ``alt`` of a picture the Markdown shows as an HTML ``<img>``."""
    return Markup(html.escape(_one_line(text)))


# ------------------------------------------------------------------------ the writers


def _is(kind: type) -> Callable[[object], bool]:
    return lambda value: isinstance(value, kind)


@cache
def _templates(markdown: bool) -> jinja2.Environment:
    """The environment of one output: HTML autoescaped by Jinja2 (MarkupSafe), the Markdown
    through ``_md_text``; every block kind a test (``block is table``)."""
    environment = jinja2.Environment(
        loader=jinja2.PackageLoader("harness.document", "templates"),
        autoescape=not markdown,
        finalize=_md_text if markdown else None,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )
    kinds = {"heading": Heading, "para": Para, "bullets": Bullets, "table": Table}
    kinds |= {"picture": Picture, "gallery": Gallery}
    environment.tests.update({name: _is(kind) for name, kind in kinds.items()})
    if markdown:
        environment.filters.update(md_block=_md_block, md_cell=_md_cell, code=_md_code)
        environment.filters.update(attribute=_md_attribute)
    return environment


def _render(name: str, blocks: list[Block], folder: Path | None, **more: Any) -> str:
    template = _templates(markdown=name.endswith(".md")).get_template(name)
    return template.render(
        blocks=blocks,
        spans=lambda text: spans(text, folder),
        inside=lambda relative: _inside(folder, relative),
        anchor=anchor,
        **more,
    )


def to_markdown(blocks: list[Block], folder: Path | None = None) -> str:
    """The blocks as Markdown; pictures and links only to files inside ``folder`` (the
    results folder the Markdown is written to; None: relative paths without ``..``)."""
    return _render("page.md", blocks, folder)


def to_html(blocks: list[Block], folder: Path, title: str) -> str:
    """One HTML page; images under ``folder`` are inlined, so the page stands alone."""
    return _render(
        "page.html", blocks, folder, title=title, embedded=lambda p: _embedded(folder, p)
    )
