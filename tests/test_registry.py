"""The variant registry: the naming grammar, canonical names, clear errors, ``rtc variants``."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from raytracer.tracer import BOOK_STEPS, PATH_STEPS
from rtc.cli import main
from steps.plugin import select_variants
from variants import registry
from variants.pooled import PooledTracer
from variants.registry import (
    Variant,
    VariantError,
    VariantSpec,
    canonical_name,
    load_variant,
    parse_bool,
    parse_variant_name,
)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("naive", VariantSpec("naive")),
        ("  cached ", VariantSpec("cached")),
        (
            "numba[float32, fastmath,threads=1]",
            VariantSpec("numba", (("float32", "true"), ("fastmath", "true"), ("threads", "1"))),
        ),
        (
            "pooled[workers=2,granularity=pixel]:prealloc",
            VariantSpec(
                "pooled", (("workers", "2"), ("granularity", "pixel")), VariantSpec("prealloc")
            ),
        ),
        (
            "pooled:pooled:naive",
            VariantSpec("pooled", (), VariantSpec("pooled", (), VariantSpec("naive"))),
        ),
        ("numba[specialize=off]", VariantSpec("numba", (("specialize", "off"),))),
    ],
)
def test_the_grammar_reads_names_options_and_inner_variants(
    text: str, expected: VariantSpec
) -> None:
    assert parse_variant_name(text) == expected


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty variant name"),
        ("pooled[workers=2", "expected ',' or ']' at column 17"),
        ("naive[", "expected an option (key=value or a flag) at column 7"),
        ("naive[x=]", "expected a value after '=' at column 9"),
        ("naive]", "expected the end of the name, '[' or ':' at column 6"),
        ("pooled:", "expected a variant name at column 8"),
        ("pooled:all", "'all' stands alone"),
        ("numba[fastmath,fastmath]", "option 'fastmath' is given twice"),
        ("3d", "expected a variant name at column 1"),
    ],
)
def test_a_malformed_name_is_an_error_that_points_at_the_column(text: str, message: str) -> None:
    with pytest.raises(VariantError) as error:
        parse_variant_name(text)
    assert message in str(error.value)
    assert isinstance(error.value, LookupError) and isinstance(error.value, ValueError)


def test_canonical_names_sort_options_and_spell_flags_bare() -> None:
    inner = Variant("naive", "", {})
    options: dict[str, object] = {"threads": 1, "fastmath": True, "specialize": False, "x": None}
    assert canonical_name("numba", options) == "numba[fastmath,specialize=off,threads=1]"
    assert canonical_name("pooled", {"workers": 2}, inner) == "pooled[workers=2]:naive"
    assert canonical_name("cached") == "cached"


@pytest.mark.parametrize(("word", "value"), [("on", True), ("true", True), ("0", False)])
def test_boolean_options_read_on_and_off(word: str, value: bool) -> None:
    assert parse_bool("numba", "fastmath", word) is value


def test_a_bad_boolean_option_names_the_variant_and_the_words() -> None:
    with pytest.raises(VariantError, match=r"variant 'numba': option fastmath='maybe' must be on"):
        parse_bool("numba", "fastmath", "maybe")


def test_naive_and_cached_reject_options_and_inner_variants() -> None:
    for name in ("naive", "cached"):
        with pytest.raises(
            VariantError, match=rf"variant '{name}' has no option 'fast'; it takes no options"
        ):
            load_variant(f"{name}[fast]")
        with pytest.raises(VariantError, match=rf"variant '{name}' does not wrap another variant"):
            load_variant(f"{name}:naive")


def test_unknown_variants_and_all_in_the_wrong_place_are_clear_errors() -> None:
    with pytest.raises(VariantError, match=r"unknown variant 'nope'; registered variants: naive"):
        load_variant("nope")
    with pytest.raises(VariantError, match=r"unknown variant 'nope'"):
        load_variant("pooled:nope")
    with pytest.raises(VariantError, match=r"'all' names several variants"):
        load_variant("all")


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("pooled[workers=0]", "option workers='0' must be a whole number 1 to 256"),
        ("pooled[workers=two]", "option workers='two' must be a whole number"),
        ("pooled[granularity=row]", "option granularity='row' must be one of line, pixel, tile"),
        ("pooled[tile=8]", "option tile=8 applies only with granularity=tile"),
        (
            "pooled[threads=2]",
            "has no option 'threads'; it accepts granularity, tile, timeout, workers",
        ),
        ("pooled[timeout=0]", "option timeout='0' must be a whole number 1 to 86400"),
    ],
)
def test_pooled_rejects_bad_options_by_name(name: str, message: str) -> None:
    with pytest.raises(VariantError) as error:
        load_variant(name)
    assert message in str(error.value)


def test_every_spelling_of_a_configuration_gets_one_canonical_name() -> None:
    a = load_variant("pooled[granularity=tile, workers=3,tile=16]:cached")
    b = load_variant("pooled[workers=3,granularity=tile]:cached")
    assert a.name == b.name == "pooled[granularity=tile,workers=3]:cached"
    c = load_variant("pooled[workers=1,granularity=tile,tile=8]")
    assert c.name == "pooled[granularity=tile,tile=8,workers=1]:naive"
    for variant in (a, c, load_variant("pooled"), load_variant("naive")):
        assert load_variant(variant.name).name == variant.name


def test_pooled_alone_wraps_naive_and_overrides_only_render() -> None:
    pooled = load_variant("pooled[workers=2]")
    naive = load_variant("naive")
    assert pooled.name == "pooled[workers=2]:naive" and pooled.base == "naive"
    assert pooled.overrides == {"render"} and pooled.steps == ("render_into",)
    assert isinstance(pooled.tracer, PooledTracer) and pooled.tracer.inner is naive.tracer
    differing = {name for name in naive.api if pooled.api[name] is not naive.api[name]}
    steps = set(BOOK_STEPS) | set(PATH_STEPS)
    assert differing == steps  # bound to the wrapper, which forwards all but render
    assert all(pooled.api[name].__self__ is pooled.tracer for name in steps)
    over_cached = load_variant("pooled[workers=2]:cached")
    assert over_cached.overrides == load_variant("cached").overrides | {"render"}


def test_select_variants_expands_all_and_keeps_each_canonical_name_once() -> None:
    selected, _ = select_variants(["all", "naive", "pooled[workers=2]:cached"])
    names = [variant.name for variant in selected]
    assert names[0] == "naive" and "cached" in names
    assert any(name.startswith("pooled[workers=") and name.endswith(":naive") for name in names)
    assert names.count("naive") == 1 and names[-1] == "pooled[workers=2]:cached"


class _FakeEntryPoint:
    def __init__(self, name: str, load: Any) -> None:
        self.name, self.value, self._load = name, f"fake.{name}:variant", load

    def load(self) -> Any:
        return self._load()


def _fake_entry_points(monkeypatch: pytest.MonkeyPatch, extra: dict[str, Any]) -> None:
    """The project's own entry points and ``extra``: a learner's package or another plugin
    installed where the suite runs is left out, so that the fakes are the only others."""
    real = {name: ep for name, ep in registry._entry_points().items() if registry.is_own(ep)}

    def fake() -> dict[str, Any]:
        return {**real, **{name: _FakeEntryPoint(name, load) for name, load in extra.items()}}

    monkeypatch.setattr(registry, "_entry_points", fake)


def _missing_dependency() -> Any:
    raise ModuleNotFoundError("No module named 'quantum_rays'")


def _broken_module() -> Any:
    raise AttributeError("module 'fake' has no attribute 'variant'")


def test_an_unavailable_variant_says_why_and_the_others_still_load(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    learner = Variant("learners", "a learner's own, zero-argument factory", {})
    _fake_entry_points(
        monkeypatch,
        {
            "quantum": _missing_dependency,
            "broken": _broken_module,
            "learners": lambda: lambda: learner,
        },
    )
    entries = {entry.name: entry for entry in registry.registry(everything=True)}
    assert set(entries) - {entry.name for entry in registry.registry()} == {
        "quantum",
        "broken",
        "learners",
    }  # ``all`` is the project's own variants: other plugins run when named
    assert entries["quantum"].reason == "ModuleNotFoundError: No module named 'quantum_rays'"
    assert "AttributeError" in entries["broken"].reason
    assert entries["naive"].available and entries["learners"].variant is learner
    with pytest.raises(VariantError, match=r"variant 'quantum' is not available here: Module"):
        load_variant("quantum")
    with pytest.raises(VariantError, match=r"variant 'learners' has no option 'x'"):
        load_variant("learners[x=1]")
    with pytest.raises(VariantError, match=r"variant 'learners' does not wrap"):
        load_variant("learners:naive")

    assert main(["variants"]) == 0
    out = capsys.readouterr().out
    assert "quantum      unavailable ModuleNotFoundError: No module named 'quantum_rays'" in out
    assert "naive        available" in out


def test_rtc_variants_lists_overrides_by_chapter_and_options(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["variants"]) == 0
    out = capsys.readouterr().out
    assert "is the reference: every book name is its own" in out
    assert "overrides ch 5: sphere; ch 7: camera, default_world;" in out
    assert "overrides ch 7: render" in out
    assert "default name: pooled[workers=" in out
    assert "options: workers=N (default: the CPU count), granularity=line|pixel|tile" in out


def test_rtc_kata_rejects_a_bad_variant_option_before_running(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "one.feature").write_text(
        "Feature: One\n  Scenario: One\n    Given a ← 1\n    Then a = 1\n", encoding="utf-8"
    )
    assert main(["kata", str(tmp_path), "--variant", "naive[fast]"]) == 2
    assert "--variant: variant 'naive' has no option 'fast'" in capsys.readouterr().err
    assert main(["kata", str(tmp_path), "--variant", "pooled[workers=2:cached"]) == 2
    assert "expected ',' or ']' at column 24, found the end" in capsys.readouterr().err


def test_a_factory_that_returns_something_else_is_reported(monkeypatch: pytest.MonkeyPatch) -> None:
    _fake_entry_points(monkeypatch, {"odd": lambda: lambda: SimpleNamespace(name="odd")})
    with pytest.raises(VariantError, match=r"its factory returned SimpleNamespace, not a Variant"):
        load_variant("odd")


def test_the_own_variants_table_is_the_installed_entry_points() -> None:
    """``registry.OWN`` (what a render looks its variant up in, without importlib.metadata's
    scan) names exactly the project's own entry points of pyproject.toml, as installed."""
    installed = {
        name: ep.value for name, ep in registry._entry_points().items() if registry.is_own(ep)
    }
    assert installed == registry.OWN
    assert next(iter(registry.OWN)) == "naive"
