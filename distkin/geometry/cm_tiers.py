r"""The explicit tiers of :func:`~distkin.geometry.cayley_menger.cayley_menger`
(``method=``): the bordered matrix of Rojas, Borràs and Thomas (ICRA 2012), eq. (1),
with its entries converted to one tier and its determinant taken there.

``fast``
    float64 (numpy LU), with the cancellation estimate of :mod:`.cm_float`.
``precise``
    ``mpmath.mpf`` at ``dps`` digits: the exact determinant correctly rounded when every
    entry is rational, else LU (:func:`distkin.exact.mp_det`) at ``dps`` + 20 digits
    with a CancellationWarning where the estimate says fewer than ``dps`` digits hold.
``certified``
    exact ``flint.fmpq`` when every entry is rational (a float is its exact binary
    value, an ``mpf`` too), else ``flint.arb`` balls (irrational sympy numbers are
    enclosed by :func:`distkin.exact.sympy_to_arb`): a certified radius.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..errors import InputError, warn as _warn
from ..exact import default_dps, mp_det, to_fmpq, to_tier

__all__ = ["tier_determinant"]


def tier_determinant(entries, k, method, dps, label, rows=None, cols=None):
    """The determinant of the bordered matrix ``entries`` ((k+1) rows of numbers of any
    tier) in ``method``'s tier; ``rows``, ``cols``: the point labels of its rows and
    columns after the border (named in a refusal; 1..k when not given)."""
    if method == "fast":
        from .cm_float import float_determinant
        rows = tuple(range(1, k + 1)) if rows is None else rows
        cols = rows if cols is None else cols
        M = np.array([[_to_float(x, (rows[r - 1], cols[c - 1]) if r and c else None)
                       for c, x in enumerate(row)] for r, row in enumerate(entries)],
                     dtype=float)
        return float_determinant(M, k, label)
    if method == "precise":
        return _precise(entries, k, default_dps(dps), label)
    import flint
    vals = [to_tier(_plain(x), "certified") for row in entries for x in row]
    if all(type(v).__name__ == "fmpq" for v in vals):
        return flint.fmpq_mat(k + 1, k + 1, vals).det()
    return flint.arb_mat(k + 1, k + 1, [flint.arb(v) for v in vals]).det()


#: guard digits of the precise tier's determinant of irrational entries
GUARD_DIGITS = 20


def _precise(entries, k, dps, label):
    """The precise tier: an ``mpf`` at ``dps`` digits.  Rational entries (ints,
    Fractions, fmpq, floats and mpf at their exact binary values, numeric strings):
    the exact determinant, correctly rounded (so 0 only when it is 0 exactly; QA: a
    nearly flat triangle of exact data read an exact-looking 0 at 30 digits).  Other
    entries (irrational sympy numbers, arb midpoints): LU in mpmath at ``dps`` +
    :data:`GUARD_DIGITS` digits, rounded to ``dps``, with the relative error estimate of
    :mod:`.cm_float` at that precision; above :math:`10^{-dps}` (more than the guard
    digits cancelled, or a value computed as 0) a CancellationWarning says so."""
    import flint
    import mpmath
    from mpmath import libmp
    exact = [_rational(x) for row in entries for x in row]
    with mpmath.workdps(dps):
        if all(v is not None for v in exact):
            det = flint.fmpq_mat(k + 1, k + 1, exact).det()
            return mpmath.mp.make_mpf(libmp.from_rational(int(det.p), int(det.q),
                                                          mpmath.mp.prec, libmp.round_nearest))
    with mpmath.workdps(dps + GUARD_DIGITS):
        M = [[to_tier(_plain(x), "precise") for x in row] for row in entries]
        det = mp_det(M)
        big = max(abs(x) for row in M[1:] for x in row[1:])
        rho = (k * mpmath.eps * big ** (k - 1) / abs(det) if det != 0
               else mpmath.inf) if k >= 3 and big > 0 else mpmath.mpf(0)
    with mpmath.workdps(dps):
        det = +det
        if rho > mpmath.mpf(10) ** -dps:
            from .cm_float import CancellationWarning
            what = ("computed as 0: it cannot be told from 0" if det == 0 else
                    f"= {mpmath.nstr(det, 8)} with a relative error estimate of "
                    f"{mpmath.nstr(rho, 2)}")
            _warn(CancellationWarning(
                f"Cayley-Menger determinant {label} {what} at {dps} + {GUARD_DIGITS} "
                f"digits (irrational entries, rounded); use a larger dps or "
                f"method='certified'", float(rho)))
        return det


def _rational(x):
    """``x`` as an exact ``flint.fmpq`` when it is rational (an mpf or a float at its
    binary value), else None."""
    x = _plain(x)
    name = type(x).__name__
    if name == "fmpq":
        return x
    if name == "fmpz" or isinstance(x, int):
        import flint
        return flint.fmpq(int(x))
    if isinstance(x, (Fraction, float)) or getattr(x, "is_Rational", False):
        return to_fmpq(x)
    return None


def _plain(x):
    """``x`` as a value :func:`distkin.exact.to_tier` takes: numpy scalars as Python
    numbers, an ``mpf`` as its exact binary value (a Fraction), symbols refused."""
    if isinstance(x, (np.integer, np.floating)) or (isinstance(x, np.ndarray) and x.ndim == 0):
        return x.item()
    if type(x).__name__ == "mpf":
        man, exp = x.man_exp
        man, exp = int(man), int(exp)
        return Fraction(man * 2 ** exp) if exp >= 0 else Fraction(man, 2 ** -exp)
    if getattr(x, "free_symbols", None):
        raise InputError(f"expected numbers for a numeric tier, got the expression {x}",
                         field="sq", hint="method=None keeps a symbolic determinant")
    return x


def _to_float(x, pair=None):
    """One entry as a float64; s(i, j) for ``pair = (i, j)`` beyond the float64 range
    (``10**400``, ``mpf("1e400")``, a huge arb or sympy number) is an InputError naming
    it (:func:`.cm_float._refuse_range`), not an OverflowError nor a silent inf."""
    x = _plain(x)
    try:
        if type(x).__name__ == "arb":
            v = float(x.mid())
        elif isinstance(x, (int, Fraction, float)) or type(x).__name__ in ("fmpq", "fmpz"):
            v = to_tier(x, "fast") if type(x).__name__ != "fmpz" else float(int(x))
        else:
            v = float(x.evalf(20))                     # a constant sympy number
    except OverflowError:
        v = math.inf
    if not math.isfinite(v) and pair is not None:
        from .cm_float import _refuse_range
        _refuse_range(pair[0], pair[1], x)
    return v
