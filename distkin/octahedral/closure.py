r"""Numeric closure condition: the octic and eq. (3) with its sign branches, every tier.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, eq. (3).
The generated kernel :mod:`distkin._generated.octic_general` maps the 12 squared
lengths to the quadratic *parts* of eq. (3) (:math:`u, v, b_1, b_2, E_1, E_2` and the
four tetrahedra) and to the octic :math:`O = G^2 - 4R_1R_2`; see
:mod:`distkin.octahedral.octic` for the algebra.  This module evaluates them:

* :func:`octic_data` calls the kernel in the tier's number type (``float`` batched or
  scalar, exact ``fmpq``, or ``mpf`` through the same integer-coefficient kernel);
* :func:`eq3_branches` evaluates the cleared eq. (3)
  :math:`N_{\epsilon}(x) = P + \epsilon_1 v\sqrt{R_1} - \epsilon_2 u\sqrt{R_2}` on all
  four branches, for the Newton polish and the rejection of spurious roots;
* :func:`feasible_interval` bounds :math:`s_{15}` by the triangle inequalities of the
  triangles through :math:`P_1P_5`, so that every real assembly has
  :math:`x \in [lo, hi]`;
* :func:`shifted_octic` rebuilds the octic around a centre :math:`x_0` from the
  quadratic parts, :math:`O(x_0 + hu) = G^2 - 4R_1R_2` in :math:`u`, far more accurate
  near its roots than the expanded coefficients (which cancel strongly there).

No sympy is imported here.
"""

from __future__ import annotations

import numpy as np

from .._generated import octic_general as _kernel

__all__ = [
    "PART_NAMES",
    "PARTS",
    "OCTIC",
    "octic_data",
    "part_values",
    "eq3_branches",
    "feasible_interval",
    "shifted_octic",
    "TRIANGLES_THROUGH_15",
]

PART_NAMES = _kernel.PART_NAMES
PARTS, OCTIC = _kernel.PARTS, _kernel.OCTIC
_IDX = {name: i for i, name in enumerate(PART_NAMES)}

#: triangles P1 Pk P5 whose two other sides are known: (side P1Pk, side PkP5) as
#: (kind, index) into the sides (s12 s13 s23 s45 s46 s56) and legs (s14 .. s16) vectors
TRIANGLES_THROUGH_15 = (
    (("legs", 0), ("sides", 3)),   # P1 P4 P5: leg 1, platform s45
    (("sides", 1), ("legs", 3)),   # P1 P3 P5: base s13, leg 4
    (("legs", 5), ("sides", 5)),   # P1 P6 P5: leg 6, platform s56
    (("sides", 0), ("legs", 2)),   # P1 P2 P5: base s12, leg 3
)


def octic_data(sides, legs, method: str):
    """The 39 kernel outputs: 10 quadratics (30 numbers) then the octic (9, highest first).

    Parameters
    ----------
    sides : (..., 6) squared sides s12 s13 s23 s45 s46 s56
    legs : (..., 6) squared legs s14 s24 s25 s35 s36 s16
    method : "fast" (float arrays, batched), "scalar" (python floats), "exact"
        (fmpq, or mpf: the kernel has integer coefficients only).
    """
    if method == "fast":
        return _kernel.octic_batched(np.asarray(sides, float), np.asarray(legs, float))
    if method == "scalar":
        return _kernel.octic_scalar(sides, legs)
    return _kernel.octic_exact(list(sides), list(legs))


def part_values(data, x):
    """Values and derivatives of the 10 quadratics at ``x``.

    ``data`` is the kernel output (``(..., 39)`` array or a list); ``x`` broadcasts
    against its leading axes.  Returns two dicts name -> value, name -> d/dx.
    """
    val, der = {}, {}
    for name, i in _IDX.items():
        if isinstance(data, np.ndarray):
            c0, c1, c2 = data[..., 3 * i], data[..., 3 * i + 1], data[..., 3 * i + 2]
        else:
            c0, c1, c2 = data[3 * i], data[3 * i + 1], data[3 * i + 2]
        val[name] = c0 + x * (c1 + x * c2)
        der[name] = c1 + 2 * x * c2
    return val, der


