"""A tiny document model written out as Markdown and as one self-contained HTML page.

Text uses three inline marks, the same in both outputs: ```code```, ``**bold**`` and
``[text](path)``, a link (a path relative to the results folder, or ``#anchor``: a heading of
the same page, ``anchor(heading text)``, as GitHub names it). Images are paths relative to the
results folder: linked from the Markdown, inlined (base64) in the HTML.
"""

from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass, field
from pathlib import Path

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


def _one_line(text: str) -> str:
    """``text`` with every line break a space: a name read from a run file cannot start a
    heading or a new block of the Markdown (in a paragraph a line break is a space anyway)."""
    return " ".join(text.splitlines())


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


def _inline(text: str, folder: Path | None, markdown: bool) -> str:
    """``text`` with its marks (code, bold, link) as Markdown or HTML, and every other
    character escaped: HTML's special characters by ``html.escape`` in both outputs (GitHub's
    Markdown shows ``&lt;`` as ``<``), and CommonMark's link and code characters by a
    backslash in the Markdown. A link that leaves the results folder is shown as text."""
    out: list[str] = []
    at = 0
    for match in _MARKS.finditer(text):
        out.append(_plain(text[at : match.start()], markdown))
        at = match.end()
        if match["code"] is not None:
            code = _one_line(match["code"]) if markdown else html.escape(match["code"])
            out.append(f"`{code}`" if markdown else f"<code>{code}</code>")
        elif match["bold"] is not None:
            inner = _inline(match["bold"], folder, markdown)
            out.append(f"**{inner}**" if markdown else f"<strong>{inner}</strong>")
        else:
            label, target = _inline(match["label"], folder, markdown), match["target"]
            if not _safe_target(folder, target):
                out.append(f"{label} ({_plain(target, markdown)})")
            elif markdown:
                out.append(f"[{label}]({target})")
            else:
                out.append(f'<a href="{html.escape(target)}">{label}</a>')
    out.append(_plain(text[at:], markdown))
    return "".join(out)


def _plain(text: str, markdown: bool) -> str:
    if not markdown:
        return html.escape(text)
    return html.escape(_one_line(text), quote=False).translate(_MD_PUNCTUATION)


_BLOCK_START = re.compile(r"(#{1,6}|[-+*]|\d{1,9}(?=[.)]))(?=[.)]?(\s|$))")


def _md_block(rendered: str) -> str:
    """A paragraph's, a heading's or a list item's Markdown, which must not start another
    block: a leading ``#`` (a heading), ``-``, ``+``, ``*`` or ``1.`` (a list) from a name is
    escaped, and leading blanks (code) dropped."""
    rendered = rendered.lstrip()
    match = _BLOCK_START.match(rendered)
    if match is None:
        return rendered
    end = match.end(1)
    if rendered[:end].isdigit():  # 1. or 1): the dot or parenthesis makes the list
        return f"{rendered[:end]}\\{rendered[end:]}"
    return "\\" + rendered


def _md_cell(text: str, folder: Path | None) -> str:
    return _inline(text, folder, markdown=True).replace("|", "\\|")


def _md_picture(p: Picture, folder: Path | None) -> str:
    if not _inside(folder, p.path):
        return f"*not shown: {_plain(p.path, True)} (not a file of the results folder)*"
    alt = _plain(p.alt, True)
    if p.width:
        return f'<img src="{p.path}" alt="{html.escape(_one_line(p.alt))}" width="{p.width}">'
    return f"![{alt}]({p.path})"


