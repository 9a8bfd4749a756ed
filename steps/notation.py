"""The book's notation rewritten as Python source for the evaluator.

A small scanner splits a step's text into tokens and bracket groups; a few rewrites then turn
the book's forms into calls the evaluator understands:

- ``√2``, ``√x``, ``√(a + b)``          -> ``sqrt(2)``, ``sqrt(x)``, ``sqrt((a + b))``
- ``intersections(2:A, -√2/2:s)``       -> ``intersections(intersection(2, A), ...)``
- ``from`` (a Python keyword as a name) -> ``from_``, the same in targets and expressions
- ``the first object in w``             -> ``nth_object(w, 1)``
- ``second child of g``                 -> ``nth_child(g, 2)``
- ``"FirstGroup" from parser``          -> ``group_named(parser, "FirstGroup")``
- ``bounding_box(min=p max=q)``          -> ``bounding_box(min=p, max=q)`` (the bonus chapter
  writes keyword arguments without commas; the evaluator accepts keyword arguments)
- ``bounding_box(empty)``                -> ``bounding_box()`` (``empty`` as the only argument:
  the book's word for "no arguments")
- in conditions, ``=`` -> ``==`` and ``= approximately`` -> ``==`` (equality is approximate)

Nothing here evaluates anything: the output is plain Python source text.
"""

from __future__ import annotations

import keyword
from dataclasses import dataclass, field
from functools import lru_cache

# Keywords that are operators (or constants) in an expression: they keep their meaning.
OPERATOR_KEYWORDS = frozenset({"and", "or", "not", "in", "is", "if", "else", "lambda"})
KEYWORD_CONSTANTS = frozenset({"True", "False", "None"})
ORDINALS = {
    "first": 1, "second": 2, "third": 3, "fourth": 4, "fifth": 5,
    "sixth": 6, "seventh": 7, "eighth": 8, "ninth": 9, "tenth": 10,
}  # fmt: skip

SQRT = "√"
ARROW = "←"
COMPARISONS = ("==", "!=", "<=", ">=", "<", ">", "=")
_MULTI_CHAR_OPS = ("==", "!=", "<=", ">=", "**", "//", "->")
_OPENING = {"(": ")", "[": "]", "{": "}"}


class NotationError(ValueError):
    """Text that is not the book's notation (an unbalanced bracket, a stray character)."""


@dataclass(frozen=True, slots=True)
class Token:
    """One lexical token: ``kind`` is number, string, name, op, space, sqrt or arrow."""

    kind: str
    text: str


@dataclass(slots=True)
class Group:
    """A bracketed group: the opening bracket, what it holds, and the closing bracket."""

    opening: str
    items: list[Token | Group] = field(default_factory=list)
    closing: str = ""


Item = Token | Group


def _rename(name: str) -> str:
    """A Python keyword used as a name (``from``) gets a trailing underscore."""
    if keyword.iskeyword(name) and name not in OPERATOR_KEYWORDS | KEYWORD_CONSTANTS:
        return name + "_"
    return name


def _scan_number(text: str, start: int) -> int:
    end = start
    while end < len(text) and (text[end].isdigit() or text[end] in "._"):
        end += 1
    if end < len(text) and text[end] in "eE":
        exponent = end + 1
        if exponent < len(text) and text[exponent] in "+-":
            exponent += 1
        if exponent < len(text) and text[exponent].isdigit():
            end = exponent
            while end < len(text) and text[end].isdigit():
                end += 1
    return end


def _scan_string(text: str, start: int) -> int:
    quote = text[start]
    end = start + 1
    while end < len(text):
        if text[end] == "\\":
            end += 2
            continue
        if text[end] == quote:
            return end + 1
        end += 1
    raise NotationError(f"unterminated string in {text!r}")


