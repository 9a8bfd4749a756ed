"""Flat, per-render copies of the reference's entities that the hot path reads (chapters 6,
10, and the soft shadows bonus chapter): a light (point or area) and a material.

A record is built once per render context (``TraceContext``) from the reference's objects;
during the render only an area light's ``points`` buffer is written (its cells' points for
the sample being traced).
"""

from __future__ import annotations

from collections.abc import Iterable

from raytracer.lights import AreaLight, Light
from raytracer.materials import Material
from variants.prealloc.buffers import Vec, color_buffer, tuple_buffer
from variants.prealloc.patterns import PatternRecord


class LightRecord:
    """Chapter 6: a point light as ``position`` ``[x, y, z, w]`` and ``intensity``
    ``[r, g, b]``; the soft shadows chapter's area light also as its ``corner``, one cell's
    edges ``uvec`` and ``vvec`` (``[x, y, z, w]``), ``usteps`` x ``vsteps`` = ``samples``
    cells, and ``points``: one ``[x, y, z, w]`` buffer per cell (v outer, u inner) that
    ``shading.light_points`` fills with the cells' ``point_on_light``.

    index: the light's place among the world's lights, for a render's per-sample jitter
    (``raytracer.tracer``'s contract); None for a light shaded on its own (the book's
    ``lighting`` and ``intensity_at``), which uses its ``jitter_by`` as it is, as the
    reference does. ``sampled``: this record's points come from the sample's jitter;
    ``fixed``: they never change (a one-value sequence, e.g. the default centres), so they
    are computed here, once; otherwise every use takes the next values of ``jitter_by``
    (the same sequence object as the light's, so its position moves as the reference's).
    """

    __slots__ = (
        "area",
        "corner",
        "fixed",
        "index",
        "intensity",
        "jitter_by",
        "points",
        "points_for",
        "position",
        "sampled",
        "samples",
        "usteps",
        "uvec",
        "vsteps",
        "vvec",
    )

    def __init__(self, light: Light, index: int | None = None) -> None:
        p = light.position
        self.position = [float(p.x), float(p.y), float(p.z), float(p.w)]
        self.intensity = color_buffer(light.intensity, "a light's intensity")
        self.index = index
        self.points_for: object = None  # the sample whose jitter is in ``points``
        if not isinstance(light, AreaLight):
            self.area = self.sampled = False
            self.fixed = True
            self.samples = self.usteps = self.vsteps = 1
            self.corner = self.uvec = self.vvec = self.position
            self.jitter_by = None
            self.points: list[Vec] = [self.position]
            return
        self.area = True
        self.corner = tuple_buffer(light.corner)
        self.uvec = tuple_buffer(light.uvec)
        self.vvec = tuple_buffer(light.vvec)
        self.usteps, self.vsteps, self.samples = light.usteps, light.vsteps, light.samples
        self.jitter_by = light.jitter_by
        self.sampled = light.jitter and index is not None
        self.fixed = not self.sampled and len(light.jitter_by.values) == 1
        self.points = [[0.0, 0.0, 0.0, 0.0] for _ in range(light.samples)]
        if self.fixed:  # every point from the one value (the sequence stays where it is)
            only = light.jitter_by.values[0]
            self.fill_points(only for _ in range(2 * light.samples))

    def fill_points(self, values: Iterable[float]) -> None:
        """``points`` from ``2 * samples`` jitter values: cell (u, v) takes the next two,
        u's then v's, as ``corner + uvec * (u + ju) + vvec * (v + jv)`` (naive twin:
        ``raytracer.lights.point_on_light``, its arithmetic in its order)."""
        cx, cy, cz, cw = self.corner
        ux, uy, uz, uw = self.uvec
        vx, vy, vz, vw = self.vvec
        taken = iter(values)
        points = self.points
        cell = 0
        for v in range(self.vsteps):
            for u in range(self.usteps):
                su = u + next(taken)
                sv = v + next(taken)
                out = points[cell]
                out[0] = cx + ux * su + vx * sv
                out[1] = cy + uy * su + vy * sv
                out[2] = cz + uz * su + vz * sv
                out[3] = cw + uw * su + vw * sv
                cell += 1


class MaterialRecord:
    """Chapters 6, 10, 11: a material's numbers, its colour as ``[r, g, b]``, and its
    pattern's record (or None)."""

    __slots__ = (
        "ambient",
        "color",
        "diffuse",
        "pattern",
        "reflective",
        "refractive_index",
        "shininess",
        "specular",
        "transparency",
    )

    def __init__(self, m: Material, pattern: PatternRecord | None) -> None:
        self.color = color_buffer(m.color, "a material's color")
        self.ambient = float(m.ambient)
        self.diffuse = float(m.diffuse)
        self.specular = float(m.specular)
        self.shininess = float(m.shininess)
        self.reflective = float(m.reflective)
        self.transparency = float(m.transparency)
        self.refractive_index = float(m.refractive_index)
        self.pattern = pattern
