"""The report's two templates (``harness/document/templates/``): whatever they print is
escaped unless it was written for the page already, and text is data, never template."""

from __future__ import annotations

from pathlib import Path

from harness.document.model import (
    Block,
    Bullets,
    Heading,
    Para,
    Picture,
    Table,
    to_html,
    to_markdown,
)
from harness.document.model import _templates as templates

HOSTILE = "[x](javascript:alert(1)) `a|b` <img src=x onerror=alert(1)> & \"q\" 'a'\n# h"


def test_a_value_the_markdown_template_prints_as_it_is_becomes_plain_text() -> None:
    """The Markdown environment's finalize escapes what a template forgot to: one line, HTML
    entities, CommonMark's link and code characters after a backslash; a value marked safe
    (written as Markdown already) is kept."""
    environment = templates(markdown=True)
    printed = environment.from_string("{{ value }}").render(value=HOSTILE)
    assert printed == (
        "\\[x\\](javascript:alert(1)) \\`a|b\\` &lt;img src=x onerror=alert(1)&gt; &amp; "
        "\"q\" 'a' # h"
    )
    assert environment.from_string("{{ value | safe }}").render(value="[x](y)") == "[x](y)"
    assert environment.from_string("{{ 3 }}").render() == "3"


def test_the_page_template_escapes_every_value() -> None:
    page = templates(markdown=False).from_string('<a title="{{ v }}">{{ v }}</a>').render(v=HOSTILE)
    assert "<img" not in page and '"q"' not in page and "'a'" not in page
    assert page.count("&lt;img src=x onerror=alert(1)&gt;") == 2


def test_text_that_looks_like_a_template_is_printed_as_it_is(tmp_path: Path) -> None:
    """A name from a run file is data: Jinja2's own syntax in it is not evaluated."""
    text = "{{ 7 * 7 }} {% if true %}yes{% endif %} {# c #}"
    blocks: list[Block] = [
        Heading(2, text),
        Para(text),
        Bullets([text]),
        Table([text], [[text]], {0}),
        Picture("missing.png", text, 10),
    ]
    page = to_html(blocks, tmp_path, text)
    markdown = to_markdown(blocks, tmp_path)
    assert "49" not in page and "49" not in markdown
    # the title, the heading, the paragraph, the item and both cells; the picture is missing
    assert page.count(text) == 6
    # the heading, the paragraph, the item, both cells and the picture's alt
    assert markdown.count(text) == 6


def test_the_markdown_keeps_a_pipe_in_a_cell_and_a_hash_at_a_line_start_plain() -> None:
    markdown = to_markdown([Table(["a|b"], [["`c|d`"]]), Para("# not a heading")])
    assert "| a\\|b |" in markdown and "| `c\\|d` |" in markdown
    assert "\\# not a heading" in markdown
