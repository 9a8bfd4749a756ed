"""The step forms of the book's notation: an ordered table per step type, first match wins.

Given / When forms bind names and change things; Then forms check. Each form is a small
handler ``(book, match, table, text)``; ``table`` is the step's data table (rows of strings)
and ``text`` its doc string. A step that no form reads raises ``UndefinedStep``; a failed
check raises ``AssertionError`` naming the step and describing both sides.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from pytest_bdd.exceptions import StepDefinitionNotFoundError

from steps.book import Book
from steps.compare import approx_equal, describe, is_number, matrix_shape, numbers_equal
from steps.errors import CheckFailed, EvaluationError, NotWrittenYet, StepError, UndefinedStep
from steps.evaluator import parse_expression
from steps.notation import NotationError, split_comparison, to_python

Table = Sequence[Sequence[str]]
Handler = Callable[[Book, re.Match[str], Table | None, str | None], None]


@dataclass(frozen=True)
class Phrase:
    """One step form: a pattern over the whole step text, its handler, what it needs."""

    pattern: re.Pattern[str]
    handler: Handler
    needs: str = ""  # "table", "doc string" or ""


def phrase(pattern: str, needs: str = "") -> Callable[[Handler], Phrase]:
    def decorate(handler: Handler) -> Phrase:
        return Phrase(re.compile(pattern), handler, needs)

    return decorate


# ----------------------------------------------------------------------------- helpers


def _check(ok: bool, book: Book, expected: str, got: str) -> None:
    __tracebackhide__ = True
    if not ok:
        raise CheckFailed(f"{book.step}\n  expected: {expected}\n  got:      {got}")


def _cells(table: Table | None) -> list[list[str]]:
    return [[cell.strip() for cell in row] for row in table or []]


def _matrix_rows(book: Book, table: Table | None, size: re.Match[str]) -> list[list[Any]]:
    rows = [[book.evaluate(cell) for cell in row] for row in _cells(table)]
    if size.group("rows"):
        wanted = (int(size.group("rows")), int(size.group("cols")))
        found = (len(rows), len(rows[0]) if rows else 0)
        if found != wanted or any(len(row) != wanted[1] for row in rows):
            raise EvaluationError(f"{book.step}: the table is {found[0]}x{found[1]}, not {wanted}")
    return rows


def _key_value_rows(book: Book, table: Table | None) -> list[tuple[str, Any]]:
    rows = []
    for row in _cells(table):
        if len(row) != 2:
            raise EvaluationError(f"{book.step}: each row needs | key | value |, got {row}")
        rows.append((row[0], book.evaluate(row[1])))
    return rows


def _call_for_effect(book: Book, text: str) -> None:
    """``f(args)`` alone; a functional variant's result of the first argument's type
    rebinds that argument's name (``write_pixel`` returning a new canvas)."""
    try:
        tree = parse_expression(to_python(text))
    except (NotationError, SyntaxError):
        tree = None
    if not isinstance(tree, ast.Call):
        raise UndefinedStep(f"no step form reads {book.step!r}")
    result = book.evaluate(text)
    first = tree.args[0] if tree.args else None
    name = getattr(first, "id", None)
    if result is not None and name in book.variables and type(result) is type(book.variables[name]):
        book.variables[name] = result


def _rows_of(value: Any) -> list[list[Any]] | None:
    shape = matrix_shape(value)
    if shape is None:
        return None
    return [[value[r, c] for c in range(shape[1])] for r in range(shape[0])]


def _table_text(rows: list[list[Any]]) -> str:
    return " ".join("| " + " | ".join(describe(cell) for cell in row) + " |" for row in rows)


def _items_of(value: Any) -> Any:
    """What ``is empty`` counts: a group's children, a world's objects, or the value."""
    for attribute in ("children", "objects"):
        if hasattr(value, attribute) and not hasattr(value, "__len__"):
            return getattr(value, attribute)
    return value


def _is_boolean(value: Any) -> bool:
    return isinstance(value, bool) or type(value).__name__ == "bool_"


# ----------------------------------------------------------------------------- Given / When


@phrase(r"the following (?:(?P<rows>\d+)x(?P<cols>\d+) )?matrix (?P<name>\S+):", "table")
def _following_matrix(book: Book, m: re.Match[str], table: Table | None, _: str | None) -> None:
    book.assign(m["name"], book.call("matrix", _matrix_rows(book, table, m)))


@phrase(r"(?P<target>[^←]+?)\s*←\s*a file containing:?", "doc string")
def _file_containing(book: Book, m: re.Match[str], _: Table | None, text: str | None) -> None:
    book.assign(m["target"], text)


