"""How deep the run goes (conftest.py): ``THOROUGH`` under ``pytest --thorough``, and how
many examples a property test draws under the loaded hypothesis profile.

A test with its own count writes ``@settings(max_examples=examples(gate, thorough))``: the
gate's profile draws ``gate`` (the same ones every run), ``--thorough`` draws ``thorough``
(ten times ``gate`` if not given; new ones each run), and a bigger profile (``long``) draws
``long`` if given, else the profile's own count.
"""

from __future__ import annotations

from hypothesis import settings

GATE_EXAMPLES = 25
THOROUGH_EXAMPLES = 250
THOROUGH = False  # set by conftest.py for ``pytest --thorough``


def examples(gate: int, thorough: int | None = None, long: int | None = None) -> int:
    """A test's example count under the loaded profile (see the module's docstring)."""
    current = settings.default
    profile = current.max_examples if current is not None else GATE_EXAMPLES
    if profile <= GATE_EXAMPLES:
        return gate
    if profile <= THOROUGH_EXAMPLES:
        return thorough if thorough is not None else 10 * gate
    return long if long is not None else profile
