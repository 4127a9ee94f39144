r"""The explicit tiers of :func:`~distkin.geometry.cayley_menger.cayley_menger`
(``method=``): the bordered matrix of Rojas, Borràs and Thomas (ICRA 2012), eq. (1),
with its entries converted to one tier and its determinant taken there.

``fast``
    float64 (numpy LU), with the cancellation estimate of :mod:`.cm_float`.
``precise``
    ``mpmath.mpf`` at ``dps`` digits (:func:`distkin.exact.mp_det`).
``certified``
    exact ``flint.fmpq`` when every entry is rational (a float is its exact binary
    value, an ``mpf`` too), else ``flint.arb`` balls (irrational sympy numbers are
    enclosed by :func:`distkin.exact.sympy_to_arb`): a certified radius.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..errors import InputError
from ..exact import default_dps, mp_det, to_tier

__all__ = ["tier_determinant"]


def tier_determinant(entries, k, method, dps, label):
    """The determinant of the bordered matrix ``entries`` ((k+1) rows of numbers of any
    tier) in ``method``'s tier."""
    if method == "fast":
        from .cm_float import float_determinant
        M = np.array([[_to_float(x) for x in row] for row in entries], dtype=float)
        return float_determinant(M, k, label)
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            return mp_det([[to_tier(_plain(x), "precise") for x in row] for row in entries])
    import flint
    vals = [to_tier(_plain(x), "certified") for row in entries for x in row]
    if all(type(v).__name__ == "fmpq" for v in vals):
        return flint.fmpq_mat(k + 1, k + 1, vals).det()
    return flint.arb_mat(k + 1, k + 1, [flint.arb(v) for v in vals]).det()


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


def _to_float(x):
    x = _plain(x)
    if type(x).__name__ == "arb":
        return float(x.mid())
    if isinstance(x, (int, Fraction, float)) or type(x).__name__ in ("fmpq", "fmpz"):
        return to_tier(x, "fast") if type(x).__name__ != "fmpz" else float(int(x))
    return float(x.evalf(20))                          # a constant sympy number
