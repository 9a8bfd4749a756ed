"""Harness building blocks: sizes and the budget rule, image error, Pareto front, rays."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import raytracer
from groundwork.sizes import Size, parse_size
from harness.engine import figures
from harness.engine.budget import Estimate, fit_to_budget, scaled, smaller_sizes
from harness.engine.plan import BENCH_CONFIGS, bench_configs, split_names
from harness.instruments.imagediff import image_error
from harness.instruments.raycount import HOOK, INSTRUMENTED, count_rays, counting_method
from harness.scenery.presets import BUILTIN_DEFAULT_WORLD, SceneRef, build_scene
from raytracer.camera import RenderSettings
from raytracer.tracer import TRACER
from variants.registry import load_variant


def test_sizes_parse_and_name_bad_input():
    assert parse_size("160x120") == Size(160, 120)
    assert parse_size(" 64 X 48 ") == Size(64, 48)
    with pytest.raises(ValueError, match=r"bad size '160': expected WIDTHxHEIGHT"):
        parse_size("160")
    with pytest.raises(ValueError, match="1 to 16384"):
        parse_size("0x10")


def test_scaling_keeps_the_aspect_ratio():
    assert scaled(Size(640, 480), 0.5) == Size(320, 240)
    assert scaled(Size(640, 480), 0.1) == Size(64, 48)
    assert scaled(Size(160, 120), 0.07) == Size(8, 6)
    assert scaled(Size(640, 480), 2.0) == Size(640, 480)
    odd = scaled(Size(173, 101), 0.5)  # no common factor: width scaled, height rounded
    assert odd == Size(86, 50)
    assert smaller_sizes(Size(160, 120), 3) == [Size(40, 30), Size(80, 60), Size(160, 120)]


def test_the_budget_rule_keeps_the_size_when_it_fits():
    choice = fit_to_budget(Size(160, 120), Estimate(0.0, 1e-5), 3, budget=10)
    assert choice.size == Size(160, 120)
    assert not choice.reduced
    assert choice.note == ""
    assert fit_to_budget(Size(160, 120), Estimate(0.0, 1.0), 3, budget=None).size == Size(160, 120)


def test_the_budget_rule_picks_a_smaller_size_of_the_same_aspect_and_says_so():
    estimate = Estimate(fixed=0.5, per_pixel=0.01)  # 160x120: 192.5 s a render
    choice = fit_to_budget(Size(160, 120), estimate, renders=4, budget=20)
    w, h = choice.size.width, choice.size.height
    assert choice.reduced
    assert w * 3 == h * 4
    assert estimate.seconds(choice.size) * 4 <= 20
    bigger = scaled(Size(160, 120), (w + 4) / 160)  # the next size up would not fit
    assert estimate.seconds(bigger) * 4 > 20
    assert choice.estimate == pytest.approx(192.5 * 4)
    assert f"measured at {w}x{h} instead of 160x120" in choice.note
    assert "over the 20 s budget" in choice.note


def test_an_estimate_separates_a_fixed_cost_from_the_cost_per_pixel():
    probes = [(Size(8, 6), 1.0 + 48 * 0.002), (Size(16, 12), 1.0 + 192 * 0.002)]
    estimate = Estimate.from_probes(probes)
    assert estimate.fixed == pytest.approx(1.0)
    assert estimate.per_pixel == pytest.approx(0.002)
    single = Estimate.from_probes(probes[:1])
    assert single.fixed == 0 and single.per_pixel == pytest.approx(1.096 / 48)


def test_probing_goes_on_until_the_cost_per_pixel_shows_above_a_start_up_cost():
    from harness.engine.child import probed_enough

    target = Size(640, 480)
    # a pool: 0.4 s to start, then cheap pixels; its first probes cost the start-up alone
    pool = [(Size(4, 3), 0.40), (Size(8, 6), 0.35)]
    assert not probed_enough(pool, target)  # long enough, but no cost per pixel visible
    assert probed_enough([*pool, (Size(96, 72), 0.95)], target)
    # a slow variant: two probes and the last above PROBE_SECONDS is enough
    assert probed_enough([(Size(4, 3), 0.2), (Size(8, 6), 1.0)], target)
    assert not probed_enough([(Size(4, 3), 0.01), (Size(8, 6), 0.04)], target)  # too short
    assert probed_enough([(Size(4, 3), 0.3)], Size(4, 3))  # the target itself
    assert not probed_enough([], target)


def test_image_error_figures():
    reference = np.zeros((2, 2, 3))
    same = image_error(reference.copy(), reference)
    assert same.max_abs == 0 and same.rmse == 0 and math.isinf(same.psnr)
    assert same.as_dict()["psnr"] is None
    image = reference.copy()
    image[0, 0, 0] = 0.5  # one channel of one pixel
    image[1, 1, 2] = 1.5  # clamped to 1 before comparing
    error = image_error(image, reference)
    assert error.max_abs == 1.0
    assert error.mean_abs == pytest.approx(1.5 / 12)
    assert error.rmse == pytest.approx(math.sqrt(1.25 / 12))
    assert error.psnr == pytest.approx(20 * math.log10(1 / error.rmse))
    assert error.pixels_over_one_step == 2
    with pytest.raises(ValueError, match="sizes differ, 3x2 against 2x2"):
        image_error(np.zeros((2, 3, 3)), reference)


def test_pareto_front_keeps_the_points_nothing_beats_in_both():
    points = [(1.0, 0.5), (2.0, 0.2), (3.0, 0.3), (4.0, 0.1), (1.5, 0.6)]
    assert figures.pareto_front(points) == [0, 1, 3]


def test_variant_lists_split_on_commas_outside_brackets():
    assert split_names("numba[float32,threads=1], cached,pooled[workers=2]:naive") == [
        "numba[float32,threads=1]",
        "cached",
        "pooled[workers=2]:naive",
    ]


def test_rays_of_the_reference_are_counted_by_kind():
    naive = load_variant("naive")
    camera, world = build_scene(SceneRef(BUILTIN_DEFAULT_WORLD, None), naive, Size(8, 6))
    counted = count_rays(naive, camera, world, RenderSettings(samples=2))
    assert counted is not None
    assert counted["camera"] == 8 * 6 * 2
    assert counted["shadow"] > 0  # the default world's spheres are lit: every hit asks
    assert counted["total"] == counted["camera"] + counted["shadow"] + counted["secondary"]
    assert counted["method"] == INSTRUMENTED


def test_cached_and_robust_cast_the_rays_naive_casts_and_nothing_global_changes():
    before = (raytracer.color_at, raytracer.is_shadowed, type(TRACER), TRACER.color_at)
    counts = {}
    for name in ("naive", "cached", "robust"):
        variant = load_variant(name)
        camera, world = build_scene(SceneRef(BUILTIN_DEFAULT_WORLD, None), variant, Size(6, 4))
        counted = count_rays(variant, camera, world, RenderSettings())
        assert counted is not None
        counts[name] = {kind: counted[kind] for kind in ("camera", "shadow", "secondary")}
        assert not type(variant.tracer).__name__.startswith("Counting")
    assert counts["cached"] == counts["naive"] == counts["robust"]
    assert counts["naive"]["camera"] == 6 * 4
    after = (raytracer.color_at, raytracer.is_shadowed, type(TRACER), TRACER.color_at)
    assert after == before and after[0] is before[0] and after[1] is before[1]
    assert raytracer.tracer.color_at is raytracer.color_at


def test_a_tracer_with_its_own_pixel_loop_is_not_counted():
    from raytracer.tracer import Tracer

    class OwnLoop(Tracer):
        def render_region(self, c, w, settings, region):
            return super().render_region(c, w, settings, region)

    class Counts(Tracer):
        def count_rays(self, camera, world, settings):
            return {"camera": 1, "shadow": 2}

    learner = dataclasses.replace(load_variant("naive"), tracer=None)
    own_loop = dataclasses.replace(load_variant("naive"), tracer=OwnLoop())
    hook = dataclasses.replace(load_variant("naive"), tracer=Counts())
    assert counting_method(learner) is None and count_rays(learner, None, None, None) is None
    assert counting_method(own_loop) is None
    assert count_rays(hook, None, None, None) == {
        "camera": 1, "shadow": 2, "total": 3, "method": HOOK,
    }  # fmt: skip


def test_bench_configs_come_from_one_table():
    assert bench_configs("numba") == BENCH_CONFIGS["numba"]
    assert "pooled[workers=2]:numba[threads=1]" in bench_configs("pooled")
    assert bench_configs("naive") == ()
    assert bench_configs(load_variant("naive")) == ()
    assert bench_configs(load_variant("pooled")) == BENCH_CONFIGS["pooled"]


def test_a_changed_result_file_does_not_make_the_tree_dirty_but_changed_code_does(tmp_path):
    import subprocess

    from harness.engine.machine import git_state

    def git(*args: str) -> None:
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "README.md").write_text("old\n")
    (tmp_path / "code.py").write_text("x = 1\n")
    git("init", "-q")
    git("add", ".")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "start")
    assert git_state(tmp_path)["dirty"] is False
    (tmp_path / "results" / "README.md").write_text("new\n")
    assert git_state(tmp_path)["dirty"] is False
    (tmp_path / "code.py").write_text("x = 2\n")
    assert git_state(tmp_path)["dirty"] is True


def test_run_names_sort_by_start_time_within_one_second():
    from datetime import UTC, datetime

    from harness.engine.results import new_stem

    first = new_stem(datetime(2026, 11, 21, 15, 5, 46, 998_000, tzinfo=UTC))
    second = new_stem(datetime(2026, 11, 21, 15, 5, 46, 999_000, tzinfo=UTC))
    later = new_stem(datetime(2026, 11, 21, 15, 5, 47, 0, tzinfo=UTC))
    assert first.startswith("bench-20261121T150546998Z-")
    assert sorted([later, second, first]) == [first, second, later]
    assert sorted([second, "bench-20261121T150545Z-ffffff"])[0].endswith("ffffff")  # older names
    stability = new_stem(datetime(2026, 11, 21, tzinfo=UTC), prefix="stability-")
    assert stability.startswith("stability-20261121T000000000Z-")


def test_probing_stops_once_two_probes_have_taken_the_rows_budget():
    """A pool whose start-up outlasts the budget (a busy machine): two probes, not a ladder of
    growing sizes that ends at the target."""
    from types import SimpleNamespace

    from groundwork.sizes import Size
    from harness.engine.child import _probe

    sizes: list[Size] = []

    def timed(size: Size, samples: int) -> SimpleNamespace:
        sizes.append(size)
        return SimpleNamespace(wall=6.0)  # all fixed cost

    renderer = SimpleNamespace(timed=timed)
    warm = {"size": [4, 3], "second": 6.0}
    found, _ = _probe(renderer, Size(160, 120), 1, warm, lambda _: None, budget=6.0)  # type: ignore[arg-type]
    assert len(sizes) == 1 and len(found["probes"]) == 2
    sizes.clear()
    _probe(renderer, Size(160, 120), 1, warm, lambda _: None)  # type: ignore[arg-type]
    assert sizes[-1] == Size(160, 120)  # no budget: up to the target itself
