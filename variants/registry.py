"""The variant registry: variants are found through the ``rtc.variants`` entry points, and
named everywhere by one small grammar (docs/architecture.md, "Variant names, options and
composition")::

    spec    := "all" | variant
    variant := NAME [ "[" option ("," option)* "]" ] [ ":" variant ]
    option  := KEY "=" VALUE | FLAG

``naive``, ``numba[float32,fastmath,threads=1]``, ``pooled[workers=2]:cached`` and
``pooled:pooled:naive`` are names; ``all`` (only at the top) means every available variant
of the project's own with its default options (a learner's tracer, or another project's
plugin, runs only when named).

An entry point names a factory ``variant(inner: Variant | None = None, **options: str)
-> Variant``. Option values reach it as strings (a bare ``FLAG`` as ``"true"``); the inner
variant, if the name has ``:INNER``, is already loaded. The factory checks both with the
helpers below (``reject_inner``, ``check_options``, ``parse_bool``, ``parse_int``), raising
``VariantError`` for anything it does not accept, and returns a ``Variant`` whose ``name`` is
the canonical spelling (``canonical_name``): options sorted, so that every spelling of the
same configuration gives the same name and result rows and test ids say exactly what ran.

A factory whose optional dependency is missing raises ``ImportError`` (or ``Unavailable``);
the registry then reports that variant as unavailable, with the reason, and the others
still load.
"""

from __future__ import annotations

import importlib
import inspect
import os
import re
import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple

from raytracer.api import naive_api
from raytracer.tracer import BOOK_STEPS, PATH_STEPS, RENDER_LOOP, Tracer
from variants.stubs import is_stub
from variants.wrapper import steps_overridden

GROUP = "rtc.variants"
# The project's own variants, as pyproject.toml's entry points name them (naive first; a test
# holds the two equal): found here without importlib.metadata, whose import and scan of every
# installed package cost some 30 ms of every render's start. Another package's variant (a
# learner's, a plug-in) is looked up through the entry points when it is named.
OWN = {
    "naive": "variants.naive:variant",
    "cached": "variants.cached:variant",
    "dask": "variants.dask_cluster:variant",
    "numba": "variants.numba:variant",
    "pooled": "variants.pooled:variant",
    "prealloc": "variants.prealloc:variant",
    "robust": "variants.robust:variant",
    "wavefront": "variants.wavefront:variant",
}
ALL = "all"
MAX_WRAPPED = 32  # variants inside each other in one name (NAME:INNER:...); more is a typo
IMPORT_SECONDS = 30  # a plug-in's import that takes longer is stopped and reported
_MARK = b"\x00rtc-import:"  # what the probe prints before its verdict
_PROBE = f"""
import sys
from importlib.metadata import EntryPoint
try:
    EntryPoint(*sys.argv[1:4]).load()
    verdict = "loaded"
except BaseException as error:  # SystemExit and KeyboardInterrupt too: they are the verdict
    verdict = f"{{type(error).__name__}}: {{error}}"[:300]
sys.stdout.flush()
sys.stdout.buffer.write({_MARK!r} + " ".join(verdict.split()).encode("utf-8", "replace"))
sys.stdout.flush()
"""
TRUE_WORDS = ("true", "on", "yes", "1")
FALSE_WORDS = ("false", "off", "no", "0")


class Unavailable(Exception):
    """Raised by a variant factory that cannot run here; the message says why."""


class RenderError(RuntimeError):
    """A variant's render failed for a reason outside the scene and the book's code (a worker
    process died or raised); no image was produced. ``rtc render`` reports it in one line."""


class VariantError(LookupError, ValueError):
    """A variant name that cannot be used: bad syntax, an unknown variant, an option or an
    inner variant the factory does not accept, a bad option value, or a variant that is not
    available here. The message names the variant and what it accepts."""


