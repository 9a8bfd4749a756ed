"""The step library is a pytest plugin; every test session here uses it.

Two depths (``pytest`` is the gate's; ``pytest --thorough`` a maintainer's before a release):

- numba's kernels: the gate renders every scene through numba's generic kernel (every
  feature compiled in, ``RTC_NUMBA_SPECIALIZE=off``, set here for the session and the
  processes it starts; float32's and fast math's hold every feature their scenes use,
  ``RTC_NUMBA_OPTION_FEATURES``; helpers called, not inlined: ``RTC_NUMBA_GENERIC_CALLS``),
  so a cold run compiles one render kernel per precision instead of one per scene's feature
  set; the tests whose subject is specialization ask for it
  (``specialized_kernels``). ``--thorough`` specializes every render, as a user's run does.
  The kernel folder is named in ``RTC_NUMBA_KERNELS`` for the session, so every worker and
  the processes they start share it however a test changes the environment.
- hypothesis: the property tests run under a profile. ``gate`` (the default) draws few
  examples a test (``examples()``: tests/budget.py scales a test's own count) and the same
  ones on every run (``derandomize``: the verdict never depends on the draw, no example
  database is read or written); ``--thorough`` loads ``thorough``: ten times as many
  examples, new ones each run, the failing ones kept in ``.hypothesis/``.
  ``--hypothesis-profile=long --timeout 0`` runs 10,000 examples a test, for hours.

A hang is a failure under every profile, but the gate's verdict never depends on how fast
the machine is: under ``gate`` and ``thorough`` no example has a deadline (one that took 2 s
on a busy machine would fail), and the hang guard is pytest-timeout's, per test
(``timeout`` in pyproject.toml); ``long`` gives each example a 2 s deadline, its hang guard
(a maintainer's run, on a quiet machine), as the per-test limit is off there.
"""

import os
from collections.abc import Iterator

import budget
import pytest
from budget import GATE_EXAMPLES, THOROUGH_EXAMPLES
from hypothesis import HealthCheck, settings
from hypothesis.database import DirectoryBasedExampleDatabase
from once_per_run import OncePerRun

from compiled.folder import kernel_folder
from variants.numba.features import OPTION_FEATURES, FeatureSet
from variants.numba.render import GENERIC_CALLS, GENERIC_ONLY

KERNELS = "RTC_NUMBA_KERNELS"
OPTIONS_LEAVE_OUT = FeatureSet.from_key(
    "texture_map+cube_map+uv_image+area_lights+jitter+nodes+test_shape+test_pattern"
)
"""What no scene the gate renders in float32 or with fast math has (test_numba.py's options
and regions, test_differential.py's random worlds, test_stability.py's cases, path-traced
ones among them): the generic kernel of those precisions leaves it out
(``RTC_NUMBA_OPTION_FEATURES``); a scene that needs any of it runs every feature."""
OPTION_KERNEL = FeatureSet(FeatureSet.everything().flags - OPTIONS_LEAVE_OUT.flags)

# tracebacks: a failure pytest cannot format is still one failure (tests/tracebacks.py);
# cpu_seconds: each test's CPU seconds, with RTC_TEST_CPU_LOG set (tests/cpu_seconds.py)
pytest_plugins = ["steps.plugin", "tracebacks", "cpu_seconds"]

settings.register_profile("gate", max_examples=GATE_EXAMPLES, deadline=None, derandomize=True)
# named in full: a profile registered without a parent inherits the loaded one's (gate's
# derandomize and no database), which would make the others draw the same examples every
# run and keep no failing one
_EXPLORING = {
    "derandomize": False,
    "database": DirectoryBasedExampleDatabase(".hypothesis/examples"),
}
settings.register_profile(
    "thorough",
    max_examples=THOROUGH_EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    **_EXPLORING,
)
settings.register_profile(
    "long",
    max_examples=10_000,
    deadline=2000,
    suppress_health_check=[HealthCheck.too_slow],
    **_EXPLORING,
)
settings.load_profile("gate")


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--thorough",
        action="store_true",
        help="the deeper run: hypothesis's 'thorough' profile (ten times the examples, new "
        "ones each run) and numba's kernels specialized to each scene",
    )


def pytest_configure(config: pytest.Config) -> None:
    """Before the test modules are imported (their example counts read the profile)."""
    if config.getoption("thorough"):
        budget.THOROUGH = True
        if config.getoption("hypothesis_profile", None) in (None, "gate"):
            settings.load_profile("thorough")
        os.environ.setdefault(GENERIC_ONLY, "on")
    os.environ.setdefault(GENERIC_ONLY, "off")
    if os.environ[GENERIC_ONLY] == "off":  # the gate's (``--thorough`` specializes)
        os.environ.setdefault(OPTION_FEATURES, OPTION_KERNEL.key)
        os.environ.setdefault(GENERIC_CALLS, "on")
    if not os.environ.get(KERNELS):
        # the run's kernel folder, named: a test that unsets it (``monkeypatch.delenv``)
        # then gets it back, so a worker never leaves the folder the others share (a test
        # of the folder's fallback sets it to a private one of its own, which, were it unset
        # here, would stay set: that worker compiled every kernel again in a cold gate)
        os.environ[KERNELS] = str(kernel_folder())


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests marked ``slow`` first, the rest after them, each in collection order.

    pytest-xdist's ``worksteal`` gives each worker a run of the list and lets a worker that
    is done take tests from the end of another's queue: a long test left near the end
    starts last and the run waits for it on one core. Started first, a long test runs while
    the other worker takes the short ones, and the run ends on short tests. A whole module
    is marked with ``pytestmark`` (its tests stay together: a module-scoped fixture is made
    once); one test of a module only if it uses no module-scoped fixture."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)


@pytest.fixture
def specialized_kernels(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """numba's renders in this test compile a kernel for their scene's feature set (the
    test's subject is specialization; the rest of the gate shares the generic kernel)."""
    monkeypatch.setenv(GENERIC_ONLY, "on")
    yield


@pytest.fixture(scope="session")
def once_per_run(tmp_path_factory: pytest.TempPathFactory) -> OncePerRun:
    """Results shared by the run's worker processes (tests/once_per_run.py): in the run's
    temporary folder, which each worker's own folder is in."""
    base = tmp_path_factory.getbasetemp()
    folder = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "once-per-run"
    folder.mkdir(exist_ok=True)
    return OncePerRun(folder)
