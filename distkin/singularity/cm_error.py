r"""Rounding-error estimates of the Cayley-Menger singularity conditions (fast and
precise tiers of :func:`~distkin.singularity.conditions.cm_pure_condition` and
:func:`~distkin.singularity.conditions.signed_cm_condition`).

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sec. IV: the
conditions are differences (or sums) of products of three Cayley-Menger
(bi)determinants of tetrahedra.  At a singular pose both products can be exactly 0
(every tetrahedron of a product flat): then the relative value is 0/0, and its float64
value is a ratio of rounding errors (QA V 2: 0.9796 at a pose where both products are 0).

The estimate.  A bordered 5 x 5 Cayley-Menger determinant :math:`D` of four points is a
sum of at most 44 terms (the derangements of 5: the diagonal is 0) each a product of
three squared distances, at most :math:`s^3`, :math:`s` the largest squared distance
among its entries (a bideterminant :math:`D(I;J)`: at most 96 terms).  The squared
distances are each rounded (relative error at most about :math:`4\varepsilon`), and LU
adds about :math:`5\varepsilon` times the size of the terms (Higham, *Accuracy and
Stability of Numerical Algorithms*, 2nd ed., SIAM 2002, Ch. 9), so

.. math:: e_D = (5 + 3\cdot 4)\,\varepsilon\; N\, s^3, \qquad N = 44 \text{ or } 96,

an estimate in the spirit of :mod:`distkin.geometry.cm_float` (which uses
:math:`4\varepsilon s^3`), deliberately larger; not a proof (the certified tier gives
one).  A product :math:`P = D_1D_2D_3` then has
:math:`e_P = \prod(|D_i|+e_i) - |P| + 2\varepsilon|P|`.  :math:`\varepsilon` is
:math:`2^{-53}` (fast) or :math:`2^{-\text{prec}}` (precise, at its ``dps``).

A relative condition :math:`(x \pm y)/d` whose denominator :math:`d` (a sum of
products that are :math:`\ge 0` in exact arithmetic) is within its error estimate of 0
is reported undefined: NaN with a :class:`~distkin.geometry.cm_float.CancellationWarning`
saying why; a value whose error estimate exceeds
:data:`~distkin.geometry.cm_float.CANCELLATION_THRESHOLD` warns with the estimate.
"""

from __future__ import annotations

import numpy as np

from ..geometry.cm_float import CANCELLATION_THRESHOLD, CancellationWarning
from ..errors import DegenerateGeometryError, UncertifiedError, warn as _warn
from .float_range import floor_error
from .tiers import _at

__all__: list[str] = []     # helpers of distkin.singularity.conditions


def eps(kind):
    """Unit roundoff of a tier (None for the exact and symbolic ones)."""
    if kind == "fast":
        return 2.0 ** -53
    if kind == "precise":
        import mpmath
        return mpmath.mpf(2) ** -mpmath.mp.prec
    return None


def det_error(sq, rows, cols, kind):
    """:math:`e_D` of the module docstring for the (bi)determinant ``D(rows; cols)``
    (1-based labels) of squared distances ``sq`` (..., 6, 6)."""
    u = eps(kind)
    cols = rows if cols is None else cols
    ri, ci = [r - 1 for r in rows], [c - 1 for c in cols]
    terms = 44 if tuple(cols) == tuple(rows) else 96
    if kind == "fast":
        block = np.abs(np.asarray(sq)[..., ri, :][..., :, ci])
        s = np.max(block, axis=(-2, -1))
        with np.errstate(under="ignore"):
            return floor_error(17 * terms * u * s ** 3, s == 0)   # 0: the points coincide
    s = max(abs(sq[i, j]) for i in ri for j in ci)
    return 17 * terms * u * s ** 3


def product_error(values, errors, kind):
    """:math:`e_P` of a product of (bi)determinants ``values`` with errors ``errors``;
    fast: 0 only where a factor is exactly 0 with a 0 estimate (coincident points),
    else at least the smallest float64 (an estimate that underflowed is not 0)."""
    exact = abs(values[0] * values[1] * values[2])
    bound = (abs(values[0]) + errors[0]) * (abs(values[1]) + errors[1]) \
        * (abs(values[2]) + errors[2])
    e = bound - exact + 2 * eps(kind) * exact
    if kind != "fast":
        return e
    return floor_error(e, np.any([(v == 0) & (x == 0) for v, x in zip(values, errors)],
                                 axis=0))


