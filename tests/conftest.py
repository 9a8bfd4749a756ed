"""The step library is a pytest plugin; every test session here uses it.

The property tests (hypothesis) run under a profile: ``default`` keeps the suite fast (a few
dozen examples a test) and draws the same examples on every run (``derandomize``: the gate's
verdict never depends on the draw, and no example database is read or written);
``pytest --hypothesis-profile=long --timeout 0`` runs 10,000 examples a test, new ones each
run, kept in ``.hypothesis/`` when they fail, for a maintainer now and then.
A hang is a failure under both, but the gate's verdict never depends on how fast the machine
is: under ``default`` no example has a deadline (one that took 2 s on a busy machine would
fail), and the hang guard is pytest-timeout's, per test (``timeout`` in pyproject.toml);
``long`` gives each example a 2 s deadline, its hang guard (a maintainer's run, on a quiet
machine), as the per-test limit is off there.
A test's own ``@settings(max_examples=...)`` still wins over the profile's count.
"""

from hypothesis import HealthCheck, settings
from hypothesis.database import DirectoryBasedExampleDatabase

# tracebacks: a failure pytest cannot format is still one failure (tests/tracebacks.py)
pytest_plugins = ["steps.plugin", "tracebacks"]

settings.register_profile("default", max_examples=40, deadline=None, derandomize=True)
# named in full: a profile registered without a parent inherits the loaded one's (default's
# derandomize and no database), which would make the long profile draw the same examples
# every run and keep no failing one
settings.register_profile(
    "long",
    max_examples=10_000,
    deadline=2000,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=False,
    database=DirectoryBasedExampleDatabase(".hypothesis/examples"),
)
settings.load_profile("default")
