r"""Exact power-of-two rescaling into the float64 range, and back with a warning.

Every fast kernel whose value is homogeneous in its inputs (a Cayley-Menger
determinant of k points has degree :math:`k-1` in the squared distances, Rojas, Borràs
and Thomas, ICRA 2012, eq. (1); the singularity conditions degree 18 in the squared
distances and :math:`\det\hat{\mathbf J}` degree 9 in the coordinates; the capability
and sensitivity indices of Kühne et al., eqs. (8)-(16), degree ±1 in the Jacobian)
can compute from inputs multiplied by :math:`2^{-e}` and multiply its value by
:math:`2^{ke}` afterwards.  Both multiplications are exact (:func:`numpy.ldexp`: no
digit changes) unless the value itself leaves float64's normal range; then
:func:`scale_back` warns once (:class:`~distkin.errors.FloatRangeWarning`) with the
value as a decimal and what to use instead.  One routine for
:mod:`distkin.geometry.cm_float`, :mod:`distkin.singularity.float_range` and
:mod:`distkin.indices.float_scale`, which differ only in the degree and the advice.
"""

from __future__ import annotations

import numpy as np

from ..errors import FloatRangeWarning, warn as _warn

__all__ = ["exponent", "scale_back", "scaled_decimal", "SMALLEST_NORMAL"]

#: the smallest normal float64: a value scaled back below it has lost digits
SMALLEST_NORMAL = 2.0 ** -1022


def exponent(m):
    """``e`` (int array) with ``m·2^-e`` in [0.5, 1) for ``m > 0``, elementwise; 0 where
    ``m`` is 0 (or NaN: left as it is, refused or flagged by the caller)."""
    m = np.asarray(m, dtype=float)
    pos = m > 0
    return np.where(pos, np.frexp(np.where(pos, m, 1.0))[1], 0)


def scaled_decimal(mant: float, ex: int) -> str:
    """``mant·2^ex`` as a decimal with an exponent (any exponent, 6 digits)."""
    import mpmath
    with mpmath.workdps(20):
        return mpmath.nstr(mpmath.ldexp(mpmath.mpf(mant), ex), 6)


def scale_back(value, k, what: str, advice: str):
    """``(value·2^k, lost)`` elementwise (broadcast); ``lost`` is True where a finite
    non-zero value becomes inf or falls below :data:`SMALLEST_NORMAL` (a value beyond
    float64, not a zero or an overflow of the method).  One FloatRangeWarning names
    ``what``, the first such value as a decimal, its batch index, the count, and
    ``advice`` (what to use instead), at the first line outside distkin
    (:func:`distkin.errors.warn`)."""
    v = np.asarray(value, dtype=float)
    with np.errstate(over="ignore", under="ignore"):
        out = np.ldexp(v, k)
    lost = np.isfinite(v) & (v != 0) & (~np.isfinite(out) | (np.abs(out) < SMALLEST_NORMAL))
    if np.any(lost):
        i = int(np.flatnonzero(np.ravel(lost))[0])
        shown = scaled_decimal(float(np.ravel(np.broadcast_to(v, out.shape))[i]),
                               int(np.ravel(np.broadcast_to(k, out.shape))[i]))
        got = float(np.ravel(out)[i])
        where = (f" at batch index {tuple(int(j) for j in np.unravel_index(i, out.shape))}"
                 if out.ndim else "")
        side = "beyond the largest" if not np.isfinite(got) else "below the smallest normal"
        _warn(FloatRangeWarning(
            f"{what} = {shown}{where} is {side} float64 number: returned {got!r} "
            f"({int(lost.sum())} of {lost.size}); use {advice}", shown))
    return out, lost
