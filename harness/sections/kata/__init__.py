"""The bench's ``kata`` section (one line of ``harness.sections``): ``measure``,
``report``."""