def eq3_branches(val, der=None, *, sqrt=np.sqrt):
    r"""Cleared eq. (3) on its four sign branches.

    Returns
    -------
    N : dict {(e1, e2): value}
        :math:`N_\epsilon = P + \epsilon_1 v\sqrt{R_1} - \epsilon_2 u\sqrt{R_2}`, with
        the radicands clipped at 0 (the caller checks the tetrahedra separately).
    dN : dict or None
        Derivatives in :math:`x` (when ``der`` is given).
    scale : value
        :math:`|ub_2| + |vb_1| + |v|\sqrt{R_1} + |u|\sqrt{R_2}`, the size of the terms
        that cancel (for relative residuals).
    """
    u, v, b1, b2 = val["u"], val["v"], val["b1"], val["b2"]
    R1 = val["T1a"] * val["T1b"]
    R2 = val["T2a"] * val["T2b"]
    if sqrt is np.sqrt:
        R1c, R2c = np.maximum(R1, 0.0), np.maximum(R2, 0.0)
    else:
        R1c, R2c = (R1 if R1 > 0 else R1 * 0), (R2 if R2 > 0 else R2 * 0)
    q1, q2 = sqrt(R1c), sqrt(R2c)
    P = u * b2 - v * b1
    N = {(e1, e2): P + e1 * v * q1 - e2 * u * q2 for e1 in (1, -1) for e2 in (1, -1)}
    scale = abs(u * b2) + abs(v * b1) + abs(v) * q1 + abs(u) * q2
    if der is None:
        return N, None, scale
    dR1 = der["T1a"] * val["T1b"] + val["T1a"] * der["T1b"]
    dR2 = der["T2a"] * val["T2b"] + val["T2a"] * der["T2b"]
    dP = der["u"] * b2 + u * der["b2"] - der["v"] * b1 - v * der["b1"]
    tiny = 1e-300 if sqrt is np.sqrt else 0
    if sqrt is np.sqrt:
        dq1 = dR1 / (2 * np.maximum(q1, tiny))
        dq2 = dR2 / (2 * np.maximum(q2, tiny))
    else:
        dq1 = dR1 / (2 * q1) if q1 > 0 else dR1 * 0
        dq2 = dR2 / (2 * q2) if q2 > 0 else dR2 * 0
    d1 = der["v"] * q1 + v * dq1
    d2 = der["u"] * q2 + u * dq2
    dN = {(e1, e2): dP + e1 * d1 - e2 * d2 for e1 in (1, -1) for e2 in (1, -1)}
    return N, dN, scale


def feasible_interval(sides, legs):
    r"""Bounds :math:`[lo, hi]` on :math:`s_{15}` from the triangles through P1 P5.

    For each triangle :math:`P_1P_kP_5` with known sides :math:`a, b`,
    :math:`(a-b)^2 \le s_{15} \le (a+b)^2`.  Float arrays (batched over leading axes).
    An empty interval (``lo > hi``) proves the octahedron cannot be assembled.

    Returns
    -------
    lo, hi : arrays of the batch shape
    which : (lo_index, hi_index) of the binding triangles in :data:`TRIANGLES_THROUGH_15`
    """
    S = {"sides": np.asarray(sides, float), "legs": np.asarray(legs, float)}
    los, his = [], []
    for (ka, ia), (kb, ib) in TRIANGLES_THROUGH_15:
        a = np.sqrt(S[ka][..., ia])
        b = np.sqrt(S[kb][..., ib])
        los.append((a - b) ** 2)
        his.append((a + b) ** 2)
    los, his = np.stack(los, -1), np.stack(his, -1)
    return los.max(-1), his.min(-1), (los.argmax(-1), his.argmin(-1))


def _pmul(a, b):
    """Products of polynomials given as (la, ...) and (lb, ...) stacks of ascending
    coefficients (any trailing shape): (la + lb - 1, ...)."""
    out = np.zeros((a.shape[0] + b.shape[0] - 1,) + np.broadcast_shapes(a.shape[1:],
                                                                         b.shape[1:]))
    for i in range(a.shape[0]):
        out[i:i + b.shape[0]] += a[i] * b
    return out


#: the factors of the five products of quadratic parts: u E2, v E1, b1 b2, T1a T1b,
#: T2a T2b (indices into PART_NAMES)
_LEFT, _RIGHT = [0, 1, 2, 6, 8], [5, 4, 3, 7, 9]


def shifted_octic(data, x0, h, *, absolute=False):
    r"""The octic around :math:`x_0`: coefficients of :math:`O(x_0 + hu)` in :math:`u`.

    Each quadratic part of eq. (3) is shifted first (three coefficients, little
    cancellation), then :math:`O = G^2 - 4R_1R_2` with :math:`G = uE_2 + vE_1 + 2b_1b_2`,
    :math:`R_1 = T_{1a}T_{1b}`, :math:`R_2 = T_{2a}T_{2b}` (:mod:`.octic`) is multiplied
    out in :math:`u`.  Near the feasible interval this keeps the digits that the
    expanded coefficients of the kernel lose to cancellation (their terms can exceed
    the octic's values by 1e6 and more there).

    Parameters
    ----------
    data : (N, 39) kernel output (:func:`octic_data`, "fast")
    x0, h : (N,) centre and scale of the new variable, :math:`x = x_0 + hu`
    absolute : bool
        Take every product with absolute values instead (:math:`|G|^2 + 4|R_1R_2|` term
        by term): then ``sum_j q_j |u|^j`` bounds the size of the terms behind the
        octic's value at u, for its rounding error.

    Returns
    -------
    q : (N, 9) coefficients, ascending in :math:`u` (C-contiguous)
    """
    C = data[:, PARTS].reshape(-1, 10, 3).transpose(2, 1, 0)      # (3, 10, N)
    c0, c1, c2 = C
    P = np.stack([c0 + x0 * (c1 + x0 * c2), h * (c1 + 2 * x0 * c2), (h * h) * c2])
    if absolute:
        P = np.abs(P)
    pr = _pmul(P[:, _LEFT], P[:, _RIGHT])                       # (5, 5, N)
    G = pr[:, 0] + pr[:, 1] + 2 * pr[:, 2]
    sq = _pmul(np.stack([G, pr[:, 3]], 1), np.stack([G, pr[:, 4]], 1))   # (9, 2, N)
    return np.ascontiguousarray((sq[:, 0] + (4 if absolute else -4) * sq[:, 1]).T)
