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
  :math:`x \in [lo, hi]`.

No sympy is imported here.
"""

from __future__ import annotations

import numpy as np

from .._generated import octic_general as _kernel

__all__ = [
    "PART_NAMES",
    "octic_data",
    "part_values",
    "eq3_branches",
    "feasible_interval",
    "TRIANGLES_THROUGH_15",
]

PART_NAMES = _kernel.PART_NAMES
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
