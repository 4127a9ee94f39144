"""The registry of scene query types.

A query type is implemented next to its algorithm and registered with
:func:`register`.  :data:`QUERY_MODULES` maps each type to the module that registers it,
so a scene imports only the modules its queries name.

A handler is a class with two static methods::

    @register("cayley_menger", mechanisms=("points",), summary="...")
    class CayleyMengerQuery:
        @staticmethod
        def parse(table, mechanism, units, field):   # validate; raise InputError
            return params                              # any immutable object
        @staticmethod
        def run(params, scene, ctx):                   # do the work
            return Outcome(result={...}, text="...", plot=None)
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from .errors import InputError

__all__ = ["QuerySpec", "Outcome", "RunContext", "register", "get", "QUERY_MODULES"]

#: query type -> module that registers it (imported on first use)
QUERY_MODULES = {
    "cayley_menger": "distkin.geometry.query",
}

_REGISTRY: dict[str, "QuerySpec"] = {}


@dataclass(frozen=True)
class QuerySpec:
    name: str
    parse: Callable
    run: Callable
    mechanisms: tuple
    summary: str


@dataclass
class Outcome:
    """What a query returns: JSON-able ``result``, a readable ``text`` (units on every
    number) and an optional ``plot(outdir) -> list[Path]``."""

    result: dict
    text: str
    plot: Callable[[Path], list] | None = None


@dataclass
class RunContext:
    """Per-run options handed to every handler."""

    plots_dir: Path | None = None
    progress: bool = True
    workdir: Path | None = None
    extra: dict = field(default_factory=dict)


def register(name: str, *, mechanisms=(), summary: str = ""):
    """Class decorator registering a query handler under ``name``."""
    def deco(cls):
        _REGISTRY[name] = QuerySpec(name, cls.parse, cls.run, tuple(mechanisms), summary)
        return cls
    return deco


def get(name: str, field: str = "type") -> QuerySpec:
    """The handler of a query type; :class:`InputError` naming the known types if absent."""
    if not isinstance(name, str):
        raise InputError(f"expected a query type name, got {name!r}", field=field)
    if name not in _REGISTRY and name in QUERY_MODULES:
        try:
            importlib.import_module(QUERY_MODULES[name])
        except ModuleNotFoundError as exc:
            if not exc.name or not exc.name.startswith("distkin"):
                raise
    if name not in _REGISTRY:
        known = sorted(available())
        raise InputError(f"unknown query type {name!r}; expected one of "
                         f"{', '.join(map(repr, known))}", field=field)
    return _REGISTRY[name]


def available() -> list[str]:
    """Query types whose implementing module is installed."""
    out = []
    for name, mod in QUERY_MODULES.items():
        if name in _REGISTRY:
            out.append(name)
            continue
        try:
            importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name and exc.name.startswith("distkin"):
                continue
            raise
        if name in _REGISTRY:
            out.append(name)
    return out
