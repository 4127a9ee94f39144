r"""The float64 (fast) tier of :func:`~distkin.geometry.cayley_menger.cayley_menger`:
the bordered matrix of Rojas, Borràs and Thomas (ICRA 2012), eq. (1), its determinant by
LU (numpy, batched), a power-of-two rescaling where the value leaves the float64 range,
and a cancellation estimate.

Every term of the expansion of the bordered determinant of k points is an integer times
a product of :math:`k-1` squared distances, so its size is at most :math:`s_{\max}^{k-1}`;
a value :math:`|D|` much smaller than that is the difference of large terms, and LU in
float64 gets it to about :math:`k\,\varepsilon\, s_{\max}^{k-1}` (the backward error of
Gaussian elimination: N. J. Higham, *Accuracy and Stability of Numerical Algorithms*,
2nd ed., SIAM 2002, Ch. 9).  Hence the relative error estimate

.. math:: \rho = k\,\varepsilon\,\frac{s_{\max}^{k-1}}{|D|},

computed in units of a power of two (exact), so it neither over- nor underflows.  It is
large where the simplex is nearly flat (for a tetrahedron
:math:`\rho \approx \varepsilon L^6 / (72 V^2)`, :math:`L^2 = s_{\max}`), and infinite
at a determinant computed as 0; it is an estimate, not a bound (the certified tier gives
one).  It costs one maximum per matrix: the fast path keeps its speed.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import CancellationWarning, FloatRangeWarning, InputError, warn as _warn
from .pow2_scale import exponent, scale_back

__all__ = ["FloatRangeWarning", "CancellationWarning", "float_determinant",
           "CANCELLATION_THRESHOLD"]

#: relative error estimate above which the fast tier warns: a bound from Hadamard's
#: inequality, which overestimates (the banana identity of a random octahedron holds to
#: 1e-10 where it read 1.9e-8), so it warns where more than ~10 of float64's 16 digits
#: may be lost, not at half of them
CANCELLATION_THRESHOLD = 1e-6
_EPS = float(np.finfo(float).eps)



def float_determinant(M, k, label="D", warn=True):
    """The determinant of bordered Cayley-Menger matrices ``M`` (..., k+1, k+1): a float
    or an array of the batch shape.  Values beyond the float64 range are recomputed
    from power-of-two scaled entries (:func:`_rescaled`, FloatRangeWarning when still
    out of range); a relative error estimate above :data:`CANCELLATION_THRESHOLD` warns
    (:class:`CancellationWarning`), naming ``label``."""
    with np.errstate(over="ignore", under="ignore"):   # said below, with the value
        d = np.linalg.det(M)
    odd = ~(np.isfinite(d) & (np.abs(d) >= _TINY))
    lost = np.zeros(np.shape(d), bool)
    if np.any(odd):
        if d.ndim == 0:
            ds, e = _rescaled(M, k)
        else:                              # only the odd ones of a batch (the others
            ds, e = d.copy(), np.zeros(d.shape, int)       # are scaled back by 2^0)
            ds[odd], e[odd] = _rescaled(M[odd], k)
        # the whole batch, so that a warning gives the batch index of the value
        d, lost = scale_back(ds, e * (k - 1), "Cayley-Menger determinant",
                             "method='certified' or a larger/smaller length unit")
    if warn:
        _cancellation(M, d, k, label, lost)
    return float(d) if d.ndim == 0 else d


def relative_error_estimate(M, d, k):
    """:math:`\rho` of the module docstring for matrices ``M`` (..., k+1, k+1) with
    determinants ``d`` (inf where ``d`` is 0)."""
    big = np.max(np.abs(M[..., 1:, 1:]), axis=(-2, -1))
    e = np.frexp(np.where(big > 0, big, 1.0))[1]
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        ds = np.abs(np.ldexp(np.asarray(d, float), -e * (k - 1)))
        return k * np.finfo(float).eps * np.ldexp(big, -e) ** (k - 1) / ds


def _cancellation(M, d, k, label, lost):
    """Warn (CancellationWarning) where :func:`relative_error_estimate` exceeds the
    threshold; not for 1 or 2 points (no cancellation), nor where the value left the
    float64 range (``lost``: FloatRangeWarning said so)."""
    if k < 3:
        return
    if np.ndim(d) == 0:                    # one matrix: plain floats (numpy's per-call
        if lost:                           # overhead on 0-d arrays would dominate)
            return
        big = float(np.abs(M[1:, 1:]).max())
        if d != 0 and big > 0:
            mb, eb = math.frexp(big)
            md, ed = math.frexp(abs(d))
            ex = max(min(eb * (k - 1) - ed, 1000), -1000)
            rho = k * _EPS * mb ** (k - 1) / md * 2.0 ** ex
        else:
            rho = math.inf
        if rho > CANCELLATION_THRESHOLD:
            _cancellation_warning(float(d), rho, (), "", label)
        return
    d = np.asarray(d, float)
    rho = relative_error_estimate(M, d, k)
    bad = (rho > CANCELLATION_THRESHOLD) & ~np.asarray(lost)
    if not np.any(bad):
        return
    idx = np.unravel_index(int(np.argmax(np.where(bad, rho, -1.0))), np.shape(rho))
    where = (f" (batch index {tuple(int(i) for i in idx)}, {int(bad.sum())} of "
             f"{bad.size} flagged)")
    _cancellation_warning(float(d[idx]), float(rho[idx]), idx, where, label)


def _cancellation_warning(val, worst, idx, where, label):
    what = ("computed as 0: the float64 value cannot tell it from 0" if val == 0 else
            f"= {val:.6g} with a relative error estimate of {worst:.2g}"
            + (": it may be 0 (e.g. a flat simplex)" if worst >= 1 else
               " (a nearly flat simplex)"))
    _warn(CancellationWarning(
        f"Cayley-Menger determinant {label} {what}{where}; use method='precise' or "
        "method='certified' (exact for exact or float input)", worst, idx))


#: the smallest normal float64; below it (or at 0, or beyond the range) the float
#: determinant is computed again from power-of-two scaled entries (rare: no cost otherwise)
_TINY = 2.2250738585072014e-308



def _rescaled(M, k):
    r"""``(D_e, e)``: the float determinants of the bordered matrices ``M``
    (..., k+1, k+1) from their entries scaled by :math:`2^{-e}` (exact), :math:`2^e` just
    above the largest squared distance: :math:`D(\lambda s) = \lambda^{k-1} D(s)`, so
    :math:`D = D_e 2^{e(k-1)}` (:func:`.pow2_scale.scale_back`, in the caller, warns
    where a value that is not zero still does not fit float64: an underflow is not a
    flat simplex, QA J 4)."""
    S = M[..., 1:, 1:]
    e = exponent(np.max(np.abs(S), axis=(-2, -1))) if k else np.zeros(M.shape[:-2], int)
    Ms = M.copy()
    Ms[..., 1:, 1:] = np.ldexp(S, -e[..., None, None])
    return np.linalg.det(Ms), e


def _bordered(s, rows, cols):
    """The bordered float matrix (..., k + 1, k + 1) of D(rows; cols), entry by entry
    (a mapping of floats); refuses a squared distance NaN, infinite or negative."""
    entries = []
    for i in rows:
        for j in cols:
            v = np.asarray(0.0 if i == j else s(i, j), dtype=float)
            if not np.all(np.isfinite(v) & (v >= 0)):
                _refuse(i, j, float(np.ravel(v)[~(np.isfinite(np.ravel(v))
                                                  & (np.ravel(v) >= 0))][0]))
            entries.append(v)
    k = len(rows)
    sub = np.stack(np.broadcast_arrays(*entries), axis=-1)
    return _border(sub.reshape(sub.shape[:-1] + (k, k)))


def _bordered_array(sq, rows, cols):
    """:func:`_bordered` of a float array (..., n, n) in one gather: the same matrix, and
    the same refusal (the first offending pair in row-major order)."""
    r, c = np.asarray(rows), np.asarray(cols)
    sub = np.where(r[:, None] == c[None, :], 0.0,
                   sq[..., r[:, None] - 1, c[None, :] - 1].astype(float))
    ok = np.isfinite(sub) & (sub >= 0)
    if not ok.all():
        badpair = ~ok.reshape((-1,) + ok.shape[-2:]).all(axis=0)
        a, b = (int(x) for x in np.argwhere(badpair)[0])
        v = np.ravel(sub[..., a, b])
        _refuse(rows[a], cols[b], float(v[~(np.isfinite(v) & (v >= 0))][0]))
    return _border(sub)


def _border(sub):
    """``sub`` (..., k, k) bordered by the row and column of ones of a Cayley-Menger
    matrix (0 in the corner): (..., k + 1, k + 1)."""
    k = sub.shape[-1]
    M = np.empty(sub.shape[:-2] + (k + 1, k + 1))
    M[..., 0, 0] = 0.0
    M[..., 0, 1:] = 1.0
    M[..., 1:, 0] = 1.0
    M[..., 1:, 1:] = sub
    return M


def _float_mismatch(a, b):
    """Where two float squared distances differ by more than 8 ulps of the larger (the
    symmetry test of :func:`_check_symmetric`; NaN never differs: refused later)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    with np.errstate(invalid="ignore"):
        return np.abs(a - b) > 8 * np.finfo(float).eps * np.maximum(np.abs(a), np.abs(b))


