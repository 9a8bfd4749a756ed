"""A small, safe evaluator for the Python source that ``notation`` produces.

It walks Python's ``ast`` with an allow-list: numbers, strings, names, calls of plain names
with positional and keyword arguments (``bounding_box(min=p, max=q)``), ``+ - * /``, unary
``-`` and ``+``, attribute access (never a name starting with ``_``), subscripts
(``M[0,0]``), tuples, lists (``[s1, s2]``) and comparisons. Everything else is
refused with ``NotAllowed``; nothing is ever handed to ``eval``.

Names: in call position the variant's API wins, then the notation's own helpers (``sqrt``,
``nth_object``...), so ``color(0, 0, 0)`` is the API even when a variable is called
``color``. Elsewhere: the scenario's variables, then the API's constants (``identity_matrix``,
``EPSILON``), then the book's constants (``π``, ``true``, ``false``, ``infinity``,
``nothing``).
"""

from __future__ import annotations

import ast
import difflib
import math
import operator
from collections.abc import Callable, Collection, Mapping, Sized
from functools import lru_cache
from typing import Any

from raytracer.api import BOOK_API
from steps.compare import approx_equal, describe
from steps.errors import EvaluationError, NotAllowed, NotImplementedByVariant

BOOK_CONSTANTS: dict[str, Any] = {
    "π": math.pi,
    "true": True,
    "false": False,
    "infinity": math.inf,
    "nothing": None,
}

_BINARY: dict[type[ast.operator], Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}
_UNARY: dict[type[ast.unaryop], Callable[[Any], Any]] = {
    ast.USub: operator.neg,
    ast.UAdd: operator.pos,
}


COMPARE: dict[type[ast.cmpop], Callable[[Any, Any], bool]] = {
    ast.Eq: approx_equal,
    ast.NotEq: lambda a, b: not approx_equal(a, b),
    ast.Lt: lambda a, b: bool(a < b),
    ast.Gt: lambda a, b: bool(a > b),
    ast.LtE: lambda a, b: bool(a <= b) or approx_equal(a, b),
    ast.GtE: lambda a, b: bool(a >= b) or approx_equal(a, b),
}


def _ordinal_item(owner: Any, attribute: str, position: int, what: str) -> Any:
    items = getattr(owner, attribute, None)
    if items is None:
        raise EvaluationError(f"{what}: {describe(owner)} has no {attribute!r}")
    if not 1 <= position <= len(items):
        raise EvaluationError(f"{what}: there are only {len(items)} {attribute}")
    return list(items)[position - 1]


def nth_object(world: Any, position: int) -> Any:
    """``the first object in w``: ``w.objects[0]``."""
    return _ordinal_item(world, "objects", position, f"object {position} of the world")


def nth_child(group: Any, position: int) -> Any:
    """``first child of g``: ``g.children[0]``."""
    return _ordinal_item(group, "children", position, f"child {position} of the group")


def group_named(parser: Any, name: str) -> Any:
    """``"FirstGroup" from parser``: ``parser.groups["FirstGroup"]``."""
    groups = getattr(parser, "groups", None)
    if groups is None:
        raise EvaluationError(f"{name!r} from parser: the parser has no 'groups'")
    if name not in groups:
        known = ", ".join(repr(key) for key in groups) or "none"
        raise EvaluationError(f"{name!r} from parser: no such group (groups: {known})")
    return groups[name]


def mean(values: Any) -> float:
    """``mean(xs)``: the arithmetic mean of a list of numbers (summed in order)."""
    items = list(values)
    if not items:
        raise EvaluationError("mean() of an empty list")
    return sum(items) / len(items)


NOTATION_FUNCTIONS: dict[str, Callable[..., Any]] = {
    "sqrt": math.sqrt,
    "mean": mean,
    "nth_object": nth_object,
    "nth_child": nth_child,
    "group_named": group_named,
}


@lru_cache(maxsize=4096)
def parse_expression(source: str) -> ast.expr:
    """The expression's syntax tree (``SyntaxError`` if it is not one expression)."""
    return ast.parse(source, mode="eval").body


