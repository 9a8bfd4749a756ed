"""Where inside a pixel each sample ray goes when rendering with several samples per pixel.

Not in the book (which shoots one ray through each pixel's centre). A pure function of
``(seed, x, y, i)``, built from integer operations only, so every variant, every worker count
and a compiled implementation produce the same offsets bit for bit:

    key   = (seed * GAMMA  mod 2**64)  XOR  (y << 34 | x << 20 | i)
    dx    = top 53 bits of splitmix64 output 1 of a generator seeded with key, times 2**-53
    dy    = the same for output 2

where splitmix64 output k is ``mix(key + k * GAMMA mod 2**64)``.
"""

from __future__ import annotations

MASK64 = (1 << 64) - 1
GAMMA = 0x9E3779B97F4A7C15  # splitmix64's increment (the golden ratio in 64 bits)
MAX_COORDINATE = 1 << 14  # 16384, the largest canvas side: x and y take 14 bits of the key
MAX_SAMPLES = 1 << 20  # sample indices take the low 20 bits of the key


def mix64(z: int) -> int:
    """splitmix64's output function: a bijective scramble of a 64-bit integer."""
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
    return z ^ (z >> 31)


def sample_key(seed: int, x: int, y: int, i: int) -> int:
    """The 64-bit key for sample ``i`` of pixel (x, y) under ``seed``."""
    if not (0 <= x < MAX_COORDINATE and 0 <= y < MAX_COORDINATE):
        raise ValueError(f"sample_offset: pixel ({x}, {y}) is outside 0..{MAX_COORDINATE - 1}")
    if not 0 <= i < MAX_SAMPLES:
        raise ValueError(f"sample_offset: sample index {i} is outside 0..{MAX_SAMPLES - 1}")
    if not 0 <= seed <= MASK64:
        raise ValueError(f"sample_offset: seed {seed} is outside 0..2**64-1")
    return ((seed * GAMMA) & MASK64) ^ ((y << 34) | (x << 20) | i)


def sample_offset(seed: int, x: int, y: int, i: int) -> tuple[float, float]:
    """Where sample ``i`` of pixel (x, y) goes: ``(dx, dy)``, each in [0, 1).

    seed: the render's seed (RenderSettings.seed); x, y: the pixel; i: the sample index.
    (0, 0) is the pixel's top left corner, (0.5, 0.5) its centre.
    """
    key = sample_key(seed, x, y, i)
    first = mix64((key + GAMMA) & MASK64)
    second = mix64((key + 2 * GAMMA) & MASK64)
    return (first >> 11) * 2.0**-53, (second >> 11) * 2.0**-53
