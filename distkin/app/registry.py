"""The registry of scene query types.

A query type is implemented in one module per family (:mod:`distkin.app.queries`) and
registered there with :func:`register`.  :data:`QUERY_MODULES` maps each type to the
functions that import the modules registering it (plain ``import`` statements, so the
arrows are visible to tools), so a scene imports only the modules its queries name.
The handler protocol (:func:`register`, :class:`Outcome`, :class:`RunContext`) is in
:mod:`.query`, which the query modules import (so they do not import this registry).
"""

from __future__ import annotations

from ..errors import InputError
from .query import _REGISTRY, Outcome, QuerySpec, RunContext, register

__all__ = ["QuerySpec", "Outcome", "RunContext", "register", "get", "available", "QUERY_MODULES"]


def _geometry():
    from .queries import geometry  # noqa: F401 (registers its handlers)


def _delta():
    from .queries import delta  # noqa: F401


def _singularity():
    from .queries import singularity  # noqa: F401


def _leg_singularity():
    from .queries import leg_singularity  # noqa: F401


def _mechanisms():
    from .queries import mechanisms  # noqa: F401


def _mechanisms_fk():
    from .queries import forward_kinematics  # noqa: F401


def _jacobian():
    from .queries import jacobian  # noqa: F401


def _octahedral():
    from .queries import octahedral  # noqa: F401


def _indices():
    from .queries import indices  # noqa: F401


def _certify():
    from .queries import certify  # noqa: F401


def _control():
    from .queries import control  # noqa: F401


#: query type -> functions importing the modules that register it (imported on first
#: use).  One type may be implemented for several mechanism kinds by different modules
#: (``forward_kinematics`` for ``octahedral``, ``rss`` and ``platform66``); each
#: registers the kinds it serves.
QUERY_MODULES: dict[str, tuple] = {
    "cayley_menger": (_geometry,),
    "delta_transform": (_delta,),
    "singularity": (_singularity, _leg_singularity),
    "inverse_kinematics": (_mechanisms,),
    "jacobian": (_jacobian,),
    "performance": (_indices,),
    "design_sweep": (_indices,),
    "certify_workspace": (_certify,),
    "table5": (_control,),
    "forward_kinematics": (_mechanisms_fk, _octahedral, _delta),
}

def _load(name: str) -> None:
    for load in QUERY_MODULES.get(name, ()):
        load()


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
