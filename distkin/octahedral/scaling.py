r"""Scale invariance of the octahedral forward kinematics: normalise by a power of two.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
Multiplying every length by :math:`\lambda` multiplies the poses' points and
translations by :math:`\lambda`, the roots :math:`s_{15}` by :math:`\lambda^2` and the
octic's coefficient of :math:`s_{15}^j` by :math:`\lambda^{2(12-j)}` (it is homogeneous
of degree 12 in the squared lengths, :mod:`.octic`), and leaves the rotations and the
relative leg residuals alone.  With :math:`\lambda = 2^{-k}` the scaling is exact in
binary floating point (and in rationals), so every tier solves the normalised problem
and scales its answer back, exactly: the float64 kernels never overflow (their
coefficients are of degree up to 24 in the lengths: lengths of 1e13 already overflowed)
and the certified tier's numbers stay small.

Lengths whose largest value lies in :math:`[2^{-10}, 2^{10})` are left as they are
(:func:`exponent` returns 0), so that the usual problems run on the user's own numbers.
The clear error is kept for what normalisation cannot help (:func:`check_range`): the
squared lengths of the answer itself (:math:`s_{15}`) must be float64 numbers, so the
largest length must lie in :math:`[2^{-500}, 2^{510})`.  A squared length so much
smaller than the largest that it vanishes in float64 after normalisation (a ratio
beyond :math:`2^{-1000}`) is not refused: the exact tiers keep it exactly, and the fast
tier's proof (:mod:`.conditioning`) says it cannot vouch for such inputs (a
ConditioningWarning; ``auto`` then answers with the certified tier).  ``check_range``'s
``smallest2`` refuses it for a caller that wants the refusal; the solvers do not.
"""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction

import numpy as np

from ..errors import InputError

__all__ = ["exponent", "exponents", "check_range", "scale_problem", "rescale_result",
           "rescale_octic", "in_units", "KEEP", "MAX_EXP", "MIN_EXP"]

#: largest lengths in [2^-KEEP, 2^KEEP) are not rescaled
KEEP = 10
#: the largest length must be below 2^MAX_EXP (its square, s15, below 2^1020) ...
MAX_EXP = 510
#: ... and at least 2^MIN_EXP (its square above the subnormal range)
MIN_EXP = -500
#: a squared length below this after normalisation vanishes in float64 arithmetic
_SMALLEST = 2.0 ** -1000


def exponent(largest: float) -> int:
    """k such that the lengths divided by 2^k have their largest value in [1/2, 1), or 0
    when it already lies in [2^-KEEP, 2^KEEP) (see the module docstring)."""
    if not largest > 0 or not math.isfinite(largest):
        return 0
    e = math.frexp(largest)[1]          # largest in [2^(e-1), 2^e)
    return 0 if -KEEP < e <= KEEP else e


def exponents(largest) -> np.ndarray:
    """:func:`exponent` of an array of largest lengths (batched)."""
    e = np.frexp(np.asarray(largest, dtype=float))[1].astype(np.int64)
    return np.where((e > -KEEP) & (e <= KEEP), 0, e)


def check_range(largest: float, field: str, smallest2: float | None = None,
                small_field: str | None = None) -> None:
    """Raise :class:`InputError` where normalisation cannot help (module docstring).

    Parameters
    ----------
    largest : float
        The largest length (coordinate modulus or leg) of the problem.
    field : str
        Where it comes from (named in the error).
    smallest2 : float, optional
        The smallest squared side or leg after normalisation, and ``small_field`` its
        field.
    """
    if not largest < 2.0 ** MAX_EXP:
        raise InputError(f"expected lengths below 2^{MAX_EXP} (about {2.0 ** MAX_EXP:.1e}), "
                         f"got {largest:.6g}: the squared lengths of the answer (s15) would "
                         "overflow float64", field=field,
                         hint="express the lengths in a larger unit")
    if not largest >= 2.0 ** MIN_EXP:
        raise InputError(f"expected lengths of at least 2^{MIN_EXP} (about "
                         f"{2.0 ** MIN_EXP:.1e}), got at most {largest:.6g}: the squared "
                         "lengths of the answer (s15) would underflow float64", field=field,
                         hint="express the lengths in a smaller unit")
    if smallest2 is not None and not smallest2 >= _SMALLEST:
        raise InputError("expected every side and leg within a factor 2^500 of the largest "
                         f"length, got a squared length {smallest2:.3g} times the largest "
                         "one's square: beyond float64's range", field=small_field or field)


