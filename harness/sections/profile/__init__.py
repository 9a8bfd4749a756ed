"""The bench's ``profile`` section (one line of ``harness.sections``): ``measure``,
``report``."""
