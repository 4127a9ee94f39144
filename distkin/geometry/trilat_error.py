r"""The fast tier's error estimate of :func:`~distkin.geometry.trilateration.trilaterate`
(Thomas and Ros 2005, in the Gram form of :mod:`.trilateration`): each rounding of the
Gram solve carried to first order, and a warning where the estimate exceeds
:data:`TRILATERATION_RTOL` of the problem's length scale.

On a nearly collinear base the Gram solve loses digits like :math:`1/\sin^2\theta`
(the condition number of the Gram matrix, :math:`\theta` the base's angle at
:math:`P_a`; QA: errors of 1e-4 .. 3.6e-2 of the scale with no flag), and the height of
a point near the base's plane is known to :math:`\sqrt\delta` only, :math:`\delta` the
error of :math:`h^2`.  The estimate is first order, not a bound (the certified tier gives
one); on sampled bases (tests/geometry/test_trilateration_accuracy.py) the observed
error stayed below a seventh of it.
"""

from __future__ import annotations

import builtins
import math

import numpy as np
from ..errors import warn as _warn

__all__ = ["TRILATERATION_RTOL", "precise_rtol", "fast_error", "point_error",
           "warn_accuracy"]

_EPS = float(np.finfo(float).eps)


def point_error(h2, e_foot, e_h2, vals, e, foot, one, lib=math, eps=_EPS):
    r"""The fast tier's point error estimate in length units and relative to the length
    scale :math:`\Lambda` (:data:`TRILATERATION_RTOL`): the foot's, the height's
    :math:`\min(\sqrt\delta, \delta/h)` (:math:`|\sqrt a - \sqrt b| \le
    \min(\sqrt{|a-b|}, |a-b|/\sqrt a)`), the normal's direction (its components off
    by :math:`2\varepsilon|v_2||v_3|`) times :math:`h`, and the rounding of the
    foot's coordinates."""
    sa, sb, sc, g22, g33, _, G = vals[:7]
    if one:                       # Python floats (lib math), or mpf (lib mpmath)
        h2 = float(h2) if lib is math else h2
        h = lib.sqrt(h2)
        e_h = min(lib.sqrt(e_h2), e_h2 / h) if h2 > 0 else lib.sqrt(e_h2)
        err = e_foot + e_h + _C_EST * 4 * eps * h * lib.sqrt(g22 * g33 / G)
        err = lib.ldexp(err, int(e)) + eps * max(abs(f) for f in foot)
        sigma = abs(sa) + abs(sb) + abs(sc) + g22 + g33
        return err, err / lib.ldexp(lib.sqrt(sigma), int(e))
    h = np.sqrt(h2)
    with np.errstate(divide="ignore", invalid="ignore"):
        e_h = np.where(h2 > 0, np.minimum(np.sqrt(e_h2), e_h2 / h), np.sqrt(e_h2))
    err = e_foot + e_h + _C_EST * 4 * _EPS * h * np.sqrt(g22 * g33 / G)
    err = np.ldexp(err, e) + _EPS * np.max(np.abs(foot), axis=0)
    sigma = np.abs(sa) + np.abs(sb) + np.abs(sc) + g22 + g33
    return err, err / np.ldexp(np.sqrt(sigma), e)


#: the relative accuracy the fast tier vouches for: an answer within
#: ``TRILATERATION_RTOL`` times the problem's length scale
#: :math:`\Lambda = \sqrt{|s_a| + |s_b| + |s_c| + |v_2|^2 + |v_3|^2}` of the exact
#: trilateration of its float64 inputs, by the estimate of :func:`fast_error`, or a
#: warning (:class:`~distkin.errors.ConditioningWarning`)
TRILATERATION_RTOL = 1e-6


def precise_rtol(dps):
    r"""The precise tier's counterpart of :data:`TRILATERATION_RTOL` at ``dps`` digits:
    :math:`10^{2 - dps/2}` (1e-13 at 30 digits), the same rule as the fast tier's
    (:math:`10^{2-16/2}` = 1e-6): a point near the base's plane is known to about half
    the working digits only (its height is :math:`\sqrt{\delta}`), so a tighter claim
    would warn for every planar configuration."""
    import mpmath
    return mpmath.mpf(10) ** (2 - mpmath.mpf(dps) / 2)
#: safety factor of the first-order estimate (:func:`fast_error`), set from sampled
#: bases (see tests/geometry/test_trilateration_accuracy.py)
_C_EST = 1.0