@dataclass(frozen=True)
class Variant:
    """A tracer, named, with the book's API it answers.

    name: the canonical name (what ``--variant`` accepts and test ids show).
    summary: one line for ``rtc variants``.
    api: the book's names (see ``raytracer.api.BOOK_API``) mapped to callables and constants;
        the pipeline's names are the tracer's bound methods (``tracer_variant`` builds it).
    tracer: the ``raytracer.tracer.Tracer`` that renders (None for a learner's own tracer,
        which answers through ``api`` alone).
    overrides: the book names whose code differs from the reference's (a wrapper's includes
        its inner variant's).
    steps: the ``Tracer`` methods whose code differs from the reference's (the same).
    base: the variant this one builds on or wraps (its canonical name), if any.
    usage: the options and inner variant the factory accepts, for ``rtc variants``.
    tolerance: the largest difference from ``naive``'s image, per colour channel, that this
        variant accepts (0: identical pixels, as every pure-Python float64 variant gives).
    differences: where this variant knowingly differs from ``naive`` beyond agreeing within
        ``tolerance``: a book name (``intersect``, ``normal_at``, ``color_at``, ``render``,
        ``world_to_object`` ...) mapped to why (float32 rounding, scaled offsets ...).
        ``tests/test_differential.py`` applies a named, documented rule to each declared name
        and holds every other name to ``tolerance``.
    """

    name: str
    summary: str
    api: Mapping[str, Any] = field(repr=False)
    tracer: Any = field(default=None, repr=False, compare=False)
    overrides: frozenset[str] = frozenset()
    steps: tuple[str, ...] = ()
    base: str | None = None
    usage: str = "none"
    tolerance: float = 0.0
    differences: Mapping[str, str] = field(default_factory=dict, compare=False)

    def world_for(self, scene: Any) -> Any:
        """What this variant renders a loaded scene file on (``Tracer.world_for``); for a
        variant without a tracer (a learner's), the book's world through its API, divided
        with its ``divide`` once it has written one."""
        if self.tracer is not None:
            return self.tracer.world_for(scene)
        divide = self.api.get("divide")
        return scene.book_world(divide=None if divide is None or is_stub(divide) else divide)


def tracer_variant(
    name: str,
    summary: str,
    tracer: Any,
    *,
    api: Mapping[str, Any] | None = None,
    overrides: Iterable[str] = (),
    base: str | None = None,
    usage: str = "none",
    tolerance: float = 0.0,
    differences: Mapping[str, str] | None = None,
) -> Variant:
    """A ``Variant`` around ``tracer``: the book's API is ``api`` (default: the reference's)
    with every pipeline name bound to ``tracer``; ``overrides`` adds the book names the
    variant changes outside the tracer (constructors of its own shapes ...)."""
    mapping = dict(api if api is not None else naive_api())
    for step in (*BOOK_STEPS, *PATH_STEPS):
        mapping[step] = getattr(tracer, step)
    steps = steps_overridden(tracer)
    book = {step for step in steps if step in BOOK_STEPS or step in PATH_STEPS}
    if set(steps) & set(RENDER_LOOP):  # chapter 7's render runs this variant's own loop
        book.add("render")
    return Variant(
        name=name,
        summary=summary,
        api=mapping,
        tracer=tracer,
        overrides=frozenset(overrides) | frozenset(book),
        steps=steps,
        base=base,
        usage=usage,
        tolerance=tolerance,
        differences=dict(differences or {}),
    )


class VariantEntry(NamedTuple):
    """One registry entry: a variant with its default options, or why it is unavailable."""

    name: str
    variant: Variant | None
    reason: str = ""

    @property
    def available(self) -> bool:
        return self.variant is not None


# ------------------------------------------------------------------------------ the grammar


class VariantSpec(NamedTuple):
    """A parsed variant name: ``NAME[options]:INNER``.

    options: (key, value) pairs in the order written (a flag's value is ``"true"``).
    """

    name: str
    options: tuple[tuple[str, str], ...] = ()
    inner: VariantSpec | None = None

    def __str__(self) -> str:
        text = self.name
        if self.options:
            text += "[" + ",".join(f"{key}={value}" for key, value in self.options) + "]"
        return text + (f":{self.inner}" if self.inner is not None else "")


_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")
_VALUE = re.compile(r"[A-Za-z0-9_.+\-:/]+")  # a scheduler address: tcp://HOST:8786


