"""Maximum sensitivities (Cardou et al. [1]; Kühne et al., Sec. II-C-4, eq. (16)).

With the actuator displacements normalised to ``||δq||∞ <= 1 rad`` the maximum
point-displacement and rotation sensitivities are the farthest points of the
translational and rotational parts of ``{J# δq}`` (eq. (5)); with actuator torques
normalised to ``||τ||∞ <= 1 N·m`` the force and torque sensitivities are the farthest
points of the parts of ``{Jᵀ τ}`` (eq. (6)).  The farthest point of a zonotope (or of
its projection) is a box vertex, so the 2^L vertices give it exactly
(:func:`distkin.indices.best_case_output`).

``mode="projection"`` is Cardou's definition (the other part unconstrained);
``mode="slice"`` constrains the other part to zero (force at zero torque, as the
paper's slicing step), by the C(L,3)·2^(L−3) vertex candidates of DESIGN.md §6.

.. [1] P. Cardou, S. Bouchard, C. Gosselin, "Kinematic-sensitivity indices for
   dimensionally nonhomogeneous Jacobian matrices", IEEE Trans. Robotics 26(1), 2010.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .zonotope import zonotope_best

__all__ = ["max_sensitivities", "SENSITIVITY_UNITS"]

#: name -> unit of each maximum sensitivity
SENSITIVITY_UNITS = {"translational": "m/rad", "rotational": "rad/rad",
                     "force": "N/(N·m)", "torque": "(N·m)/(N·m)"}


def max_sensitivities(J, mode: str = "projection", *, twist=None):
    """Cardou's four maximum sensitivities at each pose.

    Parameters
    ----------
    J : ndarray (N, L, 6)
        Jacobian, q̇ = J·(v, ω).
    mode : {"projection", "slice"}
    twist : ndarray (N, 6, L), optional
        ``pinv(J)`` if already computed.

    Returns
    -------
    dict of ndarray (N,)
        ``translational`` [m/rad], ``rotational`` [rad/rad], ``force`` [N/(N·m)],
        ``torque`` [(N·m)/(N·m)].  Exact up to float64 rounding (vertex enumeration).
    """
    if mode not in ("projection", "slice"):
        raise InputError(f"expected mode 'projection' or 'slice', got {mode!r}", field="mode")
    J = np.asarray(J, dtype=float)
    if J.ndim != 3 or J.shape[2] != 6:
        raise InputError(f"expected J of shape (N, L, 6), got {J.shape}", field="J")
    N, L, _ = J.shape
    Gt = np.linalg.pinv(J) if twist is None else twist
    Gw = np.swapaxes(J, 1, 2)
    c, r = np.zeros((N, L)), np.ones((N, L))
    out = {}
    for name, G, rows in (("translational", Gt, (0, 1, 2)), ("rotational", Gt, (3, 4, 5)),
                          ("force", Gw, (0, 1, 2)), ("torque", Gw, (3, 4, 5))):
        if mode == "projection":
            out[name] = zonotope_best(np.ascontiguousarray(G[:, list(rows), :]), c, r,
                                      [(0, 1, 2)])[0]
        else:
            out[name] = zonotope_best(G, c, r, [rows])[0]
    return out
