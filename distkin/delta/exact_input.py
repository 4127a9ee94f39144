"""Exact inputs of the Δ-transform (Rojas, Borràs, Thomas, *The Octahedral Manipulator
Revisited*, ICRA 2012, Sec. V-VI): points, offsets and leg lengths checked at the entry
points and made exact, and the exact normal forms of the transform's results.

The rule of docs/design.md §3 holds throughout: a bare float is its exact binary value,
a numeric string or a rational is exact, and nothing is ever rounded to a "nice"
number (``sympy.nsimplify`` is not used on data, see :func:`_exact_form`).  Every
malformed value raises :class:`~distkin.errors.InputError` naming the field, what was
expected and what was received.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..exact import Exact, exact_to_float, parse_exact, to_sympy

__all__: list[str] = []     # helpers of distkin.delta; the public API is in .transform


def _exact_form(x):
    """``x`` in an exact normal form: expanded, and factorised when it has symbols.

    Only exact identities are used.  ``sympy.nsimplify`` is never applied to data: it
    replaces a number by a "nice" one near its 15-digit value, which snaps the exact
    binary value of a bare float to a neighbouring rational (docs/design.md §3) and,
    on a long sum of radicals that cancels in 15 digits, returns 0 for a value that is
    not 0 (an l-leg squared of about 2.5e5 became 0)."""
    import sympy as sp
    x = sp.expand(x)
    return sp.factor(x) if x.free_symbols else x


def _quotient(num, den):
    r"""``num / den`` exact and small: factorised when symbolic; a rational or
    :math:`p + q\sqrt{D}` when the denominator has at most one square root (its conjugate
    removes it); else the plain quotient of the expanded parts.  Exact identities only
    (see :func:`_exact_form`)."""
    import sympy as sp
    if num.free_symbols or den.free_symbols:
        return sp.factor(num / den)
    if den.is_Rational:
        return sp.expand(num / den)
    if len({a for a in den.atoms(sp.Pow) if not a.exp.is_Integer}) <= 1:
        return sp.expand(sp.radsimp(num / den))
    return num / den


def _readable(x, digits: int = 6, width: int = 40) -> str:
    """A constant sympy number ``x`` for a message: its exact form and its value when
    the exact form has at most ``width`` characters, else its value only and the length
    of the exact form; the value to ``digits`` significant digits, from sympy's
    arbitrary-precision evaluation, so that a number beyond float64 (a squared leg of
    1e400) keeps its digits and exponent: never ``inf``."""
    import mpmath
    import sympy as sp
    text = str(x)
    approx = mpmath.nstr(mpmath.mpf(sp.Float(sp.N(x, digits + 5))), digits)
    if len(text) <= width:
        return f"{text} (= {approx})"
    return f"{approx} (exact form of {len(text)} characters)"


def _is_zero(x) -> bool:
    """True only when the constant ``x`` is exactly 0: structurally, or (when sympy's
    sign test cannot decide) proved by :meth:`sympy.Expr.equals`; a nonzero value,
    however small, is never declared 0."""
    if x == 0:
        return True
    if x.is_positive or x.is_negative:
        return False
    return x.equals(0) is True


def _as_sym(value, field, *, allow_symbols: bool = True):
    """One value as an exact sympy expression (docs/design.md §3).

    Integers, Fractions and numeric strings are exact (``"19.8"`` is 99/5); a bare float
    (Python, numpy or a sympy ``Float``) is its exact binary value; strings may name
    symbols (``"Delta1"``) when ``allow_symbols``.  NaN, infinities, non-real values,
    booleans and other types raise :class:`InputError` naming ``field`` and the value.
    """
    import sympy as sp
    if isinstance(value, np.generic) and not isinstance(value, np.bool_):
        value = value.item()
    if isinstance(value, Exact):
        v = to_sympy(value)
    elif isinstance(value, sp.Basic):
        v = value
        if v.has(sp.oo, -sp.oo, sp.zoo, sp.nan):
            raise InputError(f"expected a finite number, got {value}", field=field)
        floats = v.atoms(sp.Float)
        if floats:                      # exact binary values, never "nice" neighbours
            v = v.xreplace({f: sp.Rational(f) for f in floats})
    elif isinstance(value, str):
        v = to_sympy(parse_exact(value, field, allow_symbols=allow_symbols))
    else:
        v = to_sympy(parse_exact(value, field))
    if v.free_symbols and not allow_symbols:
        raise InputError(f"expected a number, got {value!r} with the symbol(s) "
                         f"{', '.join(sorted(map(str, v.free_symbols)))}", field=field)
    if not v.free_symbols and v.is_real is False:
        raise InputError(f"expected a real number, got {value!r}", field=field)
    return v


def _point_rows(points, field: str):
    """Three points of three coordinates each (any sequences), else InputError."""
    if isinstance(points, (str, bytes)) or not hasattr(points, "__len__"):
        raise InputError(f"expected 3 points of 3 coordinates, got {type(points).__name__} "
                         f"{points!r}", field=field)
    if len(points) != 3:
        raise InputError(f"expected 3 points, got {len(points)}: {points!r}", field=field)
    for i, p in enumerate(points):
        if isinstance(p, (str, bytes)) or not hasattr(p, "__len__") or len(p) != 3:
            raise InputError(f"expected a point of 3 coordinates, got {p!r}",
                             field=f"{field}[{i}]")
    return points


def _sym_points(base, platform) -> tuple:
    """P1..P6 as tuples of exact sympy numbers (floats: their exact binary values);
    a malformed point or a NaN coordinate raises InputError naming ``base[i][j]`` or
    ``platform[i][j]``."""
    return tuple(tuple(_as_sym(x, f"{name}[{i}][{j}]", allow_symbols=False)
                       for j, x in enumerate(p))
                 for name, pts in (("base", base), ("platform", platform))
                 for i, p in enumerate(_point_rows(pts, name)))


def _base_platform(octahedral):
    """``(base, platform)`` of an Octahedral mechanism or a pair, each checked to be 3
    points of 3 coordinates (InputError naming ``base``/``platform`` otherwise)."""
    if hasattr(octahedral, "base") and hasattr(octahedral, "platform"):
        base, platform = octahedral.base, octahedral.platform
    elif isinstance(octahedral, (list, tuple, np.ndarray)) and len(octahedral) == 2:
        base, platform = octahedral
    else:
        raise InputError(f"expected an octahedral mechanism or a pair (base, platform), got "
                         f"{type(octahedral).__name__} {octahedral!r}", field="octahedral")
    return _point_rows(base, "base"), _point_rows(platform, "platform")


def _check_count(values, field, what="leg lengths"):
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise InputError(f"expected 6 {what}, got {type(values).__name__} {values!r}",
                         field=field)
    if len(values) != 6:
        raise InputError(f"expected 6 {what}, got {len(values)}", field=field)


def _float_legs(values, field) -> np.ndarray:
    """Six finite positive leg lengths as float64 (strings parsed exactly, then rounded
    once); anything else raises :class:`InputError` naming ``field[i]`` and the value."""
    _check_count(values, field)
    out = np.empty(6)
    for i, v in enumerate(values):
        fld = f"{field}[{i}]"
        if isinstance(v, np.generic) and not isinstance(v, np.bool_):
            v = v.item()
        if isinstance(v, (bool, np.bool_)):
            raise InputError(f"expected a leg length, got {v!r}", field=fld)
        if isinstance(v, (int, float)):
            x = float(v) if isinstance(v, float) else exact_to_float(parse_exact(v, fld), fld)
        elif isinstance(v, Exact):
            x = exact_to_float(v, fld)
        elif hasattr(v, "free_symbols"):      # a sympy number
            x = float(_as_sym(v, fld, allow_symbols=False))
        else:
            x = exact_to_float(parse_exact(v, fld), fld)
        if not math.isfinite(x):
            raise InputError(f"expected a finite leg length, got {v!r}", field=fld)
        if not x > 0:
            raise InputError(f"expected a positive leg length, got {v!r}", field=fld)
        out[i] = x
    return out


def _check_leg_range(legs: np.ndarray, field) -> None:
    """The octahedral solver's range (:func:`distkin.octahedral.scaling.check_range`)
    applied to the m-legs, so that every tier refuses them the same way, naming
    ``field[i]``: beyond it their squares (eq. (8)) leave float64."""
    from ..octahedral.scaling import check_range
    i = int(np.argmax(legs))
    check_range(float(legs[i]), f"{field}[{i}]")


def _input_key(value):
    """A hashable key that equals for inputs :func:`_as_sym` reads alike, or ``None``
    when one part is of a type it does not know (the caller then does not cache).

    The type is part of the key, so ``1.0`` (the float, its exact binary value) and
    ``"1.0"`` (the decimal) or ``1`` stay apart even where they happen to be equal;
    floats by their bits (``float.hex``), numpy arrays by dtype, shape and bytes.  A
    mechanism object (with ``base`` and ``platform``) is keyed by its two point sets.
    Used to skip the exact parsing of a mechanism already built (the 6-6 forward
    kinematics re-parsed its string coordinates with sympy on every call)."""
    from fractions import Fraction
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool):
        return ("bool", value)
    if isinstance(value, str):
        return ("str", value)
    if isinstance(value, int):
        return ("int", value)
    if isinstance(value, float):
        return ("float", value.hex())
    if isinstance(value, Fraction):
        return ("fraction", value.numerator, value.denominator)
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            return None
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, (list, tuple)):
        parts = tuple(_input_key(v) for v in value)
        return None if any(p is None for p in parts) else ("seq", parts)
    if hasattr(value, "base") and hasattr(value, "platform"):
        parts = (_input_key(value.base), _input_key(value.platform))
        return None if None in parts else ("mechanism", parts)
    return None
