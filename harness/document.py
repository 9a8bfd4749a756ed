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


def _md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _md_picture(p: Picture) -> str:
    if p.width:
        return f'<img src="{p.path}" alt="{html.escape(p.alt)}" width="{p.width}">'
    return f"![{p.alt}]({p.path})"


def to_markdown(blocks: list[Block]) -> str:
    out: list[str] = []
    for block in blocks:
        if isinstance(block, Heading):
            out.append(f"{'#' * block.level} {block.text}")
        elif isinstance(block, Para):
            out.append(block.text)
        elif isinstance(block, Bullets):
            out.append("\n".join(f"- {item}" for item in block.items))
        elif isinstance(block, Table):
            lines = ["| " + " | ".join(_md_cell(h) for h in block.header) + " |"]
            lines.append(
                "| "
                + " | ".join(
                    "---:" if i in block.right else "---" for i in range(len(block.header))
                )
                + " |"
            )
            lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in block.rows]
            out.append("\n".join(lines))
        elif isinstance(block, Picture):
            out.append(_md_picture(block))
        elif isinstance(block, Gallery):
            lines = ["| " + " | ".join(block.header) + " |", "|" + " --- |" * len(block.header)]
            for caption, pictures in block.rows:
                cells = [_md_picture(p) if p else "-" for p in pictures]
                lines.append("| " + " | ".join([_md_cell(caption), *cells]) + " |")
            out.append("\n".join(lines))
    return "\n\n".join(out) + "\n"


def _inline_html(text: str) -> str:
    escaped = html.escape(text, quote=False)
    escaped = re.sub(r"`([^`]+)`", r"<code>\1</code>", escaped)
    escaped = re.sub(r'\[([^\]]+)\]\(([^)\s"]+)\)', r'<a href="\2">\1</a>', escaped)
    return re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", escaped)


def _data_uri(folder: Path, relative: str) -> str:
    data = (folder / relative).read_bytes()
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _html_picture(folder: Path, p: Picture) -> str:
    width = f' width="{p.width}"' if p.width else ""
    if not (folder / p.path).is_file():
        return f"<em>missing: {html.escape(p.path)}</em>"
    return f'<img src="{_data_uri(folder, p.path)}" alt="{html.escape(p.alt)}"{width}>'


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
            out.append(f'<h{block.level} id="{ident}">{_inline_html(block.text)}</h{block.level}>')
        elif isinstance(block, Para):
            out.append(f"<p>{_inline_html(block.text)}</p>")
        elif isinstance(block, Bullets):
            out.append("<ul>" + "".join(f"<li>{_inline_html(i)}</li>" for i in block.items))
            out.append("</ul>")
        elif isinstance(block, Table):
            opening = '<table class="compact">' if block.compact else "<table>"
            out.append(
                opening + "<tr>" + "".join(f"<th>{_inline_html(h)}</th>" for h in block.header)
            )
            out.append("</tr>")
            for row in block.rows:
                cells = [
                    f'<td class="num">{_inline_html(c)}</td>'
                    if i in block.right
                    else f"<td>{_inline_html(c)}</td>"
                    for i, c in enumerate(row)
                ]
                out.append("<tr>" + "".join(cells) + "</tr>")
            out.append("</table>")
        elif isinstance(block, Picture):
            out.append(f"<p>{_html_picture(folder, block)}</p>")
        elif isinstance(block, Gallery):
            out.append("<table><tr>" + "".join(f"<th>{_inline_html(h)}</th>" for h in block.header))
            out.append("</tr>")
            for caption, pictures in block.rows:
                cells = [_html_picture(folder, p) if p else "-" for p in pictures]
                out.append(
                    f"<tr><td>{_inline_html(caption)}</td>"
                    + "".join(f"<td>{c}</td>" for c in cells)
                    + "</tr>"
                )
            out.append("</table>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
