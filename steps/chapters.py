"""Which chapter of the book a scenario belongs to.

A ``@chapterNN`` tag on the scenario (or its feature) says it; an untagged file (the book's
own download) is placed by its file name.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

CHAPTER_TAG = re.compile(r"chapter(\d+)")

# The book's feature files and the chapter that introduces each.
CHAPTER_BY_FILE_NAME: dict[str, int] = {
    "tuples": 1, "canvas": 2, "matrices": 3, "transformations": 4, "rays": 5, "spheres": 5,
    "intersections": 5, "lights": 6, "materials": 6, "world": 7, "camera": 7, "shapes": 9,
    "planes": 9, "patterns": 10, "cubes": 12, "cylinders": 13, "cones": 13, "groups": 14,
    "triangles": 15, "obj_file": 15, "smooth-triangles": 15, "csg": 16, "torus": 20,
    "bounding-boxes": 17,  # the bonus chapter "Bounding boxes and hierarchies"
    "soft-shadows": 18,  # the bonus chapter "Rendering soft shadows"
    "texture-mapping": 19,  # the bonus chapter "Texture mapping"
}  # fmt: skip


def chapter_tag(chapter: int) -> str:
    """The marker name for a chapter: ``chapter05``."""
    return f"chapter{chapter:02d}"


def chapter_of(tags: Iterable[str], feature_file: str | Path) -> int | None:
    """The chapter from a ``@chapterNN`` tag, else from the feature file's name, else None."""
    for tag in sorted(tags):
        match = CHAPTER_TAG.fullmatch(tag.lstrip("@"))
        if match:
            return int(match.group(1))
    stem = Path(feature_file).stem
    return CHAPTER_BY_FILE_NAME.get(stem, CHAPTER_BY_FILE_NAME.get(stem.replace("_", "-")))
