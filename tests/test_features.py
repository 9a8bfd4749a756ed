"""The project's feature files: every scenario in ``features/``, once per ``--variant``."""

from pytest_bdd import scenarios

scenarios("../features")
