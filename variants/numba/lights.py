"""Packing a world's lights (chapter 6's point lights, the bonus chapter's area lights)
into the light table the kernels read (``layout``: one row of ``NLIGHT`` columns per light,
then the area lights' sequences of jitter values).

How an area light's cells are sampled (``raytracer.lights``, ``raytracer.tracer``):

- jittered (``jitter`` True), in a render or ``shade_hit``: at random, by the sample's key
  (``raytracer.sampling.light_jitter``), which the kernels compute themselves;
- otherwise by its ``jitter_by`` sequence, whose values the reference takes in turn,
  2 per cell, ``2 * samples`` in ``intensity_at`` and as many in ``lighting``. In a render
  the sequence is shared by every point shaded, so the kernels can reproduce it only when
  its length divides ``2 * samples`` (every call then starts where the sequence stands);
  any other sequence is refused (``PackError``). One ``lighting`` or ``intensity_at`` call
  (``for_one_call``) packs the very values that call takes, whatever the length, and moves
  the sequence on by as many, as the reference does.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from raytracer.lights import AreaLight, CyclicSequence, PointLight
from variants.arrays.rows import rgb, xyz
from variants.numba import layout as L
from variants.numba.errors import PackError


def _sequence_values(light: AreaLight, where: str, for_one_call: bool) -> tuple[list[float], int]:
    """(the values to pack, the position to start from) of ``light.jitter_by``."""
    sequence = light.jitter_by
    if not isinstance(sequence, CyclicSequence):
        raise PackError(f"numba: {where} jitters by a {type(sequence).__name__}, not a sequence")
    values = [float(v) for v in sequence.values]
    taken = 2 * light.samples
    if for_one_call:
        start = sequence.position
        return [values[(start + j) % len(values)] for j in range(taken)], 0
    if taken % len(values) != 0:
        raise PackError(
            f"numba: {where} jitters by a sequence of {len(values)} values, which does not "
            f"divide the {taken} values (2 per cell) each shaded point takes from it: the "
            "reference's picture would then depend on the order in which points are shaded, "
            "which the kernels do not follow; use a sequence whose length divides "
            f"{taken}, or jitter: true"
        )
    return values, sequence.position


def light_rows(
    lights: Sequence[Any], dtype: Any, *, for_one_call: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """(rows, values): one row per light (``NLIGHT`` columns, ``dtype``) and the area lights'
    sequence values after them. ``for_one_call``: for one ``lighting`` or ``intensity_at``
    call, which takes ``jitter_by`` as it is (jittered or not) from where it stands."""
    rows = np.zeros((len(lights), L.NLIGHT), dtype=dtype)
    values: list[float] = []
    for k, light in enumerate(lights):
        where = f"light {k} of the world"
        if isinstance(light, AreaLight):
            row = [0.0] * L.NLIGHT
            row[L.LIGHT_POSITION : L.LIGHT_POSITION + 3] = xyz(light.position)
            row[L.LIGHT_INTENSITY : L.LIGHT_INTENSITY + 3] = rgb(light.intensity)
            row[L.LIGHT_CORNER : L.LIGHT_CORNER + 3] = xyz(light.corner)
            row[L.LIGHT_UVEC : L.LIGHT_UVEC + 3] = xyz(light.uvec)
            row[L.LIGHT_VVEC : L.LIGHT_VVEC + 3] = xyz(light.vvec)
            row[L.LIGHT_USTEPS] = float(light.usteps)
            row[L.LIGHT_VSTEPS] = float(light.vsteps)
            if light.jitter and not for_one_call:
                row[L.LIGHT_JITTER] = 1.0
            else:
                own, start = _sequence_values(light, f"{where} (an area light)", for_one_call)
                row[L.LIGHT_SEQ] = float(len(values))
                row[L.LIGHT_SEQ_N] = float(len(own))
                row[L.LIGHT_SEQ_AT] = float(start)
                values += own
            rows[k] = row
        elif isinstance(light, PointLight):
            rows[k, 0:6] = xyz(light.position) + rgb(light.intensity)
        else:
            raise PackError(
                f"numba: {where} is a {type(light).__name__}; the kernels know point lights "
                "and area lights"
            )
    return rows, np.array(values, dtype=dtype)


def move_on(light: Any) -> None:
    """After one ``lighting`` or ``intensity_at`` call with an area light: its sequence
    moves on by the ``2 * samples`` values the call took (the reference's side effect)."""
    if isinstance(light, AreaLight) and isinstance(light.jitter_by, CyclicSequence):
        for _ in range(2 * light.samples):
            next(light.jitter_by)


def describe(rows: np.ndarray) -> list[str]:
    """What the light table holds, for ``explain``."""
    area = rows[:, L.LIGHT_USTEPS] > 0 if len(rows) else np.zeros(0, dtype=bool)
    lines = []
    for k in np.flatnonzero(area).tolist():
        usteps, vsteps = int(rows[k, L.LIGHT_USTEPS]), int(rows[k, L.LIGHT_VSTEPS])
        how = (
            "jittered at random per sample (light_jitter)"
            if rows[k, L.LIGHT_JITTER]
            else f"sampled by its sequence of {int(rows[k, L.LIGHT_SEQ_N])} values"
        )
        lines.append(
            f"light {k}: an area light of {usteps}x{vsteps} = {usteps * vsteps} cells, {how}; "
            "a shadow ray per cell at every shaded point"
        )
    return lines
