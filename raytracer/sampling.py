"""Where inside a pixel each sample ray goes when rendering with several samples per pixel.

Not in the book (which shoots one ray through each pixel's centre). A pure function of
``(seed, x, y, i)``, built from integer operations only, so every variant, every worker count
and a compiled implementation produce the same offsets bit for bit:

    key   = (seed * GAMMA  mod 2**64)  XOR  (y << 34 | x << 20 | i)
    dx    = top 53 bits of splitmix64 output 1 of a generator seeded with key, times 2**-53
    dy    = the same for output 2

where splitmix64 output k is ``mix(key + k * GAMMA mod 2**64)``.

The same key drives the random jitter of area lights (the bonus chapter "Rendering soft
shadows", ``light_jitter``): outputs 1 and 2 are the pixel offset; the cell (u, v) of light
number k takes outputs ``3 + 2 n`` and ``4 + 2 n`` with ``n = k << 32 | v << 16 | u``. So
where a light's cells are sampled depends on (seed, pixel, sample, light index, cell) only,
never on the order in which rays are traced, and a compiled variant reproduces it.

The path integrator (chapter 21 here, beyond the book: ``raytracer.path``) draws its numbers
from the same key, XORed with ``PATH_TAG`` so that its streams lie apart from the two above:

    path_random(seed, x, y, i, b, d) = top 53 bits of
        mix(((key XOR PATH_TAG) + (1 + (b << 32) + d) * GAMMA) mod 2**64), times 2**-53

for bounce ``b`` (the camera ray's hit is bounce 0) and dimension ``d`` (which number of
that bounce: ``raytracer.path`` lists them), each in [0, 1).
"""

from __future__ import annotations

MASK64 = (1 << 64) - 1
GAMMA = 0x9E3779B97F4A7C15  # splitmix64's increment (the golden ratio in 64 bits)
MAX_COORDINATE = 1 << 14  # 16384, the largest canvas side: x and y take 14 bits of the key
MAX_SAMPLES = 1 << 20  # sample indices take the low 20 bits of the key
MAX_LIGHT_STEPS = 1 << 16  # an area light's cells per side: u and v take 16 bits of a stream
MAX_LIGHTS = 1 << 31  # light indices: the stream stays below 2**64
PATH_TAG = 0x5851F42D4C957F2D  # an odd constant (PCG's multiplier): the path's streams
MAX_BOUNCES = 1 << 31  # a path's bounce index takes the bits above 32 of its counter
MAX_DIMENSIONS = 1 << 32  # a bounce's dimensions take the low 32 bits


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


def light_jitter_key(key: int, light_index: int, u: int, v: int) -> tuple[float, float]:
    """``light_jitter`` for a sample whose ``sample_key`` is ``key`` (no checks: the caller
    checked light_index, u and v)."""
    stream = 3 + 2 * ((light_index << 32) | (v << 16) | u)
    first = mix64((key + stream * GAMMA) & MASK64)
    second = mix64((key + (stream + 1) * GAMMA) & MASK64)
    return (first >> 11) * 2.0**-53, (second >> 11) * 2.0**-53


def light_jitter(
    seed: int, x: int, y: int, i: int, light_index: int, u: int, v: int
) -> tuple[float, float]:
    """Where in cell (u, v) of a jittered area light the point goes for sample ``i`` of
    pixel (x, y): ``(ju, jv)``, each in [0, 1) (the bonus chapter "Rendering soft shadows").

    seed, x, y, i: as ``sample_offset``; light_index: the light's place in the world's
    lights (0 first); u, v: the cell, each below ``MAX_LIGHT_STEPS``. Two splitmix64 outputs
    of the sample's key on the stream ``3 + 2 (light_index << 32 | v << 16 | u)`` (streams 1
    and 2 are ``sample_offset``'s), so it is a pure function of its arguments.
    """
    if not 0 <= light_index < MAX_LIGHTS:
        raise ValueError(f"light_jitter: light index {light_index} is outside 0..{MAX_LIGHTS - 1}")
    if not (0 <= u < MAX_LIGHT_STEPS and 0 <= v < MAX_LIGHT_STEPS):
        raise ValueError(
            f"light_jitter: cell ({u}, {v}) is outside 0..{MAX_LIGHT_STEPS - 1} on a side"
        )
    return light_jitter_key(sample_key(seed, x, y, i), light_index, u, v)


def light_jitters(
    seed: int, x: int, y: int, i: int, light_index: int, usteps: int, vsteps: int
) -> list[float]:
    """``light_jitter`` of every cell of a ``usteps`` x ``vsteps`` light, flat and in cell
    order (v outer, u inner): ``[ju(0, 0), jv(0, 0), ju(1, 0), jv(1, 0), ...]``, the
    values a jittered light's ``jitter_by`` gives during one sample."""
    if not (1 <= usteps <= MAX_LIGHT_STEPS and 1 <= vsteps <= MAX_LIGHT_STEPS):
        raise ValueError(
            f"light_jitters: {usteps}x{vsteps} cells; each side must be 1..{MAX_LIGHT_STEPS}"
        )
    if not 0 <= light_index < MAX_LIGHTS:
        raise ValueError(f"light_jitters: light index {light_index} is outside 0..{MAX_LIGHTS - 1}")
    key = sample_key(seed, x, y, i)
    values: list[float] = []
    for v in range(vsteps):
        for u in range(usteps):
            values += light_jitter_key(key, light_index, u, v)
    return values


def path_random_key(key: int, bounce: int, dimension: int) -> float:
    """``path_random`` for a sample whose ``sample_key`` is ``key`` (no checks: the caller
    checked bounce and dimension)."""
    counter = 1 + (bounce << 32) + dimension
    z = mix64(((key ^ PATH_TAG) + counter * GAMMA) & MASK64)
    return (z >> 11) * 2.0**-53


def path_random(seed: int, x: int, y: int, i: int, bounce: int, dimension: int) -> float:
    """The path integrator's random number ``dimension`` at ``bounce`` of sample ``i`` of
    pixel (x, y) under ``seed``: a number in [0, 1), a pure function of its arguments
    (chapter 21 here, beyond the book; the module docstring gives the formula).

    seed, x, y, i: as ``sample_offset``; bounce: 0 for the camera ray's hit, 1 for the next
    one ...; dimension: which number of that bounce (``raytracer.path`` lists their uses).
    """
    if not 0 <= bounce < MAX_BOUNCES:
        raise ValueError(f"path_random: bounce {bounce} is outside 0..{MAX_BOUNCES - 1}")
    if not 0 <= dimension < MAX_DIMENSIONS:
        raise ValueError(f"path_random: dimension {dimension} is outside 0..{MAX_DIMENSIONS - 1}")
    return path_random_key(sample_key(seed, x, y, i), bounce, dimension)
