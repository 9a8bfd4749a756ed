"""The bench's ``pass-size`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
