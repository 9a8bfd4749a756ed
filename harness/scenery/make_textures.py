"""The image textures of ``scenes/textures.yml`` (the bonus chapter "Texture
mapping"), drawn here pixel by pixel so the project owns them:

- ``planet.png``, 64x32 (2:1, for a spherical map): an ocean darker towards the poles, white
  polar caps, green-brown land from a sum of waves, and "RTC" in yellow on the equator
  (mirrored letters would show a mapping turned the wrong way).
- ``label.ppm``, 64x32 plain PPM (for a cylindrical map): a can's label, red bands above and
  below a cream band that reads "RAY" twice around.

Run ``python -m harness.scenery.make_textures`` to write them again (the output is the same every
time). The files are small (under 30 kB) and ship with the package.
"""

from __future__ import annotations

import math

from groundwork.images import write_image
from harness.scenery import SCENES
from raytracer.canvas import Canvas, write_pixel
from raytracer.colors import Color

FOLDER = SCENES / "textures"

# 5x7 letters, one string per row, '#' is ink
GLYPHS = {
    "R": ["####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"],
    "T": ["#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."],
    "C": [".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."],
    "A": [".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"],
    "Y": ["#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."],
}


def draw_text(c: Canvas, text: str, left: int, top: int, ink: Color) -> None:
    """``text`` in the 5x7 letters, one blank column between letters."""
    for n, letter in enumerate(text):
        for row, line in enumerate(GLYPHS[letter]):
            for col, cell in enumerate(line):
                if cell == "#":
                    write_pixel(c, left + n * 6 + col, top + row, ink)


def planet() -> Canvas:
    """The 64x32 planet: rows are latitude (row 0 the north pole), columns longitude."""
    width, height = 64, 32
    c = Canvas(width, height)
    for y in range(height):
        latitude = (0.5 - (y + 0.5) / height) * math.pi  # +π/2 at the top
        for x in range(width):
            longitude = (x + 0.5) / width * 2 * math.pi
            depth = 0.55 + 0.45 * math.cos(latitude)
            color = Color(0.05 * depth, 0.25 * depth, 0.65 * depth)
            land = (
                math.sin(2 * longitude + 1.3) * math.cos(3 * latitude)
                + 0.6 * math.sin(5 * longitude - 2 * latitude)
                + 0.4 * math.cos(3 * longitude + 4 * latitude)
            )
            if land > 0.75:
                color = Color(0.55, 0.45, 0.25) if land > 1.25 else Color(0.2, 0.55, 0.2)
            if abs(latitude) > 1.25:
                color = Color(0.95, 0.95, 0.97)
            write_pixel(c, x, y, color)
    draw_text(c, "RTC", 23, 12, Color(1.0, 0.85, 0.1))
    return c


def label() -> Canvas:
    """The 64x32 can label: red, cream with "RAY" twice, red."""
    width, height = 64, 32
    c = Canvas(width, height)
    red, cream, ink = Color(0.75, 0.1, 0.1), Color(0.95, 0.9, 0.75), Color(0.1, 0.1, 0.3)
    for y in range(height):
        for x in range(width):
            band = red if y < 8 or y >= 24 else cream
            if y in (8, 23):
                band = Color(0.85, 0.7, 0.2)  # gold trim
            write_pixel(c, x, y, band)
    draw_text(c, "RAY", 7, 12, ink)
    draw_text(c, "RAY", 39, 12, ink)
    return c


def main() -> None:
    FOLDER.mkdir(parents=True, exist_ok=True)
    for name, canvas in (("planet.png", planet()), ("label.ppm", label())):
        path = write_image(canvas, FOLDER / name)
        print(f"wrote {path} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