def tokenize(text: str) -> list[Token]:
    """Split book notation into tokens; whitespace is kept so the output reads like the input."""
    tokens: list[Token] = []
    position = 0
    while position < len(text):
        char = text[position]
        if char.isspace():
            end = position
            while end < len(text) and text[end].isspace():
                end += 1
            tokens.append(Token("space", text[position:end]))
        elif char.isdigit() or (
            char == "." and position + 1 < len(text) and text[position + 1].isdigit()
        ):
            end = _scan_number(text, position)
            tokens.append(Token("number", text[position:end]))
        elif char in "\"'":
            end = _scan_string(text, position)
            tokens.append(Token("string", text[position:end]))
        elif char.isidentifier():
            end = position + 1
            while end < len(text) and (text[end].isidentifier() or text[end].isdigit()):
                end += 1
            tokens.append(Token("name", text[position:end]))
        elif char == SQRT:
            end = position + 1
            tokens.append(Token("sqrt", char))
        elif char == ARROW:
            end = position + 1
            tokens.append(Token("arrow", char))
        elif text.startswith(_MULTI_CHAR_OPS, position):
            end = position + 2
            tokens.append(Token("op", text[position:end]))
        elif char in "()[]{},.:+-*/%<>=!@&|^~;":
            end = position + 1
            tokens.append(Token("op", char))
        else:
            raise NotationError(f"unexpected character {char!r} in {text!r}")
        position = end
    return tokens


def group(tokens: list[Token]) -> list[Item]:
    """Nest tokens into bracket groups, so rewrites can see argument lists as units."""
    root = Group("")
    stack = [root]
    for token in tokens:
        if token.kind == "op" and token.text in _OPENING:
            child = Group(token.text)
            stack[-1].items.append(child)
            stack.append(child)
        elif token.kind == "op" and token.text in _OPENING.values():
            if len(stack) == 1 or _OPENING[stack[-1].opening] != token.text:
                raise NotationError(f"unbalanced {token.text!r}")
            stack.pop().closing = token.text
        else:
            stack[-1].items.append(token)
    if len(stack) > 1:
        raise NotationError(f"unclosed {stack[-1].opening!r}")
    return root.items


def render(items: list[Item]) -> str:
    """The source text of a list of tokens and groups."""
    parts: list[str] = []
    for item in items:
        if isinstance(item, Group):
            parts.append(item.opening + render(item.items) + item.closing)
        else:
            parts.append(item.text)
    return "".join(parts)


def _is(item: Item | None, kind: str, text: str | None = None) -> bool:
    return isinstance(item, Token) and item.kind == kind and (text is None or item.text == text)


def _solid(items: list[Item]) -> list[Item]:
    """The items without whitespace tokens (for pattern matching)."""
    return [item for item in items if not _is(item, "space")]


def _call(name: str, *arguments: list[Item]) -> list[Item]:
    inner: list[Item] = []
    for index, argument in enumerate(arguments):
        if index:
            inner += [Token("op", ","), Token("space", " ")]
        inner += argument
    return [Token("name", name), Group("(", inner, ")")]


def _primary_end(items: list[Item], start: int) -> int:
    """The end of the operand that starts at ``start``: a number, or a name or group with
    trailing attribute access, calls and subscripts; ``√√x`` nests."""
    index = start
    while index < len(items) and _is(items[index], "space"):
        index += 1
    if index >= len(items):
        raise NotationError("√ needs an operand")
    item = items[index]
    if _is(item, "sqrt"):
        return _primary_end(items, index + 1)
    if _is(item, "number"):
        return index + 1
    if not (_is(item, "name") or isinstance(item, Group)):
        raise NotationError(f"√ needs a number, a name or parentheses, not {render([item])!r}")
    index += 1
    while index < len(items):
        following = items[index]
        if isinstance(following, Group) and following.opening in "([":
            index += 1
        elif _is(following, "op", ".") and index + 1 < len(items) and _is(items[index + 1], "name"):
            index += 2
        else:
            break
    return index


def _rewrite_sqrt(items: list[Item]) -> list[Item]:
    result: list[Item] = []
    index = 0
    while index < len(items):
        item = items[index]
        if _is(item, "sqrt"):
            end = _primary_end(items, index + 1)
            operand = _rewrite_sqrt(_strip(items[index + 1 : end]))
            only = operand[0] if len(operand) == 1 else None
            if isinstance(only, Group) and only.opening == "(":
                operand = only.items  # √(a + b) is sqrt(a + b)
            if result and _is(result[-1], "number"):
                result.append(Token("op", "*"))  # 2√2 is 2 * √2
            result += _call("sqrt", operand)
            index = end
        else:
            result.append(item)
            index += 1
    return result