def fast_error(sa, sb, sc, g22, g33, g23, G, w2, w3, alpha, beta, lib=np, eps=_EPS):
    r"""First-order error estimates ``(foot, h2)`` of the fast tier, in units of
    :math:`2^e` (length and length squared): each rounding of the Gram solve of the
    module docstring, carried to first order.  The right-hand sides
    :math:`w_2, w_3` are off by :math:`\varepsilon(|s_a| + |v_2|^2 + |s_b|)`, the Gram
    entries by :math:`\varepsilon|v_2||v_3|`, :math:`G = \|n\|^2` by
    :math:`\varepsilon\sqrt G|v_2||v_3|`; the numerators of :math:`\alpha, \beta`
    by those times the other factors, and both are divided by :math:`G`: the error
    grows like :math:`1/\sin^2\theta` (the Gram matrix's condition number,
    :math:`\theta` the base's angle at :math:`P_a`) on a nearly collinear base.
    :math:`h^2` is off by :math:`\delta` = the rounding of
    :math:`s_a - \alpha w_2 - \beta w_3` plus the errors of
    :math:`\alpha, \beta` times :math:`|w_2|, |w_3|`, hence the height by
    :math:`\min(\sqrt\delta, \delta/h)` (:math:`|\sqrt a - \sqrt b| \le
    \min(\sqrt{|a-b|}, |a-b|/\sqrt a)`): a point near the plane of the base is known
    to :math:`\sqrt\delta` only.  An estimate, not a bound (the certified tier gives
    one); :data:`_C_EST` is its safety factor."""
    sqrt = lib.sqrt                       # math for one problem, numpy for a batch,
    #                                       mpmath for the precise tier
    fabs = np.abs if lib is np else builtins.abs
    l2, l3 = sqrt(g22), sqrt(g33)
    eg = 4 * eps * l2 * l3
    ew2 = 2 * eps * (fabs(sa) + g22 + fabs(sb))
    ew3 = 2 * eps * (fabs(sa) + g33 + fabs(sc))
    eG = 8 * eps * sqrt(G) * l2 * l3
    aw2, aw3, ag23 = fabs(w2), fabs(w3), fabs(g23)
    ea = (2 * eps * (aw2 * g33 + aw3 * ag23) + ew2 * g33 + ew3 * ag23
          + (aw2 + aw3) * eg + fabs(alpha) * eG) / G
    eb = (2 * eps * (aw3 * g22 + aw2 * ag23) + ew3 * g22 + ew2 * ag23
          + (aw2 + aw3) * eg + fabs(beta) * eG) / G
    e_foot = ea * l2 + eb * l3 + 2 * eps * (fabs(alpha) * l2 + fabs(beta) * l3)
    e_h2 = (2 * eps * (fabs(sa) + fabs(alpha) * aw2 + fabs(beta) * aw3)
            + ea * aw2 + eb * aw3)
    return _C_EST * e_foot, _C_EST * e_h2


def warn_accuracy(err, rho, rtol=TRILATERATION_RTOL, tier="fast"):
    """One :class:`~distkin.errors.ConditioningWarning` per call where the estimated
    relative error ``rho`` exceeds ``rtol`` (the fast tier's :data:`TRILATERATION_RTOL`,
    the precise tier's :func:`precise_rtol`) of the length scale (the worst of a batch,
    its index and how many; attributes ``estimate`` (relative) and ``index``)."""
    if not isinstance(rho, np.ndarray):
        if not rho > rtol:
            return
    elif not np.any(rho > rtol):
        return
    bad = np.asarray(rho > rtol)
    from ..errors import ConditioningWarning
    if np.ndim(rho):
        idx = np.unravel_index(int(np.argmax(np.where(bad, rho, -1.0))), np.shape(rho))
        idx = tuple(int(i) for i in idx)
        where = f" (batch index {idx}, {int(bad.sum())} of {bad.size} flagged)"
    else:
        idx, where = (), ""
    worst, abs_err = (float(rho), float(err)) if idx == () else (float(rho[idx]),
                                                                  float(err[idx]))
    instead = ("method='precise' or method='certified'" if tier == "fast" else
               "a larger dps or method='certified'")
    w = ConditioningWarning(
        f"{tier} trilateration cannot vouch for its point to {float(rtol):.2g} of the "
        f"problem's scale: error estimate {abs_err:.2g} (length units), {worst:.2g} of the "
        f"scale{where}, from a nearly collinear base (|v2 x v3|^2 small against "
        f"|v2|^2|v3|^2) or a point near its plane; use {instead}")
    w.estimate, w.index = worst, idx
    _warn(w)
