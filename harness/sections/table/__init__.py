"""The bench's ``table`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
