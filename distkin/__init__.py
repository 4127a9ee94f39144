"""distkin: distance-based kinematics of parallel robots.

Symbolic derivations (sympy), generated numeric kernels, certified answers
(python-flint) and a serial-link device controller, built from

[1] N. Rojas, J. Borràs, F. Thomas, "The Octahedral Manipulator Revisited", ICRA 2012.
[2] T. Kühne et al., "Design and Evaluation of a Haptic Interface With Octopod
    Kinematics", IEEE/ASME Trans. Mechatronics.

``import distkin`` is light: it imports neither sympy nor the analyses.  Subpackages
load on first use (``distkin.geometry``, ``distkin.app.scene``, ...).
"""

from __future__ import annotations

import importlib

from ._version import __version__
from .errors import (DegenerateGeometryError, DistkinError, InfeasibleError, InputError,
                     LinkError, SingularConfigurationError, UncertifiedError)

__all__ = [
    "__version__",
    # errors
    "DistkinError", "InputError", "InfeasibleError", "DegenerateGeometryError",
    "SingularConfigurationError", "UncertifiedError", "LinkError",
    # lazily loaded subpackages
    "geometry", "numbers", "scene", "report",
]

_LAZY = {"geometry", "numbers", "scene", "report", "queries", "argcheck", "cli"}


def __getattr__(name):
    if name in _LAZY:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'distkin' has no attribute {name!r}")
