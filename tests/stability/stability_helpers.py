"""Shared constructions of the stability tests: a simple singular crossing of the HEXA
preset, and the Griffis-Duffy data of the Δ example.

Nothing here is a reference value of our own code: the crossing is *located* by
bisection of det Jx, and each test compares against a slope, a first-order
perturbation formula or a second route.
"""

from __future__ import annotations

import numpy as np

__all__ = ["GD", "GD_L_LEGS", "hexa_crossing", "first_order_sigma_slope"]

#: Griffis-Duffy octahedral example (Rojas et al., Sec. VI; docs/design.md §5)
GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
#: its l-legs, printed in Sec. VI (exact decimals)
GD_L_LEGS = ("99/5", "18", "18", "17", "149/10", "89/5")

#: a corner of the Table II cube where the HEXA's det Jx is negative (it is positive at
#: the centre): the straight line between them crosses a parallel singularity
_HEXA_TARGET = (-0.075, -0.075, 0.375)


def hexa_crossing(mech):
    """Locate the first sign change of det Jx on the line from the workspace centre
    (0, 0, z0) towards ``_HEXA_TARGET`` at zero rotation, by float64 bisection.

    Returns
    -------
    t_star : float
        Distance along the line (m) of the crossing (to about 1e-16 m).
    u : ndarray (6,)
        The line direction, unit in position, zero rotation.
    """
    home = mech.home
    u = np.r_[np.asarray(_HEXA_TARGET) - home[:3], 0.0, 0.0, 0.0]
    u /= np.linalg.norm(u[:3])

    def det(t):
        return np.linalg.det(mech.jq_jx(home + t * u)[1])

    a, b = 0.0, float(np.linalg.norm(np.asarray(_HEXA_TARGET) - home[:3]))
    sa = np.sign(det(a))
    if sa == np.sign(det(b)) or sa == 0:
        raise AssertionError("expected det Jx to change sign on the line")
    for _ in range(200):
        c = 0.5 * (a + b)
        if c in (a, b):
            break
        if np.sign(det(c)) == sa:
            a = c
        else:
            b = c
    return a, u


def first_order_sigma_slope(mech, t_star, u, h=1e-6):
    """dσmin/dt at a simple singular crossing from first-order perturbation theory:
    ``|u_minᵀ (dJ/dt) v_min|`` with the singular vectors of J at the crossing and
    dJ/dt by a central finite difference of step ``h`` (m) — a route independent of
    the SVDs at the sample poses."""
    home = mech.home
    J0 = mech.jacobian(home + t_star * u)
    dJ = (mech.jacobian(home + (t_star + h) * u) - mech.jacobian(home + (t_star - h) * u)) / (2 * h)
    U, _, Vt = np.linalg.svd(J0)
    return abs(U[:, -1] @ dJ @ Vt[-1])