@phrase(r'(?P<target>[^←]+?)\s*←\s*the file "(?P<name>[^"]+)"')
def _the_file(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    book.assign(m["target"], book.file_path(m["name"]).read_text(encoding="utf-8"))


@phrase(r"(?P<target>[^←]+?)\s*←\s*(?P<expr>.+?)\s+with:", "table")
def _assign_with(book: Book, m: re.Match[str], table: Table | None, _: str | None) -> None:
    book.assign(m["target"], book.evaluate(m["expr"]))
    for key, value in _key_value_rows(book, table):
        book.assign(f"{m['target'].strip()}.{key}", value)


@phrase(r"(?P<target>[^←]+?)\s+has:", "table")
def _has(book: Book, m: re.Match[str], table: Table | None, _: str | None) -> None:
    for key, value in _key_value_rows(book, table):
        book.assign(f"{m['target'].strip()}.{key}", value)


@phrase(r"(?P<shape>[^←]+?) is added to (?P<world>[^←]+)")
def _added_to(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    shape, world = book.evaluate(m["shape"]), book.evaluate(m["world"])
    lights = getattr(world, "lights", None)
    if hasattr(shape, "intensity") and lights is not None and hasattr(lights, "append"):
        lights.append(shape)  # a light
        return
    objects = getattr(world, "objects", None)
    if objects is None and _is_box_like(world):
        _added_to_box(book, m["world"], world, shape)
        return
    if objects is None:
        raise EvaluationError(f"{book.step}: {describe(world)} has no 'objects'")
    if hasattr(objects, "append"):
        objects.append(shape)
    else:
        book.assign(f"{m['world'].strip()}.objects", type(objects)([*objects, shape]))


def _is_box_like(value: Any) -> bool:
    return hasattr(value, "min") and hasattr(value, "max")


def _added_to_box(book: Book, target: str, box: Any, value: Any) -> None:
    """The bonus chapter's ``p is added to box`` (``add_point``) and ``box2 is added to
    box1`` (``add_box``); a returned box (an immutable one) rebinds the target."""
    function = "add_box" if _is_box_like(value) else "add_point"
    result = book.call(function, box, value)
    if result is not None and type(result) is type(box):
        book.assign(target, result)


@phrase(r"every pixel of (?P<canvas>[^←]+?) is set to (?P<expr>.+)")
def _set_every_pixel(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    original, color = book.evaluate(m["canvas"]), book.evaluate(m["expr"])
    write_pixel = book.function("write_pixel")
    canvas = original
    for y in range(canvas.height):
        for x in range(canvas.width):
            result = write_pixel(canvas, x, y, color)
            if result is not None and type(result) is type(canvas):
                canvas = result  # a functional canvas: keep the newest
    if canvas is not original:
        book.assign(m["canvas"], canvas)


# ``... for each NAME from FIRST to LAST`` (whole numbers, both included) or ``... for each
# NAME in LIST``: a step repeated with NAME bound to each value in turn (chapter 21's
# statistics over many samples)
_EACH = (
    r"\s+for each (?P<name>[A-Za-z_]\w*)"
    r" (?:from (?P<first>-?\d+) to (?P<last>-?\d+)|in (?P<items>.+))"
)


def _each(book: Book, m: re.Match[str]) -> Iterator[Any]:
    """Bind ``m["name"]`` to each value of the loop in turn (restoring what it was)."""
    if m["items"] is not None:
        values = list(book.evaluate(m["items"]))
    else:
        values = list(range(int(m["first"]), int(m["last"]) + 1))
    name = m["name"]
    before = book.variables.get(name, _UNBOUND)
    try:
        for value in values:
            book.variables[name] = value
            yield value
    finally:
        if before is _UNBOUND:
            book.variables.pop(name, None)
        else:
            book.variables[name] = before


_UNBOUND = object()


@phrase(r"(?P<target>[^←]+?)\s*←\s*(?P<expr>.+?)" + _EACH)
def _assign_each(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    book.assign(m["target"], [book.evaluate(m["expr"]) for _ in _each(book, m)])


@phrase(r"(?P<target>[^←]+?)\s*←\s*(?P<expr>.+)")
def _assign(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    book.assign(m["target"], book.evaluate(m["expr"]))


@phrase(r"(?P<call>[^←]+\))")
def _call(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    _call_for_effect(book, m["call"])


GIVEN_WHEN: list[Phrase] = [
    _following_matrix,
    _file_containing,
    _the_file,
    _assign_with,
    _has,
    _added_to,
    _set_every_pixel,
    _assign_each,
    _assign,
    _call,
]


# ----------------------------------------------------------------------------- Then


@phrase(r"(?P<expr>.+?) is the following (?:(?P<rows>\d+)x(?P<cols>\d+) )?matrix:", "table")
def _is_matrix(book: Book, m: re.Match[str], table: Table | None, _: str | None) -> None:
    actual = book.evaluate(m["expr"])
    expected = _matrix_rows(book, table, m)
    rows = _rows_of(actual)
    ok = rows is not None and approx_equal(rows, expected)
    _check(ok, book, _table_text(expected), _table_text(rows) if rows else describe(actual))


@phrase(r"every pixel of (?P<canvas>.+?) is (?P<expr>.+)")
def _every_pixel(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    canvas, expected = book.evaluate(m["canvas"]), book.evaluate(m["expr"])
    pixel_at = book.function("pixel_at")
    for y in range(canvas.height):
        for x in range(canvas.width):
            actual = pixel_at(canvas, x, y)
            _check(
                approx_equal(actual, expected),
                book,
                describe(expected),
                f"{describe(actual)} at pixel ({x}, {y})",
            )


@phrase(r"lines (?P<first>\d+)-(?P<last>\d+) of (?P<expr>.+?) are:?", "doc string")
def _lines_are(book: Book, m: re.Match[str], _: Table | None, text: str | None) -> None:
    actual_text = book.evaluate(m["expr"])
    lines = str(actual_text).split("\n")[int(m["first"]) - 1 : int(m["last"])]
    expected = (text or "").split("\n")
    indent = "\n    "
    _check(lines == expected, book, indent + indent.join(expected), indent + indent.join(lines))


@phrase(r"(?P<expr>.+?) ends with a newline character")
def _ends_with_newline(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    text = book.evaluate(m["expr"])
    _check(str(text).endswith("\n"), book, "text ending with '\\n'", repr(str(text)[-20:]))


@phrase(r"(?P<world>.+?) contains no objects")
def _no_objects(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    objects = book.evaluate(m["world"]).objects
    _check(len(objects) == 0, book, "no objects", describe(list(objects)))


@phrase(r"(?P<world>.+?) has no light source")
def _no_light(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    light = getattr(book.evaluate(m["world"]), "light", None)
    _check(light is None, book, "no light", describe(light))


@phrase(r"(?P<world>.+?) contains (?P<expr>.+)")
def _contains(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    objects, wanted = book.evaluate(m["world"]).objects, book.evaluate(m["expr"])
    found = any(item is wanted or approx_equal(item, wanted) for item in objects)
    _check(found, book, f"an object equal to {describe(wanted)}", describe(list(objects)))


@phrase(r"(?P<group>.+?) includes (?P<expr>.+)")
def _includes(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    children, wanted = book.evaluate(m["group"]).children, book.evaluate(m["expr"])
    found = any(child is wanted or approx_equal(child, wanted) for child in children)
    _check(found, book, f"a child equal to {describe(wanted)}", describe(list(children)))


@phrase(r"(?P<expr>.+?) should terminate successfully")
def _terminates(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    try:
        book.evaluate(m["expr"])
    except RecursionError:
        _check(False, book, "to terminate", "infinite recursion (RecursionError)")


@phrase(r"(?P<expr>.+?) should fail")
def _should_fail(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    """The tracer refuses bad input (``canvas_from_ppm(ppm) should fail``): a ``ValueError``,
    as the API promises; the step library's own errors and stubs are not that."""
    try:
        value = book.evaluate(m["expr"])
    except ValueError:
        return
    except (StepDefinitionNotFoundError, EvaluationError, NotImplementedError):
        raise
    except Exception as error:
        _check(False, book, "a ValueError (bad input)", f"{type(error).__name__}: {error}")
    _check(False, book, "a ValueError (bad input)", f"no error, the value {describe(value)}")


@phrase(r"(?P<expr>.+?) should have ignored (?P<count>\d+) lines?")
def _ignored_lines(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    ignored = book.evaluate(f"{m['expr']}.ignored_lines")
    count = ignored if is_number(ignored) else len(ignored)
    _check(count == int(m["count"]), book, f"{m['count']} ignored lines", str(count))


@phrase(r"(?P<expr>.+?) is (?P<negated>not )?invertible")
def _invertible(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    determinant = book.call("determinant", book.evaluate(m["expr"]))
    invertible = not numbers_equal(determinant, 0)
    wanted = not m["negated"]
    _check(
        invertible == wanted,
        book,
        "an invertible matrix" if wanted else "a matrix that is not invertible",
        f"determinant {describe(determinant)}",
    )


@phrase(r"(?P<expr>.+?) is (?P<negated>not )?an? (?P<kind>point|vector)")
def _point_or_vector(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    value = book.evaluate(m["expr"])
    w = getattr(value, "w", None)
    is_kind = (
        w is not None and is_number(w) and numbers_equal(w, 1.0 if m["kind"] == "point" else 0.0)
    )
    wanted = not m["negated"]
    article = "not a" if m["negated"] else "a"
    _check(is_kind == wanted, book, f"{article} {m['kind']}", describe(value))


@phrase(r"(?P<expr>.+?) is (?P<what>true|false|nothing|empty|not empty)")
def _is_state(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    value = book.evaluate(m["expr"])
    what = m["what"]
    if what in ("true", "false"):
        ok = _is_boolean(value) and bool(value) == (what == "true")
    elif what == "nothing":
        ok = value is None
    else:
        items = _items_of(value)
        ok = (len(items) == 0) == (what == "empty")
        value = items
    _check(ok, book, what, describe(value))


@phrase(r"(?P<condition>.+?)" + _EACH)
def _comparison_each(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    for value in _each(book, m):
        try:
            _compare(book, m["condition"])
        except CheckFailed as error:
            raise CheckFailed(f"{error}\n  for {m['name']} = {describe(value)}") from None


@phrase(r"(?P<condition>.+)")
def _comparison(book: Book, m: re.Match[str], _: Table | None, __: str | None) -> None:
    _compare(book, m["condition"])


def _compare(book: Book, condition: str) -> None:
    __tracebackhide__ = True
    try:
        parts = split_comparison(condition)
    except NotationError as error:
        raise UndefinedStep(f"{book.step}: cannot read it: {error}") from None
    if parts is None:
        raise UndefinedStep(f"no Then form reads {book.step!r}")
    left_text, operator, right_text = parts
    actual = book.evaluate(left_text)
    expected = _right_side(book, right_text, actual)
    if operator == "=":
        _check(approx_equal(actual, expected), book, describe(expected), describe(actual))
    elif operator == "!=":
        _check(
            not approx_equal(actual, expected),
            book,
            f"anything but {describe(expected)}",
            describe(actual),
        )
    else:
        ordered = {
            "<": lambda: actual < expected,
            ">": lambda: actual > expected,
            "<=": lambda: actual <= expected or approx_equal(actual, expected),
            ">=": lambda: actual >= expected or approx_equal(actual, expected),
        }[operator]
        _check(bool(ordered()), book, f"{operator} {describe(expected)}", describe(actual))


_WORD = re.compile(r"[A-Za-z_]\w*")


def _right_side(book: Book, text: str, actual: Any) -> Any:
    """The expected side of a comparison. A bare word that names nothing, compared with a
    string, is that word: an outline's ``| left |`` in ``face = <face>``."""
    if isinstance(actual, str) and _WORD.fullmatch(text.strip()):
        try:
            return book.evaluate(text)
        except EvaluationError:
            return text.strip()
    return book.evaluate(text)


THEN: list[Phrase] = [
    _is_matrix,
    _every_pixel,
    _lines_are,
    _ends_with_newline,
    _no_objects,
    _no_light,
    _contains,
    _includes,
    _terminates,
    _should_fail,
    _ignored_lines,
    _invertible,
    _point_or_vector,
    _is_state,
    _comparison_each,
    _comparison,
]


# ----------------------------------------------------------------------------- running


def run_step(
    book: Book,
    phrases: Sequence[Phrase],
    text: str,
    table: Table | None = None,
    doc_string: str | None = None,
) -> None:
    """Run one step: the first form whose pattern reads the whole text handles it."""
    __tracebackhide__ = True
    text = text.strip()
    book.step = text
    for form in phrases:
        match = form.pattern.fullmatch(text)
        if match is None:
            continue
        if form.needs == "table" and not table:
            raise UndefinedStep(f"{text!r} needs a data table below it")
        if form.needs == "doc string" and doc_string is None:
            raise UndefinedStep(f'{text!r} needs a doc string (""") below it')
        try:
            form.handler(book, match, table, doc_string)
        except UndefinedStep as error:
            hint = _outline_hint(text)
            if hint and type(error) is UndefinedStep:
                raise UndefinedStep(f"{error}{hint}") from None
            raise
        except (CheckFailed, StepDefinitionNotFoundError, EvaluationError):
            raise
        except NotImplementedError as error:  # a stub, not a failure: "to do"
            raise NotWrittenYet.from_error(text, error) from error
        except Exception as error:
            raise StepError(f"{text}: {type(error).__name__}: {error}") from error
        return
    raise UndefinedStep(f"no step form reads {text!r}{_outline_hint(text)}")


OUTLINE_PARAMETER = re.compile(r"<[A-Za-z_][\w -]*>")


def _outline_hint(text: str) -> str:
    """A hint when the text still holds ``<name>``: an outline parameter without a column."""
    names = OUTLINE_PARAMETER.findall(text)
    if not names:
        return ""
    return f" ({', '.join(names)}: no Examples column of that name)"


def given_or_when(
    book: Book, text: str, table: Table | None = None, doc_string: str | None = None
) -> None:
    """A Given or When step."""
    __tracebackhide__ = True
    run_step(book, GIVEN_WHEN, text, table, doc_string)


def then(book: Book, text: str, table: Table | None = None, doc_string: str | None = None) -> None:
    """A Then step."""
    __tracebackhide__ = True
    run_step(book, THEN, text, table, doc_string)
