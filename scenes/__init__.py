"""The project's scene files, in the book's YAML scene format (``docs/scene-format.md``), with
the image textures and OBJ models they name; ``rtc render scenes/NAME.yml`` draws one. A
package only so that an install carries the files: ``FOLDER`` is where they are."""

from pathlib import Path

FOLDER = Path(__file__).resolve().parent
"""This folder: the scene files, ``textures/``, the OBJ models and the generated ``meshes/``."""
