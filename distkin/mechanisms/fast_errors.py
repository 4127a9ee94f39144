r"""First-order error models of the fast (float64) inverse kinematics and reach margin.

Both are built on the same rounding of a leg's data at a pose (:mod:`.symbolic`, Kühne
et al. Sec. II-C, eqs. (1)-(2)): the joint position P = x + R p and w = P - B - offset
carry about eps (|x| + |p| + |B| + |offset|) per coordinate, the dot products
A = w.u, B = w.v and C = (w.w + l1^2 - l3^2) / (2 l1) their own, and the reach margin
m = rho^2 - C^2 (rho^2 = A^2 + B^2) the cancellation of its two terms.

* :func:`fast_ik_error`: the fast IK's error estimate (the ``fast`` tier of
  :mod:`.kinematics_tiers`).
* :func:`reach_margin_error`: the error of the fast reach margin itself, what decides
  whether a leg closes: within it of 0 the sign of the float margin decides nothing
  (:func:`reach_decision`; QA 25a findings 1 and 2: a hunt pose 1 ulp past full
  stretch had float margins -9.0e-17 m^2 where arb proves every leg closes, and the
  forward kinematics' slack of 64 eps lp^2 = 4.3e-17 m^2 was below that rounding).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fast_ik_error", "reach_margin_error", "reach_decision"]

_EPS = np.finfo(float).eps


def _leg_terms(mech, X, q):
    """The leg data of the fast kernels at poses X (N, 6) with joint values q (N, L)
    (module docstring) and their rounding: a dict of (N, L) arrays."""
    d = mech.leg_arrays()
    pris = d["prismatic"][None]
    P = mech.points(X, q)["P"]
    w = P - d["B"][None] - d["offset"][None]
    A = np.einsum("nli,li->nl", w, d["u"])
    Bz = np.einsum("nli,li->nl", w, d["v"])
    rho = np.hypot(A, Bz)
    # rounding of w (per coordinate) and of C
    size = (np.abs(X[:, None, :3]).max(axis=-1) + np.linalg.norm(d["p"], axis=-1)[None]
            + np.linalg.norm(d["B"], axis=-1)[None] + np.linalg.norm(d["offset"], axis=-1)[None])
    dw = _EPS * size
    ww = np.einsum("nli,nli->nl", w, w)
    l1 = np.where(d["l1"] > 0, d["l1"], 1.0)[None]
    C = (ww + d["l1"][None] ** 2 - d["l3"][None] ** 2) / (2 * l1)
    dC = (2 * _EPS * (ww + d["l1"][None] ** 2 + d["l3"][None] ** 2)
          + 2 * np.sqrt(ww) * dw) / (2 * l1)
    return {"pris": pris, "A": A, "Bz": Bz, "rho": rho, "dm": 4 * _EPS * rho ** 2, "dw": dw,
            "ww": ww, "l1": l1, "C": C, "dC": dC, "p": np.linalg.norm(d["p"], axis=-1)[None]}


def fast_ik_error(mech, X, q, margin, phi=None, jq=None, terms=None):
    """First-order error estimate (N, L) of the fast IK (:mod:`.kinematics_tiers`,
    ``fast``): the closure residual |Phi_i(q_i)| / |Jq_ii|, 2 eps max(|q|, 1), the
    rounding of the leg's data at the pose (module docstring; q = atan2(B, A) ±
    acos(C / rho) moves by dC / h + dA (1 / rho + |C| / (rho h)); a prismatic q = |w| by
    eps |w| and w's rounding), and for a revolute leg the cancellation in its reach
    margin m = rho^2 - C^2 (rounding dm = 4 eps rho^2; q moves by dm / (2 rho h) with
    h = sqrt(max(|m|, dm)), the sqrt(eps) of a double root at the reach boundary, where
    the closure residual cannot see it).  The data term is taken at 0.4 of that
    worst-case sum (the roundings are not all at their bounds, nor of one sign):
    against a 40-digit mpmath solve of the same closed form on random mixed leg tables
    the actual error is at most 0.55x the estimate (tests/mechanisms/
    test_fast_ik_estimate.py), and near a reach boundary the estimate of J stays within
    10x of the actual error (tests/mechanisms/test_fast_jacobian_error.py): an
    estimate, not a bound.  ``phi`` = Phi(q, X) and ``jq`` (N, L), if already
    evaluated; ``terms`` of :func:`_leg_terms`, if already computed."""
    t = _leg_terms(mech, X, q) if terms is None else terms
    pris = t["pris"]
    zero = pris & (q == 0.0)                      # a leg of zero length: Phi is 0/0
    if phi is None or jq is None:
        k = mech.kernels("batched")
        with np.errstate(divide="ignore", invalid="ignore"):
            phi = k.closure(q, X)[..., 0]
            jq = k.jq_jx(X)[..., 0]
    rho, dm, dw, ww, C, dC = (t[k] for k in ("rho", "dm", "dw", "ww", "C", "dC"))
    with np.errstate(divide="ignore", invalid="ignore"):
        h = np.sqrt(np.maximum(np.abs(margin), dm))
        data = 0.4 * np.where(pris, 2 * _EPS * np.sqrt(ww) + 2 * dw,
                              dC / h + dw * (1 / rho + np.abs(C) / (rho * h)))
        cancel = np.where(pris, 0.0, dm / (2 * rho * h))
        lever = np.where((phi == 0) | zero, 0.0, np.abs(phi) / np.abs(jq))  # 0/0 at h = 0
        return lever + 2 * _EPS * np.maximum(np.abs(q), 1.0) + data + cancel


def reach_margin_error(mech, X, q, pose_error=None, unit=_EPS, terms=None):
    r"""Error estimate (N, L) in m^2 of the reach margin at poses X (N, 6) (the fast
    kernels' ``reach``, :meth:`.kinematics.KernelMethods.reach_margin`), ``q`` (N, L)
    the IK there (its prismatic lengths).  The rounding of the leg's data of
    :func:`fast_ik_error`, at its worst-case sum (no 0.4: the decision "does not close"
    rests on it), for a revolute leg

    .. math:: \delta m = 4\,u\,\rho^2 + 2 (|A| + |B|)(\sqrt 3\,\delta w + 3 u |w|)
              + 2 |C|\,\delta C,

    (the IK's cancellation term 4 u rho^2, A, B and C's rounding), for a prismatic leg
    with a stroke [lo, hi] (margin (q - lo)(hi - q), q = |w|) :math:`\delta q\,(|q - lo|
    + |hi - q|) + 2 u |m|` with :math:`\delta q = u |w| + \sqrt 3\,\delta w` (without one
    the margin q^2 is a sum of squares, never negative: 0); plus, with ``pose_error``
    ((N, 6) or (6,), m and rad per coordinate), the margin's change over that much of the
    pose, :math:`|\partial m / \partial w|\,(\sum|\delta v_k| + |p| \sum |\delta r_k|)`
    with :math:`|\partial m / \partial w| \le 2 \rho + 2 |C| |w| / l_1` (revolute) and
    :math:`|\partial m / \partial q|` (prismatic).  ``unit``: the arithmetic's unit
    roundoff (eps; the precise tier's 10^(1 - dps)).  First order, not a bound; checked
    against the exact margin (arb) at boundary poses of the presets
    (tests/mechanisms/test_reach_boundary.py)."""
    t = _leg_terms(mech, X, q) if terms is None else terms
    pris, A, Bz, rho, ww, C, l1 = (t[k] for k in ("pris", "A", "Bz", "rho", "ww", "C", "l1"))
    dw = t["dw"] * (unit / _EPS)
    dC = t["dC"] * (unit / _EPS)
    wn = np.sqrt(ww)
    dP = 0.0
    if pose_error is not None:
        pe = np.abs(np.atleast_2d(np.asarray(pose_error, dtype=float)))
        dP = (pe[:, :3].sum(axis=-1)[:, None] + t["p"] * pe[:, 3:].sum(axis=-1)[:, None])
    rev = (4 * unit * rho ** 2 + 2 * (np.abs(A) + np.abs(Bz)) * (np.sqrt(3) * dw + 3 * unit * wn)
           + 2 * np.abs(C) * dC + (2 * rho + 2 * np.abs(C) * wn / l1) * dP)
    lo, hi = _strokes(mech)
    dq = unit * wn + np.sqrt(3) * dw + dP
    with np.errstate(invalid="ignore"):
        m = (wn - lo) * (hi - wn)
        pri = np.where(np.isfinite(lo), dq * (np.abs(wn - lo) + np.abs(hi - wn))
                       + 2 * unit * np.abs(m), 0.0)
    return np.where(pris, pri, rev)


def _strokes(mech):
    """(lo, hi) (1, L) of the prismatic legs' strokes (m; nan where a leg has none)."""
    table = mech.leg_description().leg_table
    r = [leg.range if leg.prismatic and leg.range is not None else (np.nan, np.nan)
         for leg in table]
    return (np.array([float(a) for a, _ in r])[None], np.array([float(b) for _, b in r])[None])


def reach_decision(margin, error):
    """(closes, undecided), bool arrays as ``margin``: a leg *closes* unless its margin
    is below minus its ``error`` (it provably does not, within the model); it is
    *undecided* where |margin| < error (the sign of the float margin decides nothing:
    at its reach boundary, or a prismatic leg at a stroke end, within rounding).  NaN:
    neither."""
    margin = np.asarray(margin, dtype=float)
    closes = margin >= -error
    return closes, closes & (np.abs(margin) < error)
