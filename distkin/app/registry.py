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
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..errors import InputError

__all__ = ["QuerySpec", "Outcome", "RunContext", "register", "get", "QUERY_MODULES"]

#: query type -> modules that register it (imported on first use).  One type may be
#: implemented for several mechanism kinds by different modules (``forward_kinematics``
#: for ``octahedral`` and for ``rss``); each registers the kinds it serves.
QUERY_MODULES: dict[str, tuple[str, ...]] = {
    "cayley_menger": ("distkin.app.queries.geometry",),
    "delta_transform": ("distkin.app.queries.delta",),
    "singularity": ("distkin.app.queries.singularity",),
    "inverse_kinematics": ("distkin.app.queries.mechanisms",),
    "jacobian": ("distkin.app.queries.mechanisms",),
    "performance": ("distkin.app.queries.indices",),
    "design_sweep": ("distkin.app.queries.indices",),
    "certify_workspace": ("distkin.app.queries.certify",),
    "table5": ("distkin.control.table5",),
    "forward_kinematics": ("distkin.app.queries.mechanisms", "distkin.app.queries.octahedral",
                           "distkin.app.queries.delta"),
}

_REGISTRY: dict[str, dict] = {}   # name -> {mechanism kind or "*": QuerySpec}


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

    def notice(self, message: str) -> None:
        """One line for the user on stderr, once per run, when progress is shown (what a
        long silent step is doing)."""
        seen = self.extra.setdefault("notices", set())
        if self.progress and message and message not in seen:
            seen.add(message)
            print(f"distkin: {message}", file=sys.stderr, flush=True)


def register(name: str, *, mechanisms=(), summary: str = ""):
    """Class decorator registering a query handler under ``name`` for the mechanism
    kinds ``mechanisms`` (empty: any kind)."""
    def deco(cls):
        spec = QuerySpec(name, cls.parse, cls.run, tuple(mechanisms), summary)
        table = _REGISTRY.setdefault(name, {})
        for kind in (mechanisms or ("*",)):
            table[kind] = spec
        return cls
    return deco


def _load(name: str) -> None:
    for mod in QUERY_MODULES.get(name, ()):
        importlib.import_module(mod)


def get(name: str, kind: str | None = None, field: str = "type") -> QuerySpec:
    """The handler of query type ``name`` for mechanism ``kind``.

    Raises :class:`InputError` naming the known types, or the kinds the type serves.
    """
    if not isinstance(name, str):
        raise InputError(f"expected a query type name, got {name!r}", field=field)
    if name not in QUERY_MODULES:
        raise InputError(f"unknown query type {name!r}; expected one of "
                         f"{', '.join(map(repr, sorted(QUERY_MODULES)))}", field=field)
    _load(name)
    table = _REGISTRY.get(name, {})
    spec = table.get(kind) or table.get("*")
    if spec is None:
        kinds = sorted(k for k in table if k != "*")
        raise InputError(f"query type {name!r} needs a mechanism of kind "
                         f"{' or '.join(map(repr, kinds))}, got {kind!r}", field=field)
    return spec


def available() -> dict[str, list[str]]:
    """Query type -> the mechanism kinds it serves ("*" for any)."""
    out = {}
    for name in QUERY_MODULES:
        _load(name)
        out[name] = sorted(_REGISTRY.get(name, {}))
    return out