class _Parser:
    """A recursive-descent reader of one variant name; errors point at the column."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.at = 0
        self.depth = 0

    def fail(self, expected: str) -> VariantError:
        found = repr(self.text[self.at]) if self.at < len(self.text) else "the end"
        return VariantError(
            f"bad variant name {self.text!r}: expected {expected} at column {self.at + 1}, "
            f"found {found} (the form is NAME, NAME[opt=value,flag] or NAME[...]:INNER)"
        )

    def skip_spaces(self) -> None:
        while self.at < len(self.text) and self.text[self.at].isspace():
            self.at += 1

    def take(self, pattern: re.Pattern[str], expected: str) -> str:
        self.skip_spaces()
        match = pattern.match(self.text, self.at)
        if not match:
            raise self.fail(expected)
        self.at = match.end()
        return match.group()

    def peek(self, char: str) -> bool:
        self.skip_spaces()
        if self.text.startswith(char, self.at):
            self.at += 1
            return True
        return False

    def variant(self) -> VariantSpec:
        name = self.take(_WORD, "a variant name")
        if name == ALL:
            self.at -= len(name)
            raise self.fail(
                "a variant name ('all' stands alone: it cannot be wrapped or take options)"
            )
        options: list[tuple[str, str]] = []
        if self.peek("["):
            options.append(self.option(options))
            while self.peek(","):
                options.append(self.option(options))
            if not self.peek("]"):
                raise self.fail("',' or ']'")
        inner = None
        if self.peek(":"):
            self.depth += 1
            if self.depth >= MAX_WRAPPED:
                shown = self.text if len(self.text) <= 60 else self.text[:57] + "..."
                raise VariantError(
                    f"bad variant name {shown!r}: more than {MAX_WRAPPED} variants inside each "
                    "other (NAME:INNER:...)"
                )
            inner = self.variant()
        return VariantSpec(name, tuple(options), inner)

    def option(self, before: list[tuple[str, str]]) -> tuple[str, str]:
        start = self.at
        key = self.take(_WORD, "an option (key=value or a flag)")
        if any(key == seen for seen, _ in before):
            self.at = start
            self.skip_spaces()
            raise VariantError(f"bad variant name {self.text!r}: option {key!r} is given twice")
        value = self.take(_VALUE, "a value after '='") if self.peek("=") else "true"
        return key, value

    def parse(self) -> VariantSpec:
        spec = self.variant()
        self.skip_spaces()
        if self.at != len(self.text):
            raise self.fail("the end of the name, '[' or ':'")
        return spec


def parse_variant_name(text: str) -> VariantSpec:
    """``"pooled[workers=2]:cached"`` -> ``VariantSpec("pooled", (("workers", "2"),),
    VariantSpec("cached"))``; a ``VariantError`` pointing at the column for anything else."""
    if not text.strip():
        raise VariantError("empty variant name: name one, e.g. naive, cached or pooled:cached")
    return _Parser(text).parse()


# ------------------------------------------------------------------ helpers for factories


def canonical_name(
    name: str, options: Mapping[str, object] | None = None, inner: Variant | None = None
) -> str:
    """The canonical spelling: ``name[key=value,...]:inner`` with keys sorted, True as a bare
    flag, False as ``key=off``; no brackets without options. None values are left out."""
    parts = []
    for key in sorted(options or {}):
        value = (options or {})[key]
        if value is None:
            continue
        if value is True:
            parts.append(key)
        elif value is False:
            parts.append(f"{key}=off")
        else:
            parts.append(f"{key}={value}")
    text = name + (f"[{','.join(parts)}]" if parts else "")
    return text + (f":{inner.name}" if inner is not None else "")


def reject_inner(name: str, inner: Variant | None) -> None:
    """For a factory that is not a wrapper: an inner variant is a ``VariantError``."""
    if inner is not None:
        raise VariantError(
            f"variant {name!r} does not wrap another variant, so '{name}:{inner.name}' "
            f"means nothing; write {name!r} alone"
        )


def tracer_of(wrapper: str, inner: Variant) -> Tracer:
    """The inner variant's tracer, which a wrapper named ``wrapper`` hands regions to; a
    ``VariantError`` for a variant without one."""
    if not isinstance(inner.tracer, Tracer):
        raise VariantError(
            f"variant {wrapper!r} cannot wrap {inner.name!r}: it has no tracer (a "
            "raytracer.tracer.Tracer whose render_region the workers call); a variant that "
            "answers through its api alone can only render in one process"
        )
    return inner.tracer


def check_options(name: str, options: Mapping[str, str], accepted: Iterable[str] = ()) -> None:
    """A ``VariantError`` for any option not in ``accepted`` (naming the ones it takes)."""
    known = sorted(accepted)
    unknown = sorted(set(options) - set(known))
    if unknown:
        takes = f"it accepts {', '.join(known)}" if known else "it takes no options"
        raise VariantError(
            f"variant {name!r} has no option {', '.join(repr(u) for u in unknown)}; {takes}"
        )


def parse_bool(name: str, key: str, value: str) -> bool:
    """An option's text as a boolean (true/on/yes/1, false/off/no/0)."""
    word = value.strip().lower()
    if word in TRUE_WORDS:
        return True
    if word in FALSE_WORDS:
        return False
    raise VariantError(
        f"variant {name!r}: option {key}={value!r} must be on or off "
        f"({'/'.join(TRUE_WORDS)} or {'/'.join(FALSE_WORDS)})"
    )


