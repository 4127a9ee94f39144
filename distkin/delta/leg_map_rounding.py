r"""A rigorous bound on the float64 rounding of the leg map of eq. (8), Rojas, Borràs,
Thomas, *The Octahedral Manipulator Revisited*: :math:`l^2 = \mathbf A^{-1}(m^2 +
\mathbf b) = \mathbf A^{-1} m^2 + c` evaluated in float64 from float m-legs
(:meth:`.transform.DeltaTransform.map_legs_float`), which the fast 6-6 tier's proof must
cover (QA J 1); and the fast map itself (:func:`map_legs_fast`), which decides the sign
of a squared l-leg exactly where that bound cannot (no InfeasibleError from a rounding
error).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, UncertifiedError
from .exact_input import _check_leg_range, _float_legs

__all__ = ["leg_map_error", "map_legs_fast", "EXACT_MAP_RHO"]

#: relative error of a squared l-leg taken from the exact map of eq. (8) and rounded to
#: float64 (at most u = 2^-53 from the rounding, plus 1e-29 from a 30-digit evaluation
#: of an irrational value): 2u covers both.
EXACT_MAP_RHO = 2.0 ** -52


def _error_terms(Ainv, c, m) -> np.ndarray:
    r""":math:`E_k = 12u\,(|\mathbf A^{-1}|\,m^2 + |c|)_k`, widened by :math:`2^{-40}`
    relative for its own rounding (see :func:`leg_map_error`)."""
    return (12.0 * 2.0 ** -53) * (np.abs(Ainv) @ (m * m) + np.abs(c)) * (1.0 + 2.0 ** -40)


def leg_map_error(Ainv, c, m_legs, l_sq) -> float:
    r"""A rigorous bound :math:`\rho` on the relative error of
    :meth:`.transform.DeltaTransform.map_legs_float`'s
    ``l_sq`` against the exact :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)` (eq. (8))
    of the exact m-legs, when each float m-leg is within :math:`u = 2^{-53}` relative
    of its exact value (floats exactly, parsed strings rounded once).

    Each entry of :math:`\mathbf A^{-1}`, :math:`c` and :math:`m_k^2` is rounded once
    and the dot product of 6 terms plus :math:`c` adds :math:`\gamma_7` (Higham,
    *Accuracy and Stability of Numerical Algorithms*, Sec. 3.1), so
    :math:`|\hat l_k^2 - l_k^2| \le E_k = 12u\,(|\mathbf A^{-1}|\,m^2 + |c|)_k`;
    :math:`\rho = \max_k E_k / (\hat l_k^2 - E_k)`, inf when some
    :math:`\hat l_k^2 \le E_k`.  Near an architectural singularity
    (:math:`\det\mathbf A \to 0`) :math:`|\mathbf A^{-1}|`, and so :math:`\rho`, grow
    like cond(A)·u: the error the fast tier's proof must cover (QA J 1).  (A ``l_sq``
    rounded from the exact map, :func:`map_legs_fast`, is within :math:`2u\,l_k^2
    \le E_k` of it: the bound holds for it too, pessimistically.)

    Parameters
    ----------
    Ainv : array (6, 6) float64, :math:`\mathbf A^{-1}` rounded entry by entry
    c : array (6,) float64, :math:`\mathbf A^{-1}\mathbf b` rounded, squared length units
    m_legs : array (6,) float64, length units
    l_sq : array (6,) float64, squared length units (from ``map_legs_float``)

    Returns
    -------
    float (dimensionless)
    """
    m = np.asarray(m_legs, dtype=float)
    E = _error_terms(Ainv, c, m)
    gap = np.asarray(l_sq, dtype=float) - E
    if not np.all(gap > 0):
        return float("inf")
    return float(np.max(E / gap))


def map_legs_fast(tr, m_legs, field: str = "m_legs", m_float=None):
    r"""The fast tier's leg map of eq. (8), :math:`l^2 = \mathbf A^{-1} m^2 + c` in
    float64 (Rojas, Borràs, Thomas, ICRA 2012, Sec. V), with its error bound.

    Where the bound :math:`E_k` of :func:`leg_map_error` proves every
    :math:`\hat l_k^2 > 0`, the float values are returned with :math:`\rho`.  Where it
    does not (a squared l-leg within its rounding error of 0, or of either sign near an
    architectural singularity, where :math:`E_k` grows like cond(A)·u), float64 cannot
    tell whether a real l-leg exists: the exact map
    (:meth:`.transform.DeltaTransform.map_legs`, on the m-legs as given) decides.  It
    raises :class:`~distkin.errors.InfeasibleError` only when the exact
    :math:`l_k^2 \le 0` (proved); otherwise the exact values rounded to float64 are
    returned, with :math:`\rho` = :data:`EXACT_MAP_RHO`, and the octahedral fast tier's
    proof decides whether it can vouch for its count (else it warns).

    Parameters
    ----------
    tr : DeltaTransform
    m_legs : 6 leg lengths (floats, Exact, numeric strings, sympy numbers; length units)
    field : str, the name used in errors
    m_float : array (6,), optional
        The m-legs already read and range-checked as float64 (by the caller's
        ``_float_legs`` and ``_check_leg_range``): not read again.

    Returns
    -------
    l_sq, l : arrays (6,) float64 (squared length units, length units)
    rho : float, a rigorous bound on the relative error of ``l_sq`` (dimensionless)
    exact : bool, True when the exact map decided

    Raises
    ------
    InputError
        As :meth:`~.transform.DeltaTransform.map_legs_float`.
    DegenerateGeometryError
        :math:`\det\mathbf A = 0`.
    InfeasibleError
        An exact squared l-leg is :math:`\le 0` (proved).
    UncertifiedError
        The exact sign of a squared l-leg cannot be decided (sympy; not seen so far).
    """
    if m_float is None:
        m = _float_legs(m_legs, field)
        _check_leg_range(m, field)
    else:
        m = m_float
    Ainv, c = tr._inverse_float
    l_sq = Ainv @ (m * m) + c
    _check_finite(l_sq, field)
    E = _error_terms(Ainv, c, m)
    if np.all(l_sq - E > 0):
        return l_sq, np.sqrt(l_sq), float(np.max(E / (l_sq - E))), False
    exact, _ = tr.map_legs(m_legs, field)      # InfeasibleError: proved exactly
    l_sq = np.array([_positive_float(x, k, field) for k, x in enumerate(exact)])
    _check_finite(l_sq, field)
    return l_sq, np.sqrt(l_sq), EXACT_MAP_RHO, True


def _check_finite(l_sq, field) -> None:
    if not np.all(np.isfinite(l_sq)):
        j = int(np.flatnonzero(~np.isfinite(l_sq))[0])
        raise InputError(f"expected m-legs whose mapped squares l^2 = A^-1 (m^2 + b) "
                         f"(eq. (8)) are float64 numbers, got l{j + 1}^2 = {l_sq[j]}",
                         field=field, hint="express the lengths in a larger unit")


def _positive_float(x, k, field) -> float:
    """An exact squared l-leg, proved positive, rounded to float64 (a rational correctly,
    an irrational from 30 correct digits)."""
    import sympy as sp
    if x.is_Rational:
        try:
            return int(x.p) / int(x.q)
        except OverflowError:
            return float("inf")
    if x.is_positive is not True:
        raise UncertifiedError(f"expected a squared l-leg of decidable sign, got l{k + 1}^2 "
                               f"= {sp.N(x, 10)} whose sign sympy cannot prove "
                               "(eq. (8), exact)", field=field)
    try:
        return float(sp.N(x, 30, strict=True))
    except sp.core.evalf.PrecisionExhausted as exc:
        raise UncertifiedError(f"expected a squared l-leg evaluable to 30 digits, got "
                               f"l{k + 1}^2 = {sp.N(x, 10)} (eq. (8), exact)",
                               field=field) from exc
