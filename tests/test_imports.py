"""No hidden circle: the project's modules import each other without a cycle, counted on the
import graph grimp builds (the one import-linter checks the floors on, ``lint-imports`` in
the gate), imports inside functions and under ``TYPE_CHECKING`` included.

The last circles (the reference's shapes, the registry, numba's and prealloc's packing) were
taken apart; any circle fails the test, naming its modules."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import grimp
import pytest

PACKAGES = ("rtc", "harness", "steps", "variants", "scene", "compiled", "groundwork", "raytracer")


def circles(imports: Mapping[str, Iterable[str]]) -> list[frozenset[str]]:
    """The import circles of ``imports`` (module -> the modules it imports): every strongly
    connected set of more than one module (Tarjan's algorithm, without recursion). A module
    that imports itself under its own name (``rtc.cli`` run as ``python -m rtc.cli``) is no
    circle."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[frozenset[str]] = []
    for root in sorted(imports):
        if root in index:
            continue
        work = [(root, iter(sorted(imports.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            module, targets = work[-1]
            target = next(targets, None)
            if target is not None:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(imports.get(target, ())))))
                elif target in on_stack:
                    low[module] = min(low[module], index[target])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[module])
            if low[module] == index[module]:
                members: set[str] = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    members.add(member)
                    if member == module:
                        break
                if len(members) > 1:
                    found.append(frozenset(members))
    return found


def test_circles_are_found_and_nothing_else() -> None:
    imports = {"a": ["b"], "b": ["c", "d"], "c": ["a"], "d": ["e", "g"], "e": [], "f": ["f"],
               "g": ["d"]}  # fmt: skip
    assert sorted(map(sorted, circles(imports))) == [["a", "b", "c"], ["d", "g"]]
    assert circles({"a": ["b"], "b": []}) == []


@pytest.fixture(scope="module")
def project_circles() -> list[frozenset[str]]:
    graph = grimp.build_graph(*PACKAGES, cache_dir=None)
    imports = {m: graph.find_modules_directly_imported_by(m) for m in graph.modules}
    return circles(imports)


def test_no_import_circle(project_circles: list[frozenset[str]]) -> None:
    assert not project_circles, f"import circles: {[sorted(c) for c in project_circles]}"