def parse_int(name: str, key: str, value: str, low: int, high: int) -> int:
    """An option's text as a whole number from ``low`` to ``high``."""
    try:
        number = int(value)
    except ValueError:
        number = None
    if number is None or not low <= number <= high:
        raise VariantError(
            f"variant {name!r}: option {key}={value!r} must be a whole number {low} to {high}"
        )
    return number


def parse_choice(name: str, key: str, value: str, choices: Iterable[str]) -> str:
    """An option's text, which must be one of ``choices``."""
    allowed = list(choices)
    if value not in allowed:
        raise VariantError(
            f"variant {name!r}: option {key}={value!r} must be one of {', '.join(allowed)}"
        )
    return value


# ---------------------------------------------------------------------------- the registry


class OwnEntry(NamedTuple):
    """One of the project's own variants (``OWN``), loaded as its entry point would be."""

    name: str
    value: str
    group: str = GROUP

    def load(self) -> Any:
        module, _, attribute = self.value.partition(":")
        return getattr(importlib.import_module(module), attribute)


def _own_entries() -> dict[str, Any]:
    return {name: OwnEntry(name, value) for name, value in OWN.items()}


def _entry_points() -> dict[str, Any]:
    """Every registered variant's entry point, naive first (importlib.metadata's scan)."""
    # deferred: importlib.metadata's import and scan cost ~30 ms; the own variants need
    # neither (OWN)
    from importlib.metadata import entry_points

    found = {ep.name: ep for ep in entry_points().select(group=GROUP)}
    return dict(sorted(found.items(), key=lambda item: (item[0] != "naive", item[0])))


def _entry(name: str) -> Any:
    """The entry point of the variant called ``name``: an own one from ``OWN``, any other
    from the installed entry points; a ``VariantError`` listing them for an unknown name."""
    if name in OWN:
        return OwnEntry(name, OWN[name])
    eps = _entry_points()
    if name not in eps:
        known = ", ".join(eps) or "none"
        raise VariantError(f"unknown variant {name!r}; registered variants: {known}")
    return eps[name]


def variant_names() -> list[str]:
    """Every registered variant name, ``naive`` first, available or not."""
    return list(_entry_points())


def _package(ep: Any) -> str:
    """The package an entry point imports (``mine`` of ``mine.tracer:variant``)."""
    return str(ep.value).split(":")[0].split(".")[0].strip()


