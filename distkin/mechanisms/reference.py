"""Plain-numpy inverse kinematics and Jacobian of an RSS/RRRS mechanism, straight from
its leg geometry (no generated kernels).

Design sweeps visit hundreds of parameter sets (Table I: 560); deriving and caching a
kernel module for each would cost a symbolic derivation per design.  This module reads
the constant leg vectors of :meth:`distkin.mechanisms.RSSMechanism.geometry` and solves
each leg in closed form:

* leg closure ``|P − D(q)|² = l3²`` with ``P = x + R p`` and
  ``D(q) = B + offset + l1 (cos q u + sin q z)`` gives ``A cos q + B sin q = C``,
  ``A = 2 l1 w·u``, ``B = 2 l1 w·z``, ``C = |w|² + l1² − l3²``, ``w = P − B − offset``;
  the branch is the one with q = 0 at the workspace centre (the mechanisms package's
  rule), and the leg closes iff ``A² + B² >= C²``;
* differentiating the closure, ``q̇ = [s·v + (R p × s)·ω] / (s·dD/dq)`` with
  ``s = P − D`` (Kühne et al., eqs. (1)-(2): J = Jq⁻¹ Jx).

The generated kernels remain the production path for fixed mechanisms; tests compare
the two routes.
"""

from __future__ import annotations

import numpy as np

from ..spatial import rotation_matrix

__all__ = ["ik_jacobian"]


def _solve(mech, X, g, branch):
    R = rotation_matrix(X[:, 3:])
    Rp = np.einsum("nij,lj->nli", R, g["p"])                  # (N, L, 3)
    P = X[:, None, :3] + Rp
    w = P - (g["B"] + g["offset"])[None]
    l1, l3 = mech.l1, mech.l3
    A = 2 * l1 * np.einsum("nli,li->nl", w, g["u"])
    Bc = 2 * l1 * w[..., 2]
    C = np.einsum("nli,nli->nl", w, w) + l1 ** 2 - l3 ** 2
    rho = np.hypot(A, Bc)
    margin = rho ** 2 - C ** 2
    delta = np.arccos(np.clip(np.divide(C, rho, out=np.ones_like(C), where=rho > 0), -1, 1))
    q = np.arctan2(Bc, A) + branch * delta
    q = (q + np.pi) % (2 * np.pi) - np.pi
    return q, margin, Rp, P


def ik_jacobian(mech, poses, *, return_jq: bool = False):
    """IK and Jacobian of ``mech`` at ``poses`` without generated kernels.

    Parameters
    ----------
    mech : RSSMechanism
    poses : ndarray (N, 6)
        (x, y, z) m and (rx, ry, rz) rad, R = Rz Ry Rx.

    Returns
    -------
    q : ndarray (N, L), rad
    valid : ndarray (N, L) bool
        The leg closes (reach margin >= 0).
    J : ndarray (N, L, 6)
        q̇ = J·(v, ω); rows of legs that do not close are meaningless.
    jq : ndarray (N, L), only with ``return_jq``
        The diagonal of eq. (1)'s Jq normalised as the kernels' (``mech.jq_jx``): m,
        up to sign (|Jq_ii| = l1 |sin| of the angle between crank and distal link).
    """
    X = np.atleast_2d(np.asarray(poses, dtype=float))
    g = mech.geometry()
    home = mech.home[None]
    qp = _solve(mech, home, g, 1.0)[0]
    qm = _solve(mech, home, g, -1.0)[0]
    branch = np.where(np.abs(qp[0]) <= np.abs(qm[0]), 1.0, -1.0)   # q = 0 at home
    q, margin, Rp, P = _solve(mech, X, g, branch[None])
    z = np.array([0.0, 0.0, 1.0])
    cq, sq = np.cos(q)[..., None], np.sin(q)[..., None]
    D = g["B"][None] + g["offset"][None] + mech.l1 * (cq * g["u"][None] + sq * z)
    dD = mech.l1 * (-sq * g["u"][None] + cq * z)
    s = P - D
    jq = np.einsum("nli,nli->nl", s, dD)
    Jx = np.concatenate([s, np.cross(Rp, s)], axis=-1)          # (N, L, 6)
    with np.errstate(divide="ignore", invalid="ignore"):
        J = Jx / jq[..., None]
    if return_jq:
        return q, margin >= 0.0, J, jq / mech.l3
    return q, margin >= 0.0, J
