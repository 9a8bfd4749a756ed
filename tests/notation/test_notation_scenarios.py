"""``notation.feature``: every form of the book's notation, once per ``--variant``."""

from pytest_bdd import scenarios

scenarios("notation.feature")