def _probe(ep: Any) -> None:
    """Import a plug-in's entry point in a child process first, bounded in time
    (``IMPORT_SECONDS``): an ``Unavailable`` naming its package when the import hangs,
    raises, exits (``SystemExit``, ``os._exit``) or is killed, so that none of it can take
    the command down; the import here then runs only code that has imported cleanly."""
    import subprocess  # deferred: only a plug-in's first load probes, never a render of ours

    package = _package(ep)
    path = os.pathsep.join([p for p in sys.path if p] + [os.environ.get("PYTHONPATH", "")])
    try:
        done = subprocess.run(
            [sys.executable, "-c", _PROBE, ep.name, ep.value, ep.group],
            stdin=subprocess.DEVNULL, capture_output=True, timeout=IMPORT_SECONDS,
            env={**os.environ, "PYTHONPATH": path},
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        raise Unavailable(
            f"importing its package {package!r} took more than {IMPORT_SECONDS} s (stopped)"
        ) from None
    except OSError as error:
        raise Unavailable(f"its package {package!r} cannot be tried: {error}") from None
    verdict = done.stdout.rpartition(_MARK)[2].decode("utf-8", "replace").strip()
    if verdict == "loaded":
        return
    if verdict:
        raise Unavailable(f"importing its package {package!r} raised {verdict}")
    how = f"signal {-done.returncode}" if done.returncode < 0 else f"status {done.returncode}"
    raise Unavailable(f"importing its package {package!r} ended the process ({how})")


def _factory(name: str, ep: Any) -> Callable[..., Variant]:
    """The entry point's factory; ``Unavailable`` (with the reason) if it cannot be loaded.
    A plug-in (not the project's own) is tried in a child process first (``_probe``)."""
    if isinstance(getattr(ep, "group", None), str) and not is_own(ep):  # a real entry point
        _probe(ep)
    try:
        factory: Callable[..., Variant] = ep.load()
    except (Exception, SystemExit) as error:  # a missing dependency, a module that fails
        raise Unavailable(f"{type(error).__name__}: {error}") from error
    if not callable(factory):
        raise Unavailable(f"entry point {ep.value!r} is not a factory function")
    return factory


def _call(
    name: str, factory: Callable[..., Variant], inner: Variant | None, options: dict[str, str]
) -> Variant:
    """Call a factory; a factory whose signature cannot take the options or the inner
    variant (a learner's ``def variant()``) gets a ``VariantError`` saying so."""
    arguments: dict[str, Any] = dict(options)
    if inner is not None:
        arguments["inner"] = inner
    try:
        inspect.signature(factory).bind(**arguments)
    except TypeError as error:
        if inner is not None:
            reject_inner(name, inner)
        check_options(name, options)
        raise VariantError(
            f"variant {name!r}: its factory cannot be called as "
            f"variant(inner=None, **options): {error}"
        ) from None
    except ValueError:  # no signature (a builtin): just call it
        pass
    return factory(**arguments)


def build_variant(spec: VariantSpec) -> Variant:
    """The variant a parsed name describes (its inner variant first)."""
    entry = _entry(spec.name)
    inner = build_variant(spec.inner) if spec.inner is not None else None
    try:
        factory = _factory(spec.name, entry)
        built = _call(spec.name, factory, inner, dict(spec.options))
    except (ImportError, Unavailable) as error:
        reason = (
            error.args[0] if isinstance(error, Unavailable) else f"{type(error).__name__}: {error}"
        )
        raise VariantError(f"variant {spec.name!r} is not available here: {reason}") from None
    if not isinstance(built, Variant):
        raise VariantError(
            f"variant {spec.name!r}: its factory returned {type(built).__name__}, not a Variant"
        )
    return built


def load_variant(name: str) -> Variant:
    """The variant called ``name`` (the grammar above; not ``all``); a ``VariantError``
    (a ``LookupError``) if it is malformed, unknown, unavailable or given bad options."""
    if name.strip() == ALL:
        raise VariantError("'all' names several variants; pick one here, e.g. naive or cached")
    return build_variant(parse_variant_name(name))


def _load_entry(name: str, ep: Any) -> VariantEntry:
    try:
        return VariantEntry(name, _call(name, _factory(name, ep), None, {}))
    except Unavailable as error:
        return VariantEntry(name, None, str(error))
    except Exception as error:  # a broken factory must not hide the other variants
        return VariantEntry(name, None, f"{type(error).__name__}: {error}")


def is_own(ep: Any) -> bool:
    """True for the project's own variants (an entry point into this ``variants`` package);
    False for a learner's tracer (``rtc new``) or another project's plugin."""
    return str(ep.value).split(":")[0].split(".")[0] == __name__.split(".")[0]


def registry(everything: bool = False) -> list[VariantEntry]:
    """The project's own variants with their default options (what ``all`` means), or with
    ``everything`` every registered one, a learner's and other plugins' too (``rtc
    variants``); broken ones are reported, not raised. A variant left out of ``all`` still
    loads by name (``--variant mine``)."""
    entries = _entry_points() if everything else _own_entries()
    return [_load_entry(name, ep) for name, ep in entries.items() if everything or is_own(ep)]


def available_variants() -> list[Variant]:
    """The project's own available variants with their default options (``all``)."""
    return [entry.variant for entry in registry() if entry.variant is not None]
