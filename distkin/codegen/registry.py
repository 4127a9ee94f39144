"""The generated modules committed in ``distkin/_generated/``.

Each entry maps a module name to a function (it imports its generator explicitly) that
takes no argument and returns the module's full source text (from :func:`.emit.module_source`).
``python -m distkin.codegen`` rewrites them; ``--check`` regenerates into a temporary
folder and fails if anything differs.
"""

from __future__ import annotations

from ..mechanisms.presets import PRESETS

__all__ = ["GENERATED", "generate"]

def _octic():
    from .octic import generate_octic_module
    return generate_octic_module()


def _rss(name, arb=False):
    def generate():
        from . import rss
        return (rss.generate_preset_arb if arb else rss.generate_preset)(name)
    return generate


#: module name in distkin/_generated/ -> the function returning its source
GENERATED: dict = {
    "octic_general": _octic,
    **{f"rss_{n}": _rss(n) for n in PRESETS},
    **{f"rss_{n}_arb": _rss(n, arb=True) for n in PRESETS},
}


def generate(name: str) -> str:
    """Source text of generated module ``name``."""
    return GENERATED[name]()
