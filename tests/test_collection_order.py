"""The order the tests start in (tests/conftest.py's collection hook): the tests marked
``slow`` first, so that none of them is left to start last and keep one core busy while
the other has nothing to do."""

from dataclasses import dataclass

import conftest
import pytest


@dataclass
class _Item:
    name: str
    slow: bool

    def get_closest_marker(self, name: str) -> object | None:
        return object() if name == "slow" and self.slow else None


def test_the_marked_tests_go_first_and_each_part_keeps_its_order() -> None:
    items = [_Item("a", False), _Item("b", True), _Item("c", False), _Item("d", True)]
    conftest.pytest_collection_modifyitems(items)  # type: ignore[arg-type]
    assert [item.name for item in items] == ["b", "d", "a", "c"]


def test_this_run_starts_with_its_slow_tests(request: pytest.FixtureRequest) -> None:
    slow = [item.get_closest_marker("slow") is not None for item in request.session.items]
    assert slow == sorted(slow, reverse=True), "a test marked slow comes after one that is not"
