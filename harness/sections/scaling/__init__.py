"""The bench's ``scaling`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
