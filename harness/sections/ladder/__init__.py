"""The bench's ``ladder`` section (one line of ``harness.sections``): ``measure``,
``report``, ``plot``."""
