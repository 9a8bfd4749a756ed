"""Threads that scale (issue 36, item 3): numba's threads take chunks of rows as they ask
(``variants.numba.render.Rows``), so a thread the machine slows does not hold the others
back, and a pixel is the same whichever thread renders it.

No verdict here depends on the machine's speed: a thread is held by the test (an event it
sets), never timed."""

from __future__ import annotations

import dataclasses
import itertools
import threading
import types
from typing import Any

import numpy as np
import pytest
from book_world import default_scene

from raytracer.camera import RenderSettings
from variants.numba import render as numba_render
from variants.numba.render import Rows, run_region
from variants.registry import load_variant


def _deal(rows: Rows, most: int | None = None) -> list[tuple[int, int]]:
    dealt = []
    while (chunk := rows.take(most))[0] < chunk[1]:
        dealt.append(chunk)
    return dealt


@pytest.mark.parametrize("threads", [2, 3, 8])
def test_rows_are_dealt_once_each_in_shrinking_chunks(threads: int) -> None:
    dealt = _deal(Rows(480, threads))
    assert dealt[0][0] == 0 and dealt[-1][1] == 480
    assert all(a[1] == b[0] for a, b in itertools.pairwise(dealt))  # no gap, no overlap
    sizes = [end - first for first, end in dealt]
    assert sizes[0] == -(-480 // (numba_render.SHARE * threads))
    assert all(b <= a for a, b in itertools.pairwise(sizes)) and sizes[-1] == 1
    assert len(dealt) >= 2 * threads  # enough chunks that the threads end together


def test_one_thread_takes_every_row_at_once_and_most_caps_a_chunk() -> None:
    assert _deal(Rows(480, 1)) == [(0, 480)]
    assert _deal(Rows(10, 1), most=4) == [(0, 4), (4, 8), (8, 10)]
    assert _deal(Rows(0, 2)) == []


def test_a_held_numba_thread_leaves_the_other_rows_to_the_free_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Thread 1 is held inside its first chunk until every other row has been handed
    out: the calling thread renders all of them (a static split would have left thread 1
    half the rows), and the picture is one thread's, bit for bit."""
    variant = load_variant("numba[threads=2]")
    c, w = default_scene(variant, 12, 40)
    settings = RenderSettings()
    alone = load_variant("numba[threads=1]").api["render"](c, w, settings).array
    frame = variant.tracer.prepared(c, w, settings)
    assert frame.threads == 2
    kernel = frame.renderer.function
    all_dealt = threading.Event()
    rows_by_thread = [0, 0]

    class Watched(Rows):
        def take(self, most: int | None = None) -> tuple[int, int]:
            chunk = super().take(most)
            if chunk[0] == chunk[1]:
                all_dealt.set()
            return chunk

    def held(*args: Any) -> int:
        top, bottom, k = args[2], args[4], args[5]
        if threading.current_thread() is not threading.main_thread():
            all_dealt.wait()
            k = 1
        rows_by_thread[k] += bottom - top
        return int(kernel(*args))

    frame = dataclasses.replace(frame, renderer=types.SimpleNamespace(function=held))
    monkeypatch.setattr(numba_render, "Rows", Watched)
    image = run_region(frame, (0, 0, 12, 40))
    assert sum(rows_by_thread) == 40
    assert rows_by_thread[1] <= -(-40 // (2 * numba_render.SHARE))  # its one chunk at most
    assert rows_by_thread[0] >= 40 - rows_by_thread[1] > 20
    assert np.array_equal(image, alone)
