"""Text quoted from a user's file, made safe to show on a terminal.

A scene's names, an OBJ path, an unknown key or a feature file's text may hold control
characters: an escape sequence (``ESC [2J`` clears the screen, ``ESC ]0;...BEL`` retitles
the terminal), a line break that splits one error line in two, or a bidirectional override
that shows text in another order than it is. ``printable`` writes each as a Python escape
(``\\x1b``, ``\\n``, ``\\u202e``) and leaves every other character as it is.
"""

from __future__ import annotations

import re

# C0 and C1 controls and DEL (category Cc), and the format characters that reorder or hide
# text (bidirectional embeddings, overrides and isolates; the line and paragraph separators).
# A pattern, compiled at its first use by ``re``'s own cache: most commands never show a
# user's text, and compiling this class takes about a millisecond of every command's start
_UNSAFE = "[\x00-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028-\u202e\u2066-\u2069]"


def _escaped(match: re.Match[str]) -> str:
    code = ord(match.group())
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def printable(text: str) -> str:
    """``text`` with every control character (and bidirectional override) escaped."""
    return re.sub(_UNSAFE, _escaped, text)

