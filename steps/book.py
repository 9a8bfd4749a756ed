"""One scenario's namespace: its variables, bound to one variant's API.

Every scenario gets a fresh ``Book``; nothing is shared between scenarios.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from steps.compare import is_color_like, is_number, is_tuple_like
from steps.errors import EvaluationError, NotImplementedByVariant, UndefinedStep
from steps.evaluator import Evaluator, close_matches, parse_expression
from steps.notation import NotationError, target_list, target_path, to_python


class Book:
    """The names a scenario has bound, and the variant's API they are evaluated against.

    api: the variant's mapping from book names to callables and constants.
    variant: the variant's name (for messages).
    feature_file: the feature file being run (``the file "x.obj"`` is looked up beside it).
    """

    def __init__(
        self, api: Mapping[str, Any], variant: str = "naive", feature_file: Path | None = None
    ) -> None:
        self.api = api
        self.variant = variant
        self.feature_file = feature_file
        self.variables: dict[str, Any] = {}
        self.step = ""  # the step being run, for error messages

    def evaluate(self, text: str, condition: bool = False) -> Any:
        """The value of a book expression (``condition=True``: ``=`` compares)."""
        try:
            source = to_python(text, condition)
            parse_expression(source)
        except NotationError as error:
            raise UndefinedStep(f"{self.step}: cannot read {text!r}: {error}") from None
        except SyntaxError as error:
            raise UndefinedStep(
                f"{self.step}: {text!r} is not an expression the step library can read"
                f" ({error.msg})"
            ) from None
        return Evaluator(self.api, self.variables, self.variant, self.step).evaluate(source)

    def function(self, name: str) -> Any:
        """The variant's function for a book name, or an "undefined" error naming the variant."""
        found = self.api.get(name)
        if found is None:
            raise NotImplementedByVariant(
                name,
                self.variant,
                f"{self.step}: variant {self.variant!r} does not provide the book's {name}()",
            )
        return found

    def call(self, name: str, *arguments: Any) -> Any:
        return self.function(name)(*arguments)

    def assign(self, target: str, value: Any) -> None:
        """``target ← value`` where target is a name or a dotted path.

        A mutable owner is changed in place; a frozen dataclass is replaced by an updated
        copy, which is stored back into its owner (or rebinds the scenario's name).
        A tuple target, ``(left, right) ← ...``, takes the value's items one by one.
        """
        try:
            targets = target_list(target)
        except NotationError as error:
            raise UndefinedStep(f"{self.step}: {error}") from None
        if targets is not None:
            self._assign_each(targets, value)
            return
        try:
            root, *attributes = target_path(target)
        except NotationError as error:
            raise UndefinedStep(f"{self.step}: {error}") from None
        if not attributes:
            self.variables[root] = value
            return
        owners = [self.resolve(root)]
        for name in attributes[:-1]:
            owners.append(self._attribute(owners[-1], name))
        value = self.coerce(getattr(owners[-1], attributes[-1], None), value)
        updated = _with_attribute(owners[-1], attributes[-1], value, self.step)
        for owner, name, before in zip(
            reversed(owners[:-1]), reversed(attributes[:-1]), reversed(owners[1:]), strict=True
        ):
            if updated is before:
                return  # changed in place: the owners already hold it
            updated = _with_attribute(owner, name, updated, self.step)
        if updated is not owners[0]:
            self.variables[root] = updated

    def _assign_each(self, targets: list[str], value: Any) -> None:
        try:
            items = list(value)
        except TypeError:
            raise EvaluationError(
                f"{self.step}: {len(targets)} names to assign, but the value is "
                f"{type(value).__name__}, not a tuple or a list"
            ) from None
        if len(items) != len(targets):
            raise EvaluationError(
                f"{self.step}: {len(targets)} names to assign, but the value has {len(items)} items"
            )
        for target, item in zip(targets, items, strict=True):
            self.assign(target, item)

    def resolve(self, name: str) -> Any:
        """A scenario variable (the root of an assignment target)."""
        if name not in self.variables:
            hint = close_matches(name, list(self.variables))
            raise EvaluationError(f"{self.step}: {name!r} has no value yet{hint}")
        return self.variables[name]

    def _attribute(self, owner: Any, name: str) -> Any:
        try:
            return getattr(owner, name)
        except AttributeError:
            raise EvaluationError(
                f"{self.step}: {type(owner).__name__} has no attribute {name!r}"
            ) from None

    def coerce(self, current: Any, value: Any) -> Any:
        """A Python tuple assigned over a colour becomes a colour (``(0.8, 1.0, 0.6)``),
        over a point or vector a point or vector."""
        if not isinstance(value, tuple) or not all(is_number(item) for item in value):
            return value
        if is_color_like(current) and len(value) == 3:
            return self.call("color", *value)
        if is_tuple_like(current) and len(value) == 4:
            return self.call("tuple", *value)
        if is_tuple_like(current) and len(value) == 3:
            return self.call("point" if current.w == 1 else "vector", *value)
        return value

    def file_path(self, name: str) -> Path:
        """``the file "NAME"``: beside the feature file, or in ``files/`` next to it."""
        folder = self.feature_file.parent if self.feature_file else Path.cwd()
        candidates = [folder / name, folder / "files" / name]
        for candidate in candidates:
            if candidate.is_file():
                return candidate
        looked = ", ".join(str(candidate) for candidate in candidates)
        raise EvaluationError(f"{self.step}: no file {name!r}; looked in {looked}")


def _with_attribute(owner: Any, name: str, value: Any, step: str) -> Any:
    """``owner`` with ``name`` set: the same object if it is mutable, else an updated copy."""
    try:
        setattr(owner, name, value)
        return owner
    except (AttributeError, TypeError) as error:
        problem = error
    if dataclasses.is_dataclass(owner) and not isinstance(owner, type):
        settable = {field.name for field in dataclasses.fields(owner) if field.init}
        if name in settable:
            return dataclasses.replace(owner, **{name: value})
    replace = getattr(owner, "_replace", None)  # a namedtuple
    if callable(replace):
        return replace(**{name: value})
    raise EvaluationError(f"{step}: cannot set {name!r} on {type(owner).__name__}: {problem}")
