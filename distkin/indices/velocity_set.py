"""The true velocity capability of a redundant device (Kühne et al., eq. (5) revisited).

Eq. (5) maps the actuator-rate box through the pseudo-inverse, ``ẋ = J# q̇``, and the
polytope algorithm takes the worst case of that zonotope.  For L = d the map is
invertible and the zonotope is exactly the set of reachable end-effector velocities.
For a redundant device (L = 8) it is not: the actuator rates are *determined* by the
motion, ``q̇ = J ẋ`` (eq. (1)-(2)), so the velocities the device can actually produce
are

.. math::  V = \\{\\dot x : |J \\dot x|_\\infty \\le \\dot q_{max}\\},

the intersection of the 2L half-spaces ``±J_i ẋ <= q̇max``, a polytope that
``{J# q̇}`` contains (for ẋ in V, q̇ = Jẋ is in the box and J# J ẋ = ẋ) and that is
strictly smaller for L > d.  Its slice ``ẋ_{S^c} = 0`` (e.g. translational velocity at
zero angular velocity, as the paper's eq. (14)) is ``{u : |J_S u|∞ <= q̇max}`` with
J_S the columns S of J, and the worst case (the largest ball about the origin inside a
polytope given by half-spaces) is exactly

.. math::  \\min_i \\dot q_{max} / \\lVert J_{i,S} \\rVert,

the distance to the nearest of the L slab planes (a redundant plane is farther than the
facet that hides it, so the minimum is attained on a facet).
"""

from __future__ import annotations

import numpy as np

from ..argcheck import as_floats, float_array, positive_number
from ..errors import InputError
from .capability import _keep_indices
from .tiers import fast_only

__all__ = ["true_velocity_worst"]


def true_velocity_worst(J, qdot_max, keep, *, method: str = "fast"):
    """Worst case of the true velocity set's slice (module docstring).

    Parameters
    ----------
    J : ndarray (N, L, d), or (L, d) for one pose
        Jacobian with q̇ = J ẋ (rad/s per m/s and rad/s per rad/s).
    qdot_max : float
        Symmetric actuator rate limit (rad/s), positive.
    keep : sequence of int
        The output coordinates of the slice (the others are 0), distinct, in 0..d-1.
    method : "fast"
        The only tier (float64; "precise" and "certified" are refused, :mod:`.tiers`).
        Accuracy of the fast answer: relative error about 1e-16 (one norm and a
        division per row).

    Returns
    -------
    ndarray (N,), or float for one J (L, d)
        In the unit of the kept coordinates (m/s or rad/s); +inf where J_S = 0 (never
        for an RSS device).  Exact up to rounding.

    Raises
    ------
    InputError
        J not finite or not (L, d) or (N, L, d), ``qdot_max`` not a positive finite number, or a
        bad ``keep`` (as :func:`~.capability.worst_case_output`).
    """
    fast_only(method, "the true velocity set")
    J = as_floats(J, "J", "a Jacobian of numbers, shape (L, d) or (N, L, d)")
    if J.ndim not in (2, 3):               # one J as worst_case_output takes it (QA T 9)
        raise InputError(f"expected a Jacobian of shape (L, d) or (N, L, d), got shape "
                         f"{J.shape}", field="J", hint="one pose's J is (L, d): L legs, "
                         "d outputs; a batch (N, L, d)")
    single = J.ndim == 2
    J = float_array(J[None] if single else J, "J", (None, None, None))
    qdot_max = positive_number(qdot_max.item() if isinstance(qdot_max, np.generic)
                               else qdot_max, "qdot_max")
    JS = J[..., list(_keep_indices(keep, J.shape[-1]))]
    n = np.sqrt(np.einsum("nls,nls->nl", JS, JS)).max(axis=1)
    with np.errstate(divide="ignore"):
        out = float(qdot_max) / n
    return float(out[0]) if single else out
