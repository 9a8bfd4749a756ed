"""The scene items of the path integrator (chapter 21 here, beyond the book): ``- add: sky``
(what a path that escapes sees) and ``- add: render`` (how to render the scene: which
integrator, samples, depth, seed, roulette, light sampling; ``rtc render``'s flags win over
it).

::

    - add: sky
      color: [0.6, 0.7, 0.9]        # a uniform sky, or
      horizon: [1, 1, 1]            # a vertical gradient (``raytracer.sky``)
      zenith: [0.5, 0.7, 1.0]

    - add: render
      integrator: path              # whitted (the book's, the default) or path
      samples: 16
      depth: 5
      seed: 0
      roulette: 3                   # 0: off
      light-sampling: off           # on (the default): shadow rays to the area lights;
                                    # off: paths find them by crossing them
"""

from __future__ import annotations

from typing import Any

from yaml.nodes import Node

from raytracer.camera import INTEGRATORS, MAX_DEPTH
from raytracer.sampling import MAX_SAMPLES
from scene.colors import read_color
from scene.context import Context
from scene.reader import Entry

SKY_KEYS = ("add", "color", "horizon", "zenith")
RENDER_KEYS = ("add", "integrator", "samples", "depth", "seed", "roulette", "light-sampling")
# what each whole-number setting may be: (low, high)
RENDER_RANGES = {
    "samples": (1, MAX_SAMPLES),
    "depth": (0, MAX_DEPTH),
    "seed": (0, 2**64 - 1),
    "roulette": (0, MAX_DEPTH),
}


def read_sky(ctx: Context, node: Node, entries: dict[str, Entry]) -> Any:
    """``- add: sky``: the variant's ``sky(color)`` or ``gradient_sky(horizon, zenith)``."""
    reader = ctx.reader
    what = "the sky"
    reader.check_keys(entries, SKY_KEYS, what)
    given = [key for key in SKY_KEYS[1:] if key in entries]
    if given == ["color"]:
        colour = read_color(ctx, entries["color"].value, f"{what}'s color")
        return ctx.need("sky", node, what)(colour)
    if given == ["horizon", "zenith"]:
        horizon = read_color(ctx, entries["horizon"].value, f"{what}'s horizon")
        zenith = read_color(ctx, entries["zenith"].value, f"{what}'s zenith")
        return ctx.need("gradient_sky", node, what)(horizon, zenith)
    reader.fail(
        node,
        f"{what} takes 'color' (a uniform sky) or both 'horizon' and 'zenith' (a gradient), "
        f"got {', '.join(given) or 'neither'}",
    )


def read_render(ctx: Context, node: Node, entries: dict[str, Entry]) -> dict[str, Any]:
    """``- add: render``: the settings it gives, by ``RenderSettings`` field name."""
    reader = ctx.reader
    what = "the render settings"
    reader.check_keys(entries, RENDER_KEYS, what)
    settings: dict[str, Any] = {}
    for key, entry in entries.items():
        if key == "integrator":
            name = reader.string(entry.value, f"{what}' integrator")
            if name not in INTEGRATORS:
                reader.fail(
                    entry.value,
                    f"unknown integrator {name!r}; known: {', '.join(INTEGRATORS)}",
                )
            settings[key] = name
        elif key == "light-sampling":
            value = reader.scalar(entry.value, f"{what}' light-sampling")
            if not isinstance(value, bool):
                reader.fail(entry.value, f"{what}' light-sampling must be on or off, got {value!r}")
            settings["light_sampling"] = value
        elif key in RENDER_RANGES:
            low, high = RENDER_RANGES[key]
            settings[key] = reader.whole(entry.value, f"{what}' {key}", low, high)
    return settings