def is_light_like(value: object) -> bool:
    return hasattr(value, "position") and hasattr(value, "intensity")


def close_matches(name: str, candidates: Collection[str]) -> str:
    found = difflib.get_close_matches(name, [c for c in candidates if not c.startswith("_")])
    return f"; did you mean: {', '.join(found)}?" if found else ""


class Evaluator:
    """Evaluates one expression against a variant's API and a scenario's variables.

    api: the variant's mapping from book names to callables and constants.
    variables: the scenario's names (read only here).
    variant: the variant's name, for "not implemented by variant" messages.
    where: the step text, for error messages.
    """

    def __init__(
        self,
        api: Mapping[str, Any],
        variables: Mapping[str, Any],
        variant: str = "variant",
        where: str = "",
    ) -> None:
        self.api = api
        self.variables = variables
        self.variant = variant
        self.where = where

    def evaluate(self, source: str) -> Any:
        """The value of a Python expression (from ``notation.to_python``)."""
        try:
            tree = parse_expression(source)
        except SyntaxError as error:
            message = self._message(f"not an expression: {source!r} ({error.msg})")
            raise NotAllowed(message) from None
        return self.node(tree)

    def _message(self, text: str) -> str:
        return f"{self.where}: {text}" if self.where else text

    def node(self, node: ast.expr) -> Any:
        """Evaluate one allowed node."""
        if isinstance(node, ast.Constant):
            if isinstance(node.value, int | float | str | bool) or node.value is None:
                return node.value
            raise NotAllowed(self._message(f"constant {node.value!r} is not allowed"))
        if isinstance(node, ast.Name):
            return self.lookup(node.id)
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.Attribute):
            return self.attribute(self.node(node.value), node.attr)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](self.node(node.left), self.node(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _UNARY[type(node.op)](self.node(node.operand))
        if isinstance(node, ast.Tuple) and isinstance(node.ctx, ast.Load):
            return tuple(self.node(element) for element in node.elts)
        if isinstance(node, ast.List) and isinstance(node.ctx, ast.Load):
            return [self.node(element) for element in node.elts]
        if isinstance(node, ast.Compare):
            return self.compare(node)
        raise NotAllowed(
            self._message(f"{_describe_syntax(node)} is not part of the book's notation")
        )

    def lookup(self, name: str) -> Any:
        """A name outside call position: variables, API constants, book constants."""
        _check_public(name, self._message)
        if name in self.variables:
            return self.variables[name]
        if name in self.api:
            return self.api[name]
        if name in BOOK_CONSTANTS:
            return BOOK_CONSTANTS[name]
        if name in BOOK_API:
            raise NotImplementedByVariant(
                name,
                self.variant,
                self._message(f"variant {self.variant!r} does not provide the book's {name!r}"),
            )
        known = [*self.variables, *self.api, *BOOK_CONSTANTS]
        raise EvaluationError(self._message(f"unknown name {name!r}{close_matches(name, known)}"))

    def function(self, name: str) -> Callable[..., Any]:
        """A name in call position: the API first, then the notation's helpers."""
        _check_public(name, self._message)
        if name in self.api:
            found = self.api[name]
            if not callable(found):
                raise EvaluationError(self._message(f"{name!r} is a constant, not a function"))
            return found
        if name in NOTATION_FUNCTIONS:
            return NOTATION_FUNCTIONS[name]
        if name in BOOK_API:
            text = f"variant {self.variant!r} does not provide the book's {name}()"
        else:
            hint = close_matches(name, [*self.api, *NOTATION_FUNCTIONS])
            text = f"{name}() is not a book function, nor provided by variant {self.variant!r}"
            text += hint
        raise NotImplementedByVariant(name, self.variant, self._message(text))

    def call(self, node: ast.Call) -> Any:
        if not isinstance(node.func, ast.Name):
            raise NotAllowed(self._message("only named functions can be called (no methods)"))
        if any(keyword.arg is None for keyword in node.keywords):
            raise NotAllowed(self._message("**arguments are not part of the notation"))
        if any(isinstance(argument, ast.Starred) for argument in node.args):
            raise NotAllowed(self._message("*arguments are not part of the notation"))
        name = node.func.id
        function = self.function(name)
        arguments = [self.node(argument) for argument in node.args]
        keywords: dict[str, Any] = {}
        for keyword in node.keywords:
            assert keyword.arg is not None  # checked above
            _check_public(keyword.arg, self._message)
            keywords[keyword.arg] = self.node(keyword.value)
        if name == "lighting":
            arguments = self.adapt_lighting(arguments)
        return function(*arguments, **keywords)

    def adapt_lighting(self, arguments: list[Any]) -> list[Any]:
        """``lighting(m, light, point, eyev, normalv[, in_shadow])`` (before chapter 10)
        gets a default object (a sphere) as its second argument."""
        if len(arguments) in (5, 6) and is_light_like(arguments[1]):
            return [arguments[0], self.function("sphere")(), *arguments[1:]]
        return arguments

    def attribute(self, value: Any, name: str) -> Any:
        """``value.name``; ``xs.count`` on a sized sequence is its length."""
        _check_public(name, self._message)
        if name == "count":
            count = getattr(value, "count", None)
            if (count is None or callable(count)) and isinstance(value, Sized):
                return len(value)
        try:
            return getattr(value, name)
        except AttributeError:
            public = [attr for attr in dir(value) if not attr.startswith("_")]
            raise EvaluationError(
                self._message(
                    f"{describe(value)} has no attribute {name!r}{close_matches(name, public)}"
                )
            ) from None

    def subscript(self, node: ast.Subscript) -> Any:
        if isinstance(node.slice, ast.Slice):
            raise NotAllowed(self._message("slices are not part of the notation"))
        value = self.node(node.value)
        index = self.node(node.slice)
        try:
            return value[index]
        except (IndexError, KeyError) as error:
            size = f" (it has {len(value)} items)" if isinstance(value, Sized) else ""
            raise EvaluationError(
                self._message(f"{ast.unparse(node)}: no item {index!r}{size}: {error}")
            ) from None

    def compare(self, node: ast.Compare) -> bool:
        left = self.node(node.left)
        for operation, right_node in zip(node.ops, node.comparators, strict=True):
            if type(operation) not in COMPARE:
                raise NotAllowed(
                    self._message(f"{_describe_syntax(operation)} is not a book comparison")
                )
            right = self.node(right_node)
            if not COMPARE[type(operation)](left, right):
                return False
            left = right
        return True


def _check_public(name: str, message: Callable[[str], str]) -> None:
    if name.startswith("_"):
        raise NotAllowed(message(f"names starting with '_' are not allowed: {name!r}"))


_SYNTAX_NAMES = {
    "Lambda": "a lambda",
    "ListComp": "a list comprehension",
    "SetComp": "a set comprehension",
    "DictComp": "a dict comprehension",
    "GeneratorExp": "a generator expression",
    "IfExp": "a conditional expression",
    "BoolOp": "and/or",
    "NamedExpr": "':='",
    "Await": "await",
    "Yield": "yield",
    "YieldFrom": "yield",
    "JoinedStr": "an f-string",
    "Dict": "a dict",
    "Set": "a set",
    "Starred": "*",
    "Is": "'is'",
    "IsNot": "'is not'",
    "In": "'in'",
    "NotIn": "'not in'",
    "Pow": "'**'",
    "Mod": "'%'",
    "FloorDiv": "'//'",
    "MatMult": "'@'",
    "Not": "'not'",
    "Invert": "'~'",
}


def _describe_syntax(node: ast.AST) -> str:
    if isinstance(node, ast.BinOp | ast.UnaryOp):
        return _SYNTAX_NAMES.get(type(node.op).__name__, type(node.op).__name__)
    return _SYNTAX_NAMES.get(type(node).__name__, type(node).__name__)
