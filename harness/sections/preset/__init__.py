"""The bench's ``preset`` section (one line of ``harness.sections``): ``measure``,
``report``."""
