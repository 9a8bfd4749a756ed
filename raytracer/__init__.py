"""The Ray Tracer Challenge, chapter by chapter: the naive, immutable reference tracer."""

__all__: list[str] = []
