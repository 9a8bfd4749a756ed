"""The bench's ``convergence`` section (one line of ``harness.sections``): ``measure``,
``fit``, ``report``, ``plot``."""
