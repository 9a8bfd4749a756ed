"""The bench's ``cluster`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