def _symmetric_array(sq, labels) -> bool:
    """:func:`_check_symmetric`'s float test in one vectorised pass over an array
    (..., n, n): True when it passes (the per-pair route then need not run; when it
    fails, that route runs and names the first offending pair)."""
    if not isinstance(sq, np.ndarray) or sq.dtype != np.float64:
        return False
    idx = np.asarray(labels) - 1
    S = sq[..., idx[:, None], idx[None, :]]
    bad = _float_mismatch(S, np.swapaxes(S, -1, -2))
    diag = np.diagonal(S, axis1=-2, axis2=-1)
    return not (bad.any() or _float_mismatch(diag, 0.0).any())


def _refuse(i, j, value):
    raise InputError(f"expected squared distances that are finite and >= 0, got "
                     f"s({i},{j}) = {value}", field="sq")


def _refuse_range(i, j, value):
    """s(i, j) = ``value`` beyond the float64 range, asked for in float64 (the fast
    tier): an :class:`InputError` worded as :func:`distkin.exact.parse_float`'s."""
    import mpmath
    from ..exact import to_tier
    with mpmath.workdps(15):
        shown = mpmath.nstr(to_tier(value, "precise"), 8)
    raise InputError(f"expected squared distances within the float64 range (|x| < 1.8e308) "
                     f"for the fast tier, got s({i},{j}) = {shown}", field="sq",
                     hint="method='precise' or method='certified' take it")