def _strip(items: list[Item]) -> list[Item]:
    start, end = 0, len(items)
    while start < end and _is(items[start], "space"):
        start += 1
    while end > start and _is(items[end - 1], "space"):
        end -= 1
    return items[start:end]


def _split(items: list[Item], separator: str) -> list[list[Item]]:
    parts: list[list[Item]] = [[]]
    for item in items:
        if _is(item, "op", separator):
            parts.append([])
        else:
            parts[-1].append(item)
    return parts


def _rewrite_pairs(items: list[Item]) -> list[Item]:
    """``t:obj`` in a parenthesized argument list becomes ``intersection(t, obj)``."""
    arguments = _split(items, ",")
    if not any(len(_split(argument, ":")) > 1 for argument in arguments):
        return items
    rewritten: list[Item] = []
    for index, argument in enumerate(arguments):
        if index:
            rewritten.append(Token("op", ","))
        halves = _split(argument, ":")
        if len(halves) == 2:
            rewritten += _leading(argument)
            rewritten += _call("intersection", _strip(halves[0]), _strip(halves[1]))
            rewritten += _trailing(argument)
        elif len(halves) == 1:
            rewritten += argument
        else:
            raise NotationError(f"more than one ':' in {render(argument)!r}")
    return rewritten


def _leading(items: list[Item]) -> list[Item]:
    start = 0
    while start < len(items) and _is(items[start], "space"):
        start += 1
    return items[:start]


def _trailing(items: list[Item]) -> list[Item]:
    end = len(items)
    while end > 0 and _is(items[end - 1], "space"):
        end -= 1
    return items[end:]


def _rewrite_phrases(items: list[Item]) -> list[Item]:
    """``the first object in w``, ``second child of g`` and ``"G" from parser``."""
    result: list[Item] = []
    index = 0
    while index < len(items):
        item = items[index]
        match = _match_phrase(items, index)
        if match is not None:
            replacement, index = match
            result += replacement
            continue
        result.append(item)
        index += 1
    return result


def _next_solid(items: list[Item], index: int, count: int) -> list[tuple[int, Item]]:
    found: list[tuple[int, Item]] = []
    while index < len(items) and len(found) < count:
        if not _is(items[index], "space"):
            found.append((index, items[index]))
        index += 1
    return found


def _match_phrase(items: list[Item], index: int) -> tuple[list[Item], int] | None:
    item = items[index]
    if _is(item, "string"):
        ahead = _next_solid(items, index + 1, 2)
        if len(ahead) == 2 and _is(ahead[0][1], "name", "from") and _is(ahead[1][1], "name"):
            parser = Token("name", _rename(_text(ahead[1][1])))
            return _call("group_named", [parser], [item]), ahead[1][0] + 1
        return None
    words = _next_solid(items, index, 5)
    if words and _is(words[0][1], "name", "the"):
        words = words[1:]
    if len(words) < 4 or not all(_is(word, "name") for _, word in words[:4]):
        return None
    ordinal, noun, preposition, owner = (_text(word) for _, word in words[:4])
    if ordinal not in ORDINALS:
        return None
    helper = {("object", "in"): "nth_object", ("child", "of"): "nth_child"}.get((noun, preposition))
    if helper is None:
        return None
    owner_name: list[Item] = [Token("name", _rename(owner))]
    position: list[Item] = [Token("number", str(ORDINALS[ordinal]))]
    return _call(helper, owner_name, position), words[3][0] + 1


def _text(item: Item) -> str:
    return item.text if isinstance(item, Token) else render([item])


def _rewrite_names(items: list[Item]) -> list[Item]:
    return [
        Token("name", _rename(item.text))
        if isinstance(item, Token) and item.kind == "name"
        else item
        for item in items
    ]


def _rewrite_condition(items: list[Item]) -> list[Item]:
    """``=`` compares (approximately), so it becomes ``==``; ``approximately`` is dropped."""
    result: list[Item] = []
    index = 0
    while index < len(items):
        item = items[index]
        if _is(item, "op", "="):
            result.append(Token("op", "=="))
            ahead = _next_solid(items, index + 1, 1)
            if ahead and _is(ahead[0][1], "name", "approximately"):
                index = ahead[0][0] + 1
                continue
        else:
            result.append(item)
        index += 1
    return result


