"""Scenes, their loader, and the measurements: time, allocations and image error per variant."""