class in_units:
    """Context manager: an error raised inside, by a tier working on lengths divided by
    2^k, says so (its numbers, e.g. a root s15, are in those units)."""

    def __init__(self, k: int):
        self.k = k

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        from ..errors import DistkinError
        if self.k and isinstance(exc, DistkinError):
            exc.message += (f" (numbers in this message are for the lengths divided by "
                            f"2^{self.k}, s15 by 4^{self.k})")
            exc.args = (exc.one_line(),)
        return False


def _scale_value(v, k: int):
    """v times 2^-k, exactly, for Fractions, floats, sympy numbers."""
    if k == 0:
        return v
    if isinstance(v, Fraction):
        return v / 2 ** k if k > 0 else v * 2 ** (-k)
    if isinstance(v, float):
        return math.ldexp(v, -k)
    import sympy
    return v * sympy.Rational(1, 2) ** k


def scale_problem(problem, k: int):
    """The :class:`~.problem.Problem` with every length divided by 2^k (exactly)."""
    if k == 0:
        return problem
    f = lambda rows: tuple(tuple(_scale_value(v, k) for v in r) for r in rows)  # noqa: E731
    return replace(problem, base=f(problem.base), platform=f(problem.platform),
                   legs=tuple(_scale_value(v, k) for v in problem.legs),
                   sides2=tuple(_scale_value(v, 2 * k) for v in problem.sides2),
                   legs2=tuple(_scale_value(v, 2 * k) for v in problem.legs2))


def _native(x, k: int):
    """A tier-native number (float, Fraction, fmpq, arb, mpf, or nested lists/arrays of
    them) times 2^k, exactly."""
    if k == 0 or x is None:
        return x
    if isinstance(x, (list, tuple)):
        return type(x)(_native(v, k) for v in x)
    if isinstance(x, np.ndarray):
        return np.ldexp(x, k) if x.dtype.kind == "f" else np.array(
            [_native(v, k) for v in x.tolist()], dtype=object)
    if isinstance(x, float):
        return math.ldexp(x, k)
    name = type(x).__name__
    if name == "mpf":
        import mpmath
        return mpmath.ldexp(x, k)
    if isinstance(x, Fraction) or name in ("fmpq", "arb", "fmpz", "int"):
        return x * 2 ** k if k > 0 else x / 2 ** (-k)
    return x * 2 ** k


def rescale_octic(octic, k: int):
    """The octic's coefficients (highest degree first) for lengths times 2^k: the
    coefficient of s15^j times 2^(2k(12 - j)).  Returns (coefficients, ok): ok is False
    when a float coefficient over- or underflows (the normalised ones are returned)."""
    if k == 0:
        return tuple(octic), True
    out = []
    for i, c in enumerate(octic):
        j = len(octic) - 1 - i
        if isinstance(c, float):
            try:
                v = math.ldexp(c, 2 * k * (12 - j))
            except OverflowError:
                return tuple(octic), False
            if (c != 0 and (v == 0 or not math.isfinite(v))) or (
                    c != 0 and abs(v) < 2.0 ** -1022):
                return tuple(octic), False
            out.append(v)
        else:
            out.append(_native(c, 2 * k * (12 - j)))
    return tuple(out), True


def rescale_result(res, k: int):
    """An :class:`~.forward.AssemblyResult` of the problem divided by 2^k, scaled back
    (module docstring)."""
    if k == 0:
        return res
    poses = tuple(replace(
        p, s15=math.ldexp(p.s15, 2 * k), translation=np.ldexp(p.translation, k),
        points=np.ldexp(p.points, k), max_leg_error=math.ldexp(p.max_leg_error, k),
        radius=math.ldexp(p.radius, k),
        native=None if p.native is None else {
            "s15": _native(p.native["s15"], 2 * k), "points": _native(p.native["points"], k),
            "rotation": p.native["rotation"],
            "translation": _native(p.native["translation"], k)})
        for p in res.poses)
    roots = tuple(replace(r, value=math.ldexp(r.value, 2 * k),
                          radius=math.ldexp(r.radius, 2 * k),
                          native=_native(r.native, 2 * k)) for r in res.roots)
    octic, ok = rescale_octic(res.octic, k)
    notes = res.notes
    if not ok:
        notes = notes + (f"the octic's coefficients in the given units overflow float64: "
                         f"those shown are for the lengths divided by 2^{k} (s15 by "
                         f"4^{k})",)
    cond = res.conditioning
    return replace(res, poses=poses, roots=roots, octic=octic, notes=notes,
                   conditioning=None if cond is None else cond.scaled(k))
