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
from .errors import (CancellationWarning, ConditioningWarning, DegenerateGeometryError,
                     DistkinError, FloatRangeWarning, GeometryWarning, InfeasibleError,
                     InputError, LinkError, NotFoundError, SingularConfigurationError,
                     UncertifiedError)

#: the subpackages and modules loaded on first use (``distkin.octahedral``, ...): the
#: analyses (each of its own paper section), the command line and scene files (``app``),
#: exact numbers (``exact``), input checks (``argcheck``) and spatial maths (``spatial``)
SUBMODULES = ("geometry", "octahedral", "delta", "mechanisms", "singularity", "indices",
              "certify", "codegen", "control", "app", "exact", "argcheck", "spatial",
              "errors")

__all__ = [
    "__version__",
    # errors (the family of distkin.errors)
    "DistkinError", "InputError", "InfeasibleError", "NotFoundError",
    "DegenerateGeometryError", "SingularConfigurationError", "UncertifiedError", "LinkError",
    # warnings
    "ConditioningWarning", "CancellationWarning", "FloatRangeWarning", "GeometryWarning",
    # lazily loaded subpackages and modules
    *SUBMODULES,
]


def __getattr__(name):
    if name in SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'distkin' has no attribute {name!r}")
