"""The bench's ``scene-size`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
