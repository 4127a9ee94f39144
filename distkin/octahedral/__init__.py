"""The octahedral manipulator (3-3 Stewart-Gough platform): bananas, the octic, every
assembly mode (Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012).

Importing this package does not import sympy; :mod:`.banana` and :mod:`.octic` import it
inside their functions (derivations and code generation only).
"""

from .. import _jitcache  # noqa: F401  (drops numba caches older than the sources)
from .forward import AssemblyResult, Pose, forward_kinematics, forward_kinematics_batched

__all__ = ["forward_kinematics", "forward_kinematics_batched", "Pose", "AssemblyResult"]