def _rewrite_empty(items: list[Item]) -> list[Item]:
    """``(empty)`` as a whole argument list is ``()``: ``bounding_box(empty)``."""
    solid = _solid(items)
    return [] if len(solid) == 1 and _is(solid[0], "name", "empty") else items


def _rewrite_keywords(items: list[Item]) -> list[Item]:
    """``min=p max=q`` in an argument list gets the commas the book leaves out: a
    ``name =`` that follows an argument (not a comma) starts a new one."""
    result: list[Item] = []
    for index, item in enumerate(items):
        ahead = _next_solid(items, index + 1, 1)
        is_keyword = _is(item, "name") and bool(ahead) and _is(ahead[0][1], "op", "=")
        before = _solid(result)
        if is_keyword and before and not _is(before[-1], "op", ","):
            trailing = _trailing(result)
            result = result[: len(result) - len(trailing)]
            result += [Token("op", ","), Token("space", " ")]
        result.append(item)
    return result


def _rewrite(items: list[Item], condition: bool) -> list[Item]:
    items = _rewrite_phrases(items)
    items = _rewrite_names(items)
    items = _rewrite_sqrt(items)
    if condition:
        items = _rewrite_condition(items)
    for item in items:
        if isinstance(item, Group):
            inner = _rewrite(item.items, condition=False)
            if item.opening == "(":
                inner = _rewrite_keywords(_rewrite_empty(_rewrite_pairs(inner)))
            item.items = inner
    return _implicit_products(items)


def _implicit_products(items: list[Item]) -> list[Item]:
    """``2π`` is ``2 * π`` (the number touches the name, no space between)."""
    result: list[Item] = []
    for item in items:
        if result and _is(result[-1], "number") and _is(item, "name", "π"):
            result.append(Token("op", "*"))
        result.append(item)
    return result


@lru_cache(maxsize=4096)
def to_python(text: str, condition: bool = False) -> str:
    """Python source for a book expression; ``condition=True`` for a Then step's comparison."""
    tokens = tokenize(text.strip())
    if any(token.kind == "arrow" for token in tokens):
        raise NotationError(f"'←' inside an expression: {text!r}")
    return render(_rewrite(group(tokens), condition)).strip()


def target_path(text: str) -> list[str]:
    """The names of an assignment target: ``outer.material.ambient`` -> three names.

    Keywords are renamed as in expressions (``from`` -> ``from_``).
    """
    parts = [part.strip() for part in text.strip().split(".")]
    if not parts or not all(part.isidentifier() for part in parts):
        raise NotationError(f"not a name or a dotted name: {text!r}")
    return [_rename(parts[0]), *parts[1:]]


def target_list(text: str) -> list[str] | None:
    """The targets of a tuple assignment, ``(left, right) ← ...`` (parentheses optional),
    each checked as by ``target_path``; None for a single target."""
    inner = text.strip()
    if inner.startswith("(") and inner.endswith(")"):
        inner = inner[1:-1]
    if "," not in inner:
        return None
    targets = [part.strip() for part in inner.split(",")]
    for target in targets:
        target_path(target)
    return targets


def split_assignment(text: str) -> tuple[str, str] | None:
    """``target ← expression`` split at the first ``←`` outside strings, or None."""
    offset = 0
    for token in tokenize(text):
        if token.kind == "arrow":
            return text[:offset].strip(), text[offset + 1 :].strip()
        offset += len(token.text)
    return None


def split_comparison(text: str) -> tuple[str, str, str] | None:
    """A condition split at its top-level comparison: ``(left, operator, right)``, or None.

    ``=`` and ``= approximately`` give the operator ``=``.
    """
    items = group(tokenize(text))
    found: list[tuple[int, str]] = [
        (index, item.text)
        for index, item in enumerate(items)
        if isinstance(item, Token) and item.kind == "op" and item.text in COMPARISONS
    ]
    if len(found) != 1:
        return None
    index, operator = found[0]
    left, right = render(items[:index]).strip(), render(items[index + 1 :]).strip()
    if operator == "=":
        words = right.split(None, 1)
        if words and words[0] == "approximately":
            right = words[1] if len(words) > 1 else ""
    if operator == "==":
        operator = "="
    if not left or not right:
        return None
    return left, operator, right
