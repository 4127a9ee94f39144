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
  ``s = P − D`` (Kühne et al., eqs. (1)-(2): J = Jq⁻¹ Jx);
* the closure's value (:class:`NumericKernels`, for the forward kinematics) in the
  closed form the IK solves,
  ``(|w|² − 2 l1 (w·u cos q + w·v sin q) + l1² − l3²) / (2 l3)``, and its q-derivative
  ``−w·dD/dq / l3``, as :class:`~.symbolic.ModelExprs` writes them: the same mechanism
  as the IK when a table's (u, v) is orthonormal only to its tolerance (1e-9).

The generated kernels remain the production path for fixed mechanisms; tests compare
the two routes.
"""

from __future__ import annotations

import numpy as np

from ..spatial import rotation_matrix

__all__ = ["ik_jacobian", "NumericKernels", "jacobian_q_derivatives", "home_reach_margins"]


def _solve(mech, X, g, branch):
    R = rotation_matrix(X[:, 3:])
    Rp = np.einsum("nij,lj->nli", R, g["p"])                  # (N, L, 3)
    P = X[:, None, :3] + Rp
    A, Bc, C = _closure(mech, P - (g["B"] + g["offset"])[None], g)
    rho = np.hypot(A, Bc)
    margin = rho ** 2 - C ** 2
    delta = np.arccos(np.clip(np.divide(C, rho, out=np.ones_like(C), where=rho > 0), -1, 1))
    q = np.arctan2(Bc, A) + branch * delta
    q = (q + np.pi) % (2 * np.pi) - np.pi
    return q, margin, Rp, P


def _closure(mech, w, g):
    """A cos q + Bc sin q = C, the closure of each leg (w: spherical joint minus the
    universal joint's circle centre, (..., L, 3))."""
    l1, l3 = mech.l1, mech.l3
    A = 2 * l1 * np.einsum("...li,li->...l", w, g["u"])
    return A, 2 * l1 * w[..., 2], np.einsum("...li,...li->...l", w, w) + l1 ** 2 - l3 ** 2


def home_reach_margins(mech) -> np.ndarray:
    """(L,) reach margins of an RSS mechanism or description at its home pose (0, 0,
    z0, no rotation), in m^2: the closure's rho^2 - C^2 divided by (2 l1)^2 (>= 0: the
    leg closes)."""
    g = mech.geometry()
    A, Bc, C = _closure(mech, g["p"] + [0.0, 0.0, mech.z0] - g["B"] - g["offset"], g)
    return (A * A + Bc * Bc - C * C) / (2 * mech.l1) ** 2


def ik_jacobian(mech, poses, *, return_jq: bool = False):
    """IK and Jacobian of ``mech`` at ``poses`` without generated kernels.

    Parameters
    ----------
    mech : RSSMechanism, or a leg mechanism (kind "legs": :class:`NumericKernels`, with
        jq normalised as its kernels', so ``transmission`` uses ``mech.l1``)
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
    if getattr(mech, "kind", None) == "legs":
        return _legs_ik_jacobian(mech, X, return_jq)
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


def jacobian_q_derivatives(mech, X, q):
    """dJq_ii/dq_i (N, L) and dJx_i/dq_i (N, L, 6) of ``mech`` (RSS or leg mechanism)
    at the poses X (N, 6) (m, rad) and joint values q (N, L), from the leg table (the
    formulas of :mod:`.symbolic`, as :class:`NumericKernels` writes them; Kühne et al.,
    eq. (1)); the fast tier's error estimate of J propagates the IK's error through them
    (:mod:`.kinematics_tiers`).  Revolute leg, w = P - B - offset,
    s = P - D(q), D' = l1 (-sin q u + cos q v), D'' = -l1 (cos q u + sin q v):
    Jq = -w.D'/l3 and Jx = -(s, Rp x s)/l3, so dJq/dq = -w.D''/l3 and
    dJx/dq = (D', Rp x D')/l3.  Prismatic leg, s = P - B: Jq = -(|s|^2 + q^2)/(2 q^2) and
    Jx = -(s, Rp x s)/q, so dJq/dq = |s|^2/q^3 and dJx/dq = (s, Rp x s)/q^2."""
    d = mech.leg_arrays()
    P = mech.points(X, q)["P"]
    Rp = P - X[:, None, :3]
    pris = d["prismatic"]
    cq, sq = np.cos(q)[..., None], np.sin(q)[..., None]
    l1 = d["l1"][:, None]
    dD = l1 * (-sq * d["u"] + cq * d["v"])
    ddD = -l1 * (cq * d["u"] + sq * d["v"])
    w = P - d["B"] - d["offset"]
    l3 = np.where(pris, 1.0, d["l3"])
    sp = P - d["B"]
    qq = np.where(pris, q, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        djq = np.where(pris, np.einsum("nli,nli->nl", sp, sp) / qq ** 3,
                       -np.einsum("nli,nli->nl", w, ddD) / l3)
        djx = np.where(pris[:, None], np.concatenate([sp, np.cross(Rp, sp)], -1)
                       / (qq ** 2)[..., None],
                       np.concatenate([dD, np.cross(Rp, dD)], -1) / l3[:, None])
    return djq, djx


def _legs_ik_jacobian(mech, X, return_jq):
    k = NumericKernels(mech.leg_description())
    q = k.ik(X)
    out = k.jq_jx(X)
    valid = k.reach(X) >= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        J = out[..., 1:] / out[..., :1]
    return (q, valid, J, out[..., 0]) if return_jq else (q, valid, J)


class NumericKernels:
    """The kernel interface of :mod:`.kernels` (``ik, reach, jacobian, jq_jx, closure``)
    computed in plain numpy from a leg table (:class:`~.legs.LegsDescription`): the route
    that needs no generated module (no sympy, no derivation), selected with
    ``LegMechanism(..., route="numpy")`` or ``route = "numpy"`` in a scene.

    The formulas are those of :mod:`.symbolic` (revolute legs: ``A cos q + Bz sin q = C``
    with the leg's branch, ``Jq = dPhi/dq``, ``Jx = -dPhi/d(v, omega)``; prismatic legs:
    ``q = |P - B|``, ``Jq = -1``, the normalised Plücker line, Rojas et al. eq. (5)), so
    the two routes agree to rounding (tests/mechanisms/test_legs_numeric.py).  Flavours
    "batched" (arrays (..., 6)) and "scalar" (one pose, lists); no "arb".
    """

    def __init__(self, desc, flavour: str = "batched"):
        self.desc = desc
        self.flavour = flavour
        self.module = None
        self._d = desc.arrays()
        lo = np.array([leg.range[0] if leg.prismatic and leg.range else np.nan
                       for leg in desc.leg_table])
        hi = np.array([leg.range[1] if leg.prismatic and leg.range else np.nan
                       for leg in desc.leg_table])
        self._stroke = (lo, hi)
        if flavour == "scalar":
            for name in ("ik", "reach", "jacobian", "jq_jx"):
                setattr(self, name, self._scalar(getattr(self, "_" + name)))
            self.closure = lambda q, pose: self._closure(
                np.asarray(q, float)[None], np.asarray(pose, float)[None])[0].tolist()
        else:
            self.ik, self.reach, self.jacobian = self._ik, self._reach, self._jacobian
            self.jq_jx, self.closure = self._jq_jx, self._closure

    def __repr__(self):
        return f"<NumericKernels {self.flavour} of {self.desc.name!r}>"

    @staticmethod
    def _scalar(fn):
        return lambda pose: fn(np.asarray(pose, dtype=float)[None])[0].tolist()

    def _geometry(self, X):
        d = self._d
        X = np.asarray(X, dtype=float)
        Rp = np.einsum("...ij,lj->...li", rotation_matrix(X[..., 3:]), d["p"])
        P = X[..., None, :3] + Rp
        return d, Rp, P

    def _revolute(self, d, P):
        w = P - d["B"] - d["offset"]
        A = np.einsum("...li,li->...l", w, d["u"])
        Bz = np.einsum("...li,li->...l", w, d["v"])
        l1 = np.where(d["prismatic"], 1.0, d["l1"])
        C = (np.einsum("...li,...li->...l", w, w) + l1 ** 2 - d["l3"] ** 2) / (2 * l1)
        return A, Bz, C

    def _ik(self, X):
        d, _, P = self._geometry(X)
        A, Bz, C = self._revolute(d, P)
        h = np.sqrt(np.abs(A ** 2 + Bz ** 2 - C ** 2))
        s = d["branch"]
        q = np.arctan2(Bz * C - s * A * h, A * C + s * Bz * h)
        return np.where(d["prismatic"], np.linalg.norm(P - d["B"], axis=-1), q)

    def _reach(self, X):
        d, _, P = self._geometry(X)
        A, Bz, C = self._revolute(d, P)
        qp = np.linalg.norm(P - d["B"], axis=-1)
        lo, hi = self._stroke
        pris = np.where(np.isnan(lo), qp ** 2, (qp - lo) * (hi - qp))
        return np.where(d["prismatic"], pris, A ** 2 + Bz ** 2 - C ** 2)

    def _rows(self, X, q):
        """Phi (..., L), dPhi/dq (..., L), dPhi/d(v, omega) (..., L, 6) at joint values q."""
        d, Rp, P = self._geometry(X)
        pris = d["prismatic"]
        cq, sq = np.cos(q)[..., None], np.sin(q)[..., None]
        l1 = d["l1"][:, None]
        D = d["B"] + d["offset"] + l1 * (cq * d["u"] + sq * d["v"])
        dD = l1 * (-sq * d["u"] + cq * d["v"])
        D = np.where(pris[:, None], d["B"], D)
        s = P - D
        qq = np.where(pris, q, 1.0)
        den = np.where(pris, qq, d["l3"])
        n2 = np.einsum("...li,...li->...l", s, s)
        # revolute: the closed form the IK solves (symbolic.ModelExprs), w = P - B - o:
        # (w.w - 2 l1 (w.u cos q + w.v sin q) + l1^2 - l3^2) / (2 l3), its q-derivative
        # -w.dD / l3; equal to the literal |P - D|^2 form for an orthonormal (u, v)
        w = P - d["B"] - d["offset"]
        wu = np.einsum("...li,li->...l", w, d["u"])
        wv = np.einsum("...li,li->...l", w, d["v"])
        l1r, l3 = d["l1"], d["l3"]
        rev = (np.einsum("...li,...li->...l", w, w)
               - 2 * l1r * (wu * cq[..., 0] + wv * sq[..., 0]) + l1r ** 2 - l3 ** 2)
        phi = np.where(pris, (n2 - qq ** 2) / (2 * qq), rev / (2 * den))
        dq = np.where(pris, -(n2 + qq ** 2) / (2 * qq ** 2),
                      -np.einsum("...li,...li->...l", w, dD) / den)
        g = s / den[..., None]
        return phi, dq, np.concatenate([g, np.cross(Rp, g)], axis=-1)

    def _jq_jx(self, X):
        q = self._ik(X)
        _, jq, gx = self._rows(X, q)
        jq = np.where(self._d["prismatic"], -1.0, jq)     # at the IK, as symbolic.py
        return np.concatenate([jq[..., None], -gx], axis=-1)

    def _jacobian(self, X):
        out = self._jq_jx(X)
        with np.errstate(divide="ignore", invalid="ignore"):
            return out[..., 1:] / out[..., :1]

    def _closure(self, q, X):
        phi, _, gx = self._rows(X, np.asarray(q, dtype=float))
        return np.concatenate([phi[..., None], gx], axis=-1)
