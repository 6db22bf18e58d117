"""The types of an API call's arguments, checked against the function's annotations before any
work: a wrong type is an :class:`~vorobound.errors.InputError` naming the keyword, never a bare
``TypeError`` from deep inside, and an empty path is refused as the command line refuses
``--out ""``.

Paths (``str | os.PathLike``), ``bool``, ``Sequence[...]`` and ``Progress`` are checked here; a
keyword whose annotation holds a number, a plain ``str`` (a choice) or any other name (an Enum
such as ``Mode``) is left to the function, which checks its value with a message naming the
choices or the range (tests/api/test_api_types.py holds every keyword to that).
"""

from __future__ import annotations

import functools
import inspect
import os
from collections.abc import Callable
from typing import Any


def _is_bool(value) -> bool:
    """True or False, or a numpy bool scalar."""
    dtype = getattr(value, "dtype", None)
    return isinstance(value, bool) or (dtype is not None and dtype.kind == "b" and not value.ndim)


def _is_path(value) -> bool:
    return isinstance(value, str | os.PathLike) and os.fspath(value) not in ("", b"")


def _is_mesh(value) -> bool:
    """A :class:`vorobound.mesh.TriangleMesh` (imported only when a value is checked)."""
    if type(value).__name__ != "TriangleMesh":
        return False
    from ..mesh import TriangleMesh

    return isinstance(value, TriangleMesh)


_ATOMS: dict[str, Callable[[Any], bool]] = {
    "None": lambda v: v is None,
    "TriangleMesh": _is_mesh,
    "bool": _is_bool,
    "os.PathLike": _is_path,
    "Progress": callable,
}
_WORDS = {
    "None": "None",
    "TriangleMesh": "a TriangleMesh",
    "bool": "True or False",
    "os.PathLike": "a path",
    "Progress": "a callable (task, done, total)",
}


def _split(annotation: str) -> list[str]:
    """The members of a union ``A | B[C | D]`` (brackets respected)."""
    parts, depth, start = [], 0, 0
    for i, char in enumerate(annotation):
        depth += (char == "[") - (char == "]")
        if char == "|" and depth == 0:
            parts.append(annotation[start:i].strip())
            start = i + 1
    parts.append(annotation[start:].strip())
    return parts


def _checker(annotation: str):
    """A predicate for values of ``annotation``, and its words; None when it has a name this
    module does not know."""
    members = []
    parts = _split(annotation)
    if "os.PathLike" in parts:  # a path: str or os.PathLike, and not empty
        parts.remove("str")
    for part in parts:
        if part.startswith("Sequence[") and part.endswith("]"):
            inner = _checker(part[len("Sequence[") : -1])
            if inner is None:  # the items are left to the function, not the sequence
                members.append((_sequence_of(lambda item: True), "a sequence"))
            else:
                members.append((_sequence_of(inner[0]), f"a sequence of ({inner[1]})"))
        elif part in _ATOMS:
            members.append((_ATOMS[part], _WORDS[part]))
        else:
            return None
    words = " or ".join(dict.fromkeys(w for _, w in members))
    return (lambda value: any(check(value) for check, _ in members)), words


def _sequence_of(check):
    def is_sequence(value) -> bool:
        if isinstance(value, str | bytes | os.PathLike | dict) or not hasattr(value, "__len__"):
            return False
        try:
            items = list(value)
        except TypeError:
            return False
        return all(check(item) for item in items)

    return is_sequence


def _brief(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def checked_arguments(function):
    """Check every argument of ``function`` against its annotation on each call (module
    docstring); an argument that does not fit is an InputError naming the keyword."""
    signature = inspect.signature(function)
    checks = {
        name: _checker(parameter.annotation)
        for name, parameter in signature.parameters.items()
        if isinstance(parameter.annotation, str)
    }

    @functools.wraps(function)
    def call(*args, **kwargs):
        from ..errors import InputError

        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError as exc:
            raise InputError(f"{function.__name__}(): {exc}") from None
        for name, value in bound.arguments.items():
            check = checks.get(name)
            if check is not None and not check[0](value):
                empty = isinstance(value, str | os.PathLike) and check[0]("x")
                got = "an empty path (the command line refuses it too)" if empty else _brief(value)
                raise InputError(f"{function.__name__}(): {name} must be {check[1]}, got {got}")
        return function(*args, **kwargs)

    return call
