"""What a scene query is: its handler protocol, its outcome and its run context.

A handler is a class with two static methods, registered with :func:`register` by the
module of its family (:mod:`distkin.app.queries`); :mod:`distkin.app.registry` finds
it by type and mechanism kind::

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

import contextlib
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

__all__ = ["QuerySpec", "Outcome", "RunContext", "register"]

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
    """Per-run options handed to every handler.

    ``store``, ``workers``, ``scheduler``: set by ``distkin sweep``, they override the
    fields of the same names of every chunked query (:meth:`store_dir`,
    :meth:`executor`)."""

    plots_dir: Path | None = None
    progress: bool = True
    workdir: Path | None = None
    extra: dict = field(default_factory=dict)
    store: Path | None = None
    workers: int | None = None
    scheduler: str | None = None

    def store_dir(self, store, scene, name) -> Path:
        """Where a chunked query keeps its finished chunks: ``--store`` of ``distkin
        sweep``, else the query's ``store`` (relative to the scene file), else the user
        cache, one folder per code version (:func:`distkin.runstore.default_store`)."""
        if self.store:
            return Path(self.store)
        if store:
            p = Path(store)
            return p if p.is_absolute() else Path(scene.path).resolve().parent / p
        from ..runstore import default_store
        return default_store(f"{Path(scene.path).stem}_{name}")

    @contextlib.contextmanager
    def executor(self, workers, scheduler):
        """The executor of a chunked query (its fields, overridden by ``distkin
        sweep``): a context manager (:func:`distkin.runstore.executor_for`).  An error
        about the cluster (field ``scheduler``) names ``--scheduler`` when the address
        came from that option (QA: it blamed the scene's ``query[0].scheduler``)."""
        from ..errors import DistkinError
        from ..runstore import executor_for
        try:
            with executor_for(scheduler=self.scheduler or scheduler,
                              workers=self.workers or workers) as ex:
                yield ex
        except DistkinError as exc:
            if self.scheduler and exc.field == "scheduler":
                exc.field = "--scheduler"
                exc.args = (exc.one_line(),)
            raise

    def notice(self, message: str) -> None:
        """One line for the user on stderr, once per run, when progress is shown (what a
        long silent step is doing)."""
        seen = self.extra.setdefault("notices", set())
        if self.progress and message and message not in seen:
            seen.add(message)
            print(f"distkin: {message}", file=sys.stderr, flush=True)


    def option_field(self, exc) -> None:
        """Re-anchor, in place, an error of the chunk store (field ``store``, from
        :mod:`distkin.runstore`) at ``--store`` when the store is the sweep's override: the
        scene has no such field (QA: ``distkin sweep --store DIR`` said
        ``query[0].store``), as :meth:`executor` does for ``--scheduler``.  A store
        written in the scene keeps its field (the caller prefixes ``query[N].``)."""
        if self.store and exc.field is not None and (exc.field == "store"
                                                     or exc.field.startswith("store.")):
            exc.field = "--" + exc.field
            exc.args = (exc.one_line(),)

    def warn(self, message: str) -> None:
        """One line on stderr, once per run, whether or not progress is shown (what the
        user should know about the answer: a range not on the grid, many workers)."""
        seen = self.extra.setdefault("warnings", set())
        if message and message not in seen:
            seen.add(message)
            print(f"distkin: warning: {message}", file=sys.stderr, flush=True)


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