def to_markdown(blocks: list[Block], folder: Path | None = None) -> str:
    """The blocks as Markdown; pictures and links only to files inside ``folder`` (the
    results folder the Markdown is written to; None: relative paths without ``..``)."""

    def text(value: str) -> str:
        return _md_block(_inline(value, folder, markdown=True))

    out: list[str] = []
    for block in blocks:
        if isinstance(block, Heading):
            out.append(f"{'#' * block.level} {text(block.text)}")
        elif isinstance(block, Para):
            out.append(text(block.text))
        elif isinstance(block, Bullets):
            out.append("\n".join(f"- {text(item)}" for item in block.items))
        elif isinstance(block, Table):
            lines = ["| " + " | ".join(_md_cell(h, folder) for h in block.header) + " |"]
            lines.append(
                "| "
                + " | ".join(
                    "---:" if i in block.right else "---" for i in range(len(block.header))
                )
                + " |"
            )
            lines += [
                "| " + " | ".join(_md_cell(c, folder) for c in row) + " |" for row in block.rows
            ]
            out.append("\n".join(lines))
        elif isinstance(block, Picture):
            out.append(_md_picture(block, folder))
        elif isinstance(block, Gallery):
            lines = [
                "| " + " | ".join(_md_cell(h, folder) for h in block.header) + " |",
                "|" + " --- |" * len(block.header),
            ]
            for caption, pictures in block.rows:
                cells = [_md_picture(p, folder).replace("|", "\\|") if p else "-" for p in pictures]
                lines.append("| " + " | ".join([_md_cell(caption, folder), *cells]) + " |")
            out.append("\n".join(lines))
    return "\n\n".join(out) + "\n"


def _inline_html(text: str, folder: Path | None = None) -> str:
    return _inline(text, folder, markdown=False)


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


def _html_picture(folder: Path, p: Picture) -> str:
    width = f' width="{p.width}"' if p.width else ""
    data = _png_data(folder, p.path)
    if isinstance(data, str):
        return f"<em>{html.escape(data)}: {html.escape(p.path)}</em>"
    uri = "data:image/png;base64," + base64.b64encode(data).decode("ascii")
    return f'<img src="{uri}" alt="{html.escape(p.alt)}"{width}>'


STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; padding: 0 1em;
       color: #222; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.85em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; vertical-align: top; }
th { background: #f0f0f0; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.compact { font-size: 0.78em; }
img { image-rendering: pixelated; }
code { background: #f4f4f4; padding: 0 0.2em; }
"""


def to_html(blocks: list[Block], folder: Path, title: str) -> str:
    """One HTML page; images under ``folder`` are inlined, so the page stands alone."""
    out = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>",
    ]
    for block in blocks:
        if isinstance(block, Heading):
            ident = html.escape(anchor(block.text))
            out.append(
                f'<h{block.level} id="{ident}">{_inline_html(block.text, folder)}</h{block.level}>'
            )
        elif isinstance(block, Para):
            out.append(f"<p>{_inline_html(block.text, folder)}</p>")
        elif isinstance(block, Bullets):
            out.append("<ul>" + "".join(f"<li>{_inline_html(i, folder)}</li>" for i in block.items))
            out.append("</ul>")
        elif isinstance(block, Table):
            opening = '<table class="compact">' if block.compact else "<table>"
            out.append(
                opening
                + "<tr>"
                + "".join(f"<th>{_inline_html(h, folder)}</th>" for h in block.header)
            )
            out.append("</tr>")
            for row in block.rows:
                cells = [
                    f'<td class="num">{_inline_html(c, folder)}</td>'
                    if i in block.right
                    else f"<td>{_inline_html(c, folder)}</td>"
                    for i, c in enumerate(row)
                ]
                out.append("<tr>" + "".join(cells) + "</tr>")
            out.append("</table>")
        elif isinstance(block, Picture):
            out.append(f"<p>{_html_picture(folder, block)}</p>")
        elif isinstance(block, Gallery):
            out.append(
                "<table><tr>" + "".join(f"<th>{_inline_html(h, folder)}</th>" for h in block.header)
            )
            out.append("</tr>")
            for caption, pictures in block.rows:
                cells = [_html_picture(folder, p) if p else "-" for p in pictures]
                out.append(
                    f"<tr><td>{_inline_html(caption, folder)}</td>"
                    + "".join(f"<td>{c}</td>" for c in cells)
                    + "</tr>"
                )
            out.append("</table>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
