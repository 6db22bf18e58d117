"""The one way a command runs: its options, by name, are the keywords of its API function.

Every command's options mirror the keywords of the function in :mod:`vorobound.api` that runs
it (tests/test_api_types.py holds them to that), so a command hands its options over as they
are: :func:`invoke` turns the few that the command line spells differently into the API's
form (a choice into its value, ``--no-tight`` into ``tight``, the surface options into the
API's surface keywords), runs the function under a progress bar, and renders the result with
:func:`~vorobound.cli.render.emit` (its exit code).
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import typing
from collections.abc import Callable, Mapping
from enum import Enum
from typing import Any

from .options import surface_args
from .progress import progress_bar
from .render import emit

SURFACE_KEYS = ("sphere", "torus", "mesh", "lfs", "sizing")
"""The surface options, in :func:`~vorobound.cli.options.surface_args`'s order."""


def api_keywords(options: Mapping[str, Any], instead: dict | None = None) -> dict[str, Any]:
    """A command's options as its API function's keywords (``as_json`` is the renderer's).

    ``instead`` (the options that may replace a surface, ``{"--balls FILE": value}``) goes to
    :func:`~vorobound.cli.options.surface_args` for the message when no surface is given."""
    flat: dict[str, Any] = {}
    for name, value in options.items():
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            flat |= {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
        elif name != "as_json":
            flat[name] = value
    kwargs = {
        name: value.value if isinstance(value, Enum) else value for name, value in flat.items()
    }
    if "no_tight" in kwargs:
        kwargs["tight"] = not kwargs.pop("no_tight")
    if "sphere" in kwargs:
        surface = [kwargs.pop(key, None) for key in SURFACE_KEYS]
        kwargs |= surface_args(*surface, instead=instead)
    return kwargs


def invoke(
    run: str | Callable[..., Any],
    show: Callable[[Any], None],
    options: Mapping[str, Any],
    *,
    bar: bool = True,
    task: str | None = None,
    instead: dict | None = None,
    **changes: Any,
) -> int:
    """Run the API function ``run`` (a top-level name of :mod:`vorobound`, loaded only now:
    ``vorobound --help`` imports no numpy) with the command's ``options`` (``changes`` replace
    the ones the command parses itself) and render its result: the command's exit code.

    A progress bar is drawn when ``bar`` and not ``--json`` (``task`` names it before the
    run, for a function that reports no progress itself)."""
    if isinstance(run, str):
        import vorobound

        run = typing.cast(Callable[..., Any], getattr(vorobound, run))
    as_json = bool(options.get("as_json", False))
    kwargs = api_keywords(options, instead) | changes
    with progress_bar(bar and not as_json) as progress:
        if task is not None:
            progress(task, 0, None)
        if "progress" in inspect.signature(run).parameters:
            kwargs["progress"] = progress
        result = run(**kwargs)
    return emit(result, as_json, show)


def grouped(command: Callable[..., int]) -> Callable[..., int]:
    """The command with each parameter whose type is an option group (a dataclass of
    :mod:`~vorobound.cli.options`, such as ``SurfaceOptions``) spelled out as that group's
    options, in place, for typer; the command receives the group as one object."""
    hints = typing.get_type_hints(command, include_extras=True)
    groups: dict[str, Any] = {}
    parameters = []
    for parameter in inspect.signature(command).parameters.values():
        kind = hints[parameter.name]
        if not (isinstance(kind, type) and dataclasses.is_dataclass(kind)):
            parameters.append(parameter.replace(annotation=kind))
            continue
        groups[parameter.name] = kind
        fields = typing.get_type_hints(kind, include_extras=True)
        parameters += [
            inspect.Parameter(f.name, parameter.kind, default=f.default, annotation=fields[f.name])
            for f in dataclasses.fields(kind)
        ]

    @functools.wraps(command)
    def run(**options: Any) -> int:
        for name, kind in groups.items():
            names = [f.name for f in dataclasses.fields(kind)]
            options[name] = kind(**{key: options.pop(key) for key in names})
        return command(**options)

    run.__signature__ = inspect.Signature(parameters, return_annotation=int)  # type: ignore[attr-defined]
    run.__annotations__ = {p.name: p.annotation for p in parameters} | {"return": int}
    return run
