r"""Krawczyk's test: a certified, unique zero of a square system in a box (python-flint).

For :math:`F : \mathbb{R}^n \to \mathbb{R}^n`, an approximate zero :math:`\tilde x`, a
box :math:`X = \tilde x + [-r, r]`, an enclosure :math:`F'(X)` of the Jacobian over the
box and any real matrix :math:`Y` (here the float inverse of :math:`F'(\tilde x)`),
Krawczyk's operator

.. math:: K(X) = \tilde x - Y F(\tilde x) + \bigl(I - Y F'(X)\bigr)(X - \tilde x)

satisfies: if :math:`K(X)` lies in the interior of :math:`X`, then :math:`F` has exactly
one zero in :math:`X`, and it lies in :math:`K(X)` (R. Krawczyk, *Computing* 4 (1969);
R. E. Moore, *SIAM J. Numer. Anal.* 14 (1977); A. Neumaier, *Interval Methods for
Systems of Equations*, 1990, Thm. 5.1.7).  Every quantity is an ``arb`` ball, so the
rounding of the evaluation is part of the proof; ``Y`` only needs to be a good
preconditioner, not exact.

The box is found by epsilon inflation (Rump): radii a few times the Newton correction
:math:`|Y F(\tilde x)|`, widened while the test fails (at most :data:`TRIES` times).
Near a singular Jacobian (two solutions about to merge) :math:`I - Y F'(X)` does not
contract on any box and the test refuses: the answer is then not certified, never
certified wrongly.

Used by the certified tier of the forward kinematics of RSS and leg mechanisms
(:mod:`distkin.mechanisms.forward_tiers`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .boxes import _up

__all__ = ["KrawczykResult", "krawczyk", "TRIES"]

#: inflations of the box before the test gives up
TRIES = 8


@dataclass(frozen=True)
class KrawczykResult:
    """The outcome of :func:`krawczyk`.

    Attributes
    ----------
    proved : bool
        A unique zero of F lies in the box ``centre ± radii`` (and nowhere else in the
        box tested, ``centre ± box``).
    centre : (n,) float64
        The approximate zero the box is centred on.
    radii : (n,) float64
        Proved: upper bounds of ``|x* - centre|`` per coordinate (from K(X)).  Not
        proved: the last box tried.
    box : (n,) float64
        Half-widths of the box X in which the zero is unique (proved), or of the last
        box tried.
    contraction : float
        Upper bound of the row sums of ``|I - Y F'(X)|`` weighted by the radii, over
        the radii (< 1 is needed; inf when an enclosure was not finite).
    reason : str
        Why not proved ("" when proved).
    """

    proved: bool
    centre: np.ndarray
    radii: np.ndarray
    box: np.ndarray
    contraction: float
    reason: str = ""


def krawczyk(f_point, jac_box, x, *, floor=None, Y=None) -> KrawczykResult:
    """Certify a unique zero of a square system near ``x`` (Krawczyk's test).

    Parameters
    ----------
    f_point : callable
        ``f_point(balls)`` -> n ``arb`` balls enclosing F at the point (the balls are
        exact: the float coordinates of ``x``).
    jac_box : callable
        ``jac_box(balls)`` -> n x n nested lists (rows) of ``arb`` enclosing F' over the
        box given as n balls.
    x : (n,) float
        Approximate zero (its floats are taken exactly).
    floor : (n,) float, optional
        Smallest radii to try (default: 2^-40 max(|x_i|, 1)); the units of x.
    Y : (n, n) float, optional
        Preconditioner (default: the float inverse of the midpoint of F' at ``x``).

    Returns
    -------
    :class:`KrawczykResult`
    """
    from flint import arb
    x = np.asarray(x, dtype=float)
    n = x.size
    pt = [arb(float(v)) for v in x]
    F = f_point(pt)
    if len(F) != n:
        raise ValueError(f"expected {n} equations (a square system), got {len(F)}")
    if not all(f.is_finite() for f in F):
        return _refused(x, np.zeros(n), "F is not finite at the approximate zero")
    if Y is None:
        J0 = np.array([[float(v.mid()) for v in row] for row in jac_box(pt)])
        if not np.all(np.isfinite(J0)):
            return _refused(x, np.zeros(n), "F' is not finite at the approximate zero")
        try:
            Y = np.linalg.inv(J0)
        except np.linalg.LinAlgError:
            return _refused(x, np.zeros(n), "F' is singular at the approximate zero")
    Ya = [[arb(float(v)) for v in row] for row in np.asarray(Y, dtype=float)]
    YF = [sum((Ya[i][j] * F[j] for j in range(n)), arb(0)) for i in range(n)]
    step = np.array([_up(abs(v)) for v in YF])
    if not np.all(np.isfinite(step)):
        return _refused(x, np.zeros(n), "the Newton correction is not finite")
    base = (np.full(n, 2.0 ** -40) * np.maximum(np.abs(x), 1.0) if floor is None
            else np.asarray(floor, dtype=float))
    r = np.maximum(4.0 * step, base)
    rho = math.inf
    for _ in range(TRIES):
        X = [arb(float(x[i]), float(r[i])) for i in range(n)]
        JX = jac_box(X)
        dev = np.empty(n)
        rho = 0.0
        for i in range(n):
            acc = -YF[i]
            lin = arb(0)
            for j in range(n):
                m = (arb(1) if i == j else arb(0)) - sum(
                    (Ya[i][k] * JX[k][j] for k in range(n)), arb(0))
                lin += m * arb(0, float(r[j]))
            acc += lin
            dev[i] = _up(abs(acc))
            rho = max(rho, _up(abs(lin)) / r[i])
        if not np.all(np.isfinite(dev)):
            return _refused(x, r, "F' is not finite over the box (a leg's reach or a "
                            "singular point inside it)", math.inf)
        if np.all(dev < r):
            return KrawczykResult(True, x, dev, r, rho)
        if rho >= 1.0 and np.all(r > 1e6 * base):
            break
        r = np.maximum(2.0 * dev, 10.0 * r)
    return _refused(x, r, f"Krawczyk's operator does not map the box into itself "
                    f"(contraction {rho:.3g}, needs < 1): the Jacobian is near singular "
                    f"or the approximate zero is poor", rho)


def _refused(x, r, reason, rho=math.inf):
    return KrawczykResult(False, x, np.asarray(r, dtype=float), np.asarray(r, dtype=float),
                          rho, reason)
