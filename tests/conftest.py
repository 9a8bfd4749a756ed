"""The step library is a pytest plugin; every test session here uses it."""

pytest_plugins = ["steps.plugin"]