def relative(num, den, err, kind, what):
    """``num / den`` with the error estimate of the quotient, ``err`` the error of both
    ``num`` and ``den``: NaN (with a warning) where ``den <= err`` (0/0 cannot be ruled
    out); a warning where the estimate exceeds the threshold.  Returns (value, error)."""
    if kind == "fast":
        num, den, err = (np.asarray(x, dtype=float) for x in (num, den, err))
        undefined = ~(den > err)
        with np.errstate(divide="ignore", invalid="ignore"):
            val = np.where(undefined, np.nan, num / np.where(undefined, 1.0, den))
            e = np.where(undefined, np.nan,
                         (err + np.abs(val) * err) / np.where(undefined, 1.0, den - err))
        if undefined.any():
            idx = tuple(int(i) for i in np.argwhere(undefined)[0]) if undefined.ndim else ()
            _undefined_warning(what, float(den[idx]), float(err[idx]), idx,
                               int(undefined.sum()), undefined.size)
        bad = ~undefined & (e > CANCELLATION_THRESHOLD)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0]) if bad.ndim else ()
            _inaccurate_warning(what, float(val[idx]), float(e[idx]), idx)
        return (float(val), float(e)) if val.ndim == 0 else (val, e)
    import mpmath
    if not den > err:
        _undefined_warning(what, float(den), float(err), (), 1, 1)
        return mpmath.nan, mpmath.nan
    val = num / den
    e = (err + abs(val) * err) / (den - err)
    if e > CANCELLATION_THRESHOLD:
        _inaccurate_warning(what, float(val), float(e), ())
    return val, e


def _undefined_warning(what, den, err, idx, count, size):
    where = f" at batch index {idx} ({count} of {size})" if idx else ""
    _warn(CancellationWarning(
        f"relative {what} undefined{where}: both products are within their rounding error "
        f"estimate of 0 (denominator {den:.3g}, error estimate {err:.3g}), so the value may "
        f"be 0/0; returned NaN (use method='certified', or det J)", float("inf"), idx))


def _inaccurate_warning(what, val, e, idx):
    where = f" at batch index {idx}" if idx else ""
    _warn(CancellationWarning(
        f"relative {what} = {val:.6g}{where} with a rounding error estimate of {e:.2g} "
        f"(the products cancel or are nearly 0); use method='certified', or a higher dps",
        e, idx))


def _vanishes(x):
    """Exactly zero (float, fmpq, mpf, an exact arb 0, sympy when provably 0)."""
    if isinstance(x, np.ndarray) and x.dtype != object:
        return x == 0
    return bool(x == 0) or getattr(x, "is_zero", None) is True


def exact_relative(num, den, kind, tets, what):
    """``num / den`` for a denominator that is a sum of products of Cayley-Menger
    determinants (>= 0).  Where it vanishes (then so does ``num``) the relative value
    is 0/0: :class:`DegenerateGeometryError` naming the flat tetrahedra (``tets()``:
    tetrahedron -> D, called only then); an arb
    denominator whose ball contains 0 is :class:`UncertifiedError`."""
    if kind == "fast":
        zero = np.asarray(den == 0)
        if not zero.any():
            return num / den
        idx = tuple(int(i) for i in np.argwhere(zero)[0]) if zero.ndim else ()
    elif type(den).__name__ == "arb" and not den > 0 and not den.is_zero():
        near = [t for t, v in tets().items() if not (v > 0 or v < 0)]
        names = ", ".join("P" + "P".join(map(str, t)) for t in near)
        raise UncertifiedError(f"expected the denominator of the relative {what} to exclude "
                               f"0, got {den.str(5, radius=True)}: the balls of the "
                               f"Cayley-Menger determinants of {names} contain 0 (flat "
                               f"tetrahedra, or within the radius of flat; the relative value "
                               f"may be 0/0)", hint="raise the precision")
    elif not _vanishes(den):
        return num / den
    else:
        idx = ()
    flat = [t for t, v in tets().items() if _vanishes(np.asarray(v)[idx] if kind == "fast" else v)]
    names = ", ".join("P" + "P".join(map(str, t)) for t in flat)
    raise DegenerateGeometryError(
        f"expected a non-vanishing denominator for the relative {what}, got 0{_at(idx)}: "
        f"flat tetrahedra {names} (the condition itself is exactly 0 there)", field="points",
        hint="use relative=False, or det J (jacobian_det)")
