"""What the ``prealloc`` variant refuses: a shape or pattern type it has no implementation
of, and a subclass that changes a method it reimplements. It never falls back to the
reference's code: it says which type it cannot run.
"""

from __future__ import annotations


class PreallocUnsupported(TypeError):
    """A shape or pattern type the ``prealloc`` variant has no implementation of. It never
    falls back to the reference's code: it says which type it cannot run."""


def check_reimplemented(obj: object, reference: type, methods: tuple[str, ...]) -> None:
    """Refuse ``obj`` if its class replaces one of ``methods`` that ``prealloc`` reimplements
    from ``reference`` (a learner's subclass with its own ``local_intersect``, say): running
    ``reference``'s version instead would silently change the picture."""
    cls = type(obj)
    for name in methods:
        if getattr(cls, name) is not getattr(reference, name):
            raise PreallocUnsupported(
                f"prealloc: {cls.__name__} overrides {reference.__name__}.{name}, which the "
                f"prealloc variant reimplements; it cannot run {cls.__name__}'s own version"
            )
