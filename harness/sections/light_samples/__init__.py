"""The bench's ``light-samples`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
