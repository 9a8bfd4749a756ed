"""PNGs written without Pillow (``groundwork.images.png_bytes``, issue 36 item 4): Pillow
reads every one back to the byte, and a render's PNG is about the size of Pillow's own fast one
(``compress_level=1``), which the writer replaced."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from groundwork.images import png_bytes, rgb8
from raytracer.camera import RenderSettings
from scene import load_scene
from scenes import FOLDER as SCENES
from variants.registry import load_variant


def _decoded(data: bytes) -> tuple[str, tuple[int, int], bytes]:
    with Image.open(io.BytesIO(data), formats=["PNG"]) as image:
        image.load()  # checks every chunk's CRC and the zlib stream
        return image.mode, image.size, image.tobytes()


@pytest.mark.parametrize("size", [(1, 1), (3, 2), (17, 5), (64, 48)])
def test_pillow_reads_back_every_byte(size: tuple[int, int]) -> None:
    width, height = size
    rgb = np.random.default_rng(width * height).integers(0, 256, width * height * 3, np.uint8)
    assert _decoded(png_bytes(rgb.tobytes(), width, height)) == ("RGB", size, rgb.tobytes())


@pytest.mark.parametrize("name", ["reference.yml", "shapes.yml", "csg.yml"])
def test_a_renders_png_is_about_the_size_of_pillows_fast_one(name: str) -> None:
    """Within 10% of Pillow's ``compress_level=1`` PNG of the same render (one filter for
    every row rather than Pillow's choice per row: the reference scene at 640x480 packs 5%
    smaller, the shapes 5% larger)."""
    variant = load_variant("wavefront")
    scene = load_scene(SCENES / name, variant.api).resized(160, 120)
    canvas = variant.api["render"](scene.camera, variant.world_for(scene), RenderSettings(), None)
    rgb = rgb8(canvas)
    ours = png_bytes(rgb, 160, 120)
    buffer = io.BytesIO()
    Image.frombytes("RGB", (160, 120), rgb).save(buffer, format="PNG", compress_level=1)
    assert _decoded(ours) == ("RGB", (160, 120), rgb)
    assert len(ours) <= 1.1 * len(buffer.getvalue())
