"""The bench's ``sweep`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
