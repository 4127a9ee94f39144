"""The generated modules committed in ``distkin/_generated/``.

Each entry maps a module name to ``"package.module:function"``; the function takes no
argument and returns the module's full source text (from :func:`.emit.module_source`).
``python -m distkin.codegen`` rewrites them; ``--check`` regenerates into a temporary
folder and fails if anything differs.
"""

from __future__ import annotations

import importlib

__all__ = ["GENERATED", "generate"]

#: module name in distkin/_generated/ -> generator "module:function"
GENERATED: dict[str, str] = {
    "octic_general": "distkin.octahedral.octic:generate_octic_module",
    "rss_hunt": "distkin.mechanisms.kernels:generate_hunt",
    "rss_hexa": "distkin.mechanisms.kernels:generate_hexa",
    "rss_ergin": "distkin.mechanisms.kernels:generate_ergin",
    "rss_octopod": "distkin.mechanisms.kernels:generate_octopod",
    "rss_octo": "distkin.mechanisms.kernels:generate_octo",
    "rss_hunt_arb": "distkin.mechanisms.kernels:generate_hunt_arb",
    "rss_hexa_arb": "distkin.mechanisms.kernels:generate_hexa_arb",
    "rss_ergin_arb": "distkin.mechanisms.kernels:generate_ergin_arb",
    "rss_octopod_arb": "distkin.mechanisms.kernels:generate_octopod_arb",
    "rss_octo_arb": "distkin.mechanisms.kernels:generate_octo_arb",
}


def generate(name: str) -> str:
    """Source text of generated module ``name``."""
    mod, _, fn = GENERATED[name].partition(":")
    return getattr(importlib.import_module(mod), fn)()
