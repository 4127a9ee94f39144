"""Exact numbers from scene text, and the three arithmetic tiers.

A scene value written as a string is parsed *exactly*: ``"19.8"`` is 99/5,
``"sqrt(108)"`` is 6*sqrt(3), ``"12/5"`` is 12/5.  An integer is exact.  A bare
float is taken as its exact binary value and flagged (:class:`Exact.from_float`).

The tiers (docs/design.md §3):

``fast``
    float64 (numpy, generated kernels).
``precise``
    mpmath at ``dps`` decimal digits.
``certified``
    python-flint: exact ``fmpq`` where the data are rational, ``arb`` balls otherwise.

Parsing uses :mod:`ast`, not ``eval``; sympy is imported only when an irrational
value (``sqrt``, ``pi``) or a symbol is met, so ``import distkin`` stays light.

Sizes are bounded before anything is evaluated (:func:`size_bound`): a value whose
exact form would need more than :data:`MAX_BITS` bits in its numerator or denominator
(``"10**10**10"``, ``"9**9**9**9"``, ``"1e999999999"``) is an :class:`InputError`
naming the field, answered at once instead of after minutes of big-integer arithmetic.
"""

from __future__ import annotations

import ast
import functools
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from .errors import InputError

__all__ = [
    "MAX_BITS",
    "size_bound",
    "METHODS",
    "METHODS_AUTO",
    "dps_without_precise",
    "Exact",
    "parse_exact",
    "parse_float",
    "exact_to_float",
    "parse_vector",
    "check_method",
    "to_fraction",
    "to_fmpq",
    "to_tier",
    "mp_det",
    "to_sympy",
    "sympy_to_arb",
    "default_dps",
    "MAX_DPS",
    "float_ball",
    "float_mpf",
]

#: the arithmetic tiers every numeric entry point accepts
METHODS = ("fast", "precise", "certified")
#: the tiers of entry points that can also choose one themselves from a conditioning
#: estimate (``"auto"``: fast first, escalated when the estimate says so)
METHODS_AUTO = METHODS + ("auto",)

_FUNCS = {"sqrt", "cbrt", "pi"}
#: the largest exact number a scene value may stand for: numerator and denominator of at
#: most this many bits (about 1,200 decimal digits; a float's exact value needs at most
#: 1,075, ``"1e308"`` 1,024)
MAX_BITS = 4096
_LOG2_10 = math.log2(10)
_DECIMAL = None  # compiled lazily: the regular expression of a decimal literal


#: the largest ``dps`` of the precise tier: the digits of :data:`MAX_BITS` bits
#: (floor(4096 log10 2) = 1233), the bound of the certified tier's ``bits`` (53..4096)
#: and of an exact scene value; a million digits ran for hours
MAX_DPS = int(MAX_BITS / _LOG2_10)


def default_dps(dps: int | None) -> int:
    """The decimal precision of the ``precise`` tier (30 when not given): an integer
    5..:data:`MAX_DPS` (1233 digits, about 4096 bits); :class:`InputError` otherwise."""
    if dps is None:
        return 30
    if not isinstance(dps, int) or isinstance(dps, bool) or not 5 <= dps <= MAX_DPS:
        raise InputError(f"expected dps as an integer 5..{MAX_DPS} (decimal digits, at most "
                         f"{MAX_BITS} bits), got {dps!r}", field="dps")
    return dps


def dps_without_precise(dps, method, field: str = "dps") -> InputError:
    """The error of ``dps`` given with a method other than "precise" (the only tier that
    reads it; it would be ignored): with no method, the default computes in the input's
    own number type, and the message says so (QA: it ended in "got method None")."""
    got = (f"got method {method!r}" if method is not None else
           f"got dps={dps!r} and no method (the default, the input's own number type, "
           "has no digits to set)")
    return InputError(f"expected 'dps' only with method 'precise' (the mpmath digits), "
                      f"{got}", field=field, hint="method='precise' with dps")


def check_method(method: str, *, allowed=METHODS, field: str = "method") -> str:
    """Validate a tier name; raises :class:`InputError` naming the choices."""
    if method not in allowed:
        raise InputError(f"expected one of {', '.join(map(repr, allowed))}, got {method!r}",
                         field=field)
    return method


@dataclass(frozen=True)
class Exact:
    """An exactly known real number.

    Attributes
    ----------
    value : fractions.Fraction or sympy.Expr
        A :class:`~fractions.Fraction` when rational, else a sympy expression.
    text : str
        What the user wrote (for messages and reports).
    from_float : bool
        True when the value was a bare float taken as its exact binary value.
    """

    value: Any
    text: str
    from_float: bool = False

    @property
    def is_rational(self) -> bool:
        return isinstance(self.value, Fraction)

    def __float__(self) -> float:
        # exact, but beyond float64 ("1e400"; a Fraction overflows): InputError
        return exact_to_float(self, None)

    def __str__(self) -> str:
        v = self.value
        if isinstance(v, Fraction):
            return str(v.numerator) if v.denominator == 1 else f"{v.numerator}/{v.denominator}"
        return str(v)


class _Irrational(Exception):
    """Internal: the expression needs sympy."""


def _eval_rational(node):
    """Evaluate an AST of + - * / ** over integers and decimals, exactly."""
    if isinstance(node, ast.Expression):
        return _eval_rational(node.body)
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise ValueError("not a number")
        if isinstance(node.value, float):
            # the literal text is handled by the caller (Fraction(str)), see _literal
            raise _Irrational()
        return Fraction(node.value)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        v = _eval_rational(node.operand)
        return v if isinstance(node.op, ast.UAdd) else -v
    if isinstance(node, ast.BinOp):
        a, b = _eval_rational(node.left), _eval_rational(node.right)
        if isinstance(node.op, ast.Add):
            return a + b
        if isinstance(node.op, ast.Sub):
            return a - b
        if isinstance(node.op, ast.Mult):
            return a * b
        if isinstance(node.op, ast.Div):
            if b == 0:
                raise ZeroDivisionError
            return a / b
        if isinstance(node.op, ast.Pow):
            if b.denominator != 1 or abs(b) > 64:
                raise _Irrational()
            if a == 0 and b < 0:
                raise ZeroDivisionError
            return a ** int(b)
    if isinstance(node, (ast.Call, ast.Name)):
        raise _Irrational()
    raise ValueError("unsupported syntax")


def _show(value, n: int = 40) -> str:
    """``repr(value)``, shortened to about n characters (a scene value can be huge)."""
    r = repr(value)
    return r if len(r) <= n else f"{r[:n - 12]}...{r[-8:]} ({len(r) - 2} characters)"


def _decimal_bits(text: str):
    """Bits of the exact rational a decimal literal stands for (digits and exponent
    read from the text, nothing evaluated), or None if ``text`` is not one."""
    global _DECIMAL
    if _DECIMAL is None:
        import re
        _DECIMAL = re.compile(r"\s*[+-]?(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?\s*$")
    m = _DECIMAL.match(text.replace("_", ""))
    if not m or not (m.group(1) or m.group(2)):
        return None
    digits = len(m.group(1) or "") + len(m.group(2) or "")
    exp = m.group(3) or "0"
    if len(exp.lstrip("+-")) > 12:
        return math.inf
    return (digits + abs(int(exp)) + len(m.group(2) or "")) * _LOG2_10 + 1


def size_bound(tree, text: str) -> float:
    """An upper bound on the bits of the numerator and denominator of the exact value of
    an expression (an :mod:`ast` tree of ``text``), computed without evaluating it:
    integers by their length, decimals by their digits and exponent, ``a + b`` and
    ``a * b`` by ``bits(a) + bits(b) + 1``, ``a ** n`` by ``|n| bits(a)`` (the exponent is
    evaluated only when it is itself below 64 bits), ``sqrt``/``cbrt`` by half/third of
    their argument's (plus one); ``pi`` and symbols count 2.  ``inf`` when an exponent
    is too large to evaluate."""
    def bits(node):
        if isinstance(node, ast.Expression):
            return bits(node.body)
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, int) and not isinstance(v, bool):
                return math.log2(abs(v)) if abs(v) > 1 else 0.0
            if isinstance(v, float):
                seg = ast.get_source_segment(text, node)
                b = _decimal_bits(seg) if seg is not None else None
                return b if b is not None else 1100.0
            return 1.0
        if isinstance(node, ast.UnaryOp):
            return bits(node.operand)
        if isinstance(node, ast.Name):
            return 2.0
        if isinstance(node, ast.Call):
            inner = max((bits(a) for a in node.args), default=1.0)
            return inner / (3 if getattr(node.func, "id", "") == "cbrt" else 2) + 1
        if isinstance(node, ast.BinOp):
            a = bits(node.left)
            if isinstance(node.op, ast.Pow):
                eb = bits(node.right)
                if eb > 64:
                    return math.inf
                try:
                    e = _eval_rational(node.right)
                except (_Irrational, ValueError, ZeroDivisionError):
                    return a * 2.0 ** eb           # an irrational exponent: |e| < 2^eb
                return a * abs(float(e))
            return a + bits(node.right) + 1
        return 1.0
    return bits(tree)


def _check_names(tree, allow_symbols: bool):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in _FUNCS or node.keywords:
                raise ValueError("only sqrt(...), cbrt(...) and pi are allowed")
        elif isinstance(node, ast.Name):
            if node.id not in _FUNCS and not allow_symbols:
                raise ValueError(f"unknown name {node.id!r}")
        elif isinstance(node, (ast.Attribute, ast.Subscript, ast.Lambda, ast.Compare,
                               ast.BoolOp, ast.IfExp, ast.List, ast.Tuple, ast.Dict)):
            raise ValueError("unsupported syntax")


@functools.lru_cache(maxsize=1024)
def _sympy_from_text(text: str, allow_symbols: bool):
    """The sympy value of an irrational scene string (cached: sympy's parser costs about
    1 ms, and the same strings come back on every call of, e.g., the 6-6 forward
    kinematics; sympy expressions are immutable, and a failure is not cached)."""
    import sympy
    # decimals are exact: "19.8" -> 99/5, never a binary float
    # cbrt is the real cube root (numpy's cbrt: cbrt(-8) = -2), not sympy.cbrt, whose
    # principal root of a negative number is complex
    return sympy.sympify(text, rational=True, locals={
        "sqrt": sympy.sqrt, "cbrt": lambda x: sympy.real_root(x, 3), "pi": sympy.pi})


def exact_to_float(ex: Exact, field: str | None = "value", factor=1) -> float:
    """``ex`` times ``factor`` (a unit, exact when a Fraction) as a float64, rounded once
    when both are rational; beyond the float64 range (``"1e400"``) an
    :class:`InputError` naming ``field``.  (``float(ex)`` is this with no field.)"""
    try:
        if isinstance(ex.value, Fraction) and isinstance(factor, (int, Fraction)):
            x = float(ex.value * factor)
        else:
            x = float(ex.value) * float(factor)
    except OverflowError:
        x = math.inf
    if math.isinf(x):
        text = ex.text if len(ex.text) <= 60 else ex.text[:57] + "..."
        si = " in SI units" if factor != 1 else ""
        raise InputError(f"expected a number within the float64 range (|x| < 1.8e308{si}), "
                         f"got {text!r}", field=field)
    return x


def parse_float(value, field: str = "value") -> float:
    """A scene value as a float64 (:func:`parse_exact`, then rounded once); a value
    beyond the float64 range (``"1e400"``) is an :class:`InputError` naming ``field``."""
    return exact_to_float(parse_exact(value, field), field)


def parse_exact(value, field: str = "value", *, allow_symbols: bool = False) -> Exact:
    """Parse one scene value exactly.

    Parameters
    ----------
    value : str, int, float, Fraction
        ``"19.8"``, ``"sqrt(108)"``, ``"12/5"``, ``"-3e-2"``, ``7`` or ``0.1``.
    field : str
        The scene field the value comes from; named in any error.
    allow_symbols : bool
        Accept free names such as ``"Delta1"`` (returned as sympy symbols).

    Returns
    -------
    Exact

    Raises
    ------
    InputError
        Unparsable text, a non-finite float, or a value of the wrong type; the message
        quotes the offending text and names ``field``.

    Examples
    --------
    >>> parse_exact("19.8").value
    Fraction(99, 5)
    >>> str(parse_exact("12/5"))
    '12/5'
    """
    if isinstance(value, bool):
        raise InputError(f"expected a number, got the boolean {value!r}", field=field)
    if isinstance(value, Fraction):
        return Exact(value, str(value))
    if isinstance(value, int):
        return Exact(Fraction(value), str(value))
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(f"expected a finite number, got {value!r}", field=field)
        return Exact(Fraction(value), repr(value), from_float=True)
    if not isinstance(value, str):
        raise InputError(f"expected a number or a numeric string, got {type(value).__name__} "
                         f"{_show(value)}", field=field)
    text = value.strip()
    if not text:
        raise InputError("expected a number, got an empty string", field=field)
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
        _check_names(tree, allow_symbols)
    except (SyntaxError, ValueError) as exc:
        raise InputError(f"cannot parse {_show(value)} as an exact number "
                         f"({_show(str(exc), 80)})", field=field,
                         hint='write e.g. "19.8", "12/5" or "sqrt(108)"') from None
    size = size_bound(tree, text.replace("^", "**"))
    if not size <= MAX_BITS:
        raise InputError(f"expected a number of at most {MAX_BITS} bits (about "
                         f"{int(MAX_BITS / _LOG2_10)} digits), got {_show(value)}"
                         + ("" if math.isinf(size) else f" (about {int(size)} bits)"),
                         field=field, hint="write the value in a unit where it is smaller")
    try:
        # plain decimal literal: Fraction parses "19.8" and "1e-3" exactly
        return Exact(Fraction(text), text)
    except (ValueError, ZeroDivisionError):
        pass
    try:
        return Exact(_eval_rational(tree), text)
    except ZeroDivisionError:
        raise InputError(f"division by zero in {_show(value)}", field=field) from None
    except ValueError as exc:
        raise InputError(f"cannot parse {_show(value)} as an exact number ({exc})", field=field) from None
    except _Irrational:
        pass
    try:
        expr = _sympy_from_text(text.replace("^", "**"), allow_symbols)
    except Exception as exc:  # sympy raises many types on bad text
        raise InputError(f"cannot parse {_show(value)} as an exact number ({exc})", field=field) from None
    if expr.has(__import__("sympy").zoo, __import__("sympy").nan):
        raise InputError(f"{_show(value)} is not a finite number", field=field)
    if expr.is_Rational:
        return Exact(Fraction(int(expr.p), int(expr.q)), text)
    if not allow_symbols and expr.free_symbols:
        raise InputError(f"expected a number, got symbols in {_show(value)}", field=field)
    if not expr.free_symbols and expr.is_real is False:
        raise InputError(f"expected a real number, got {_show(value)} = {expr}", field=field)
    return Exact(expr, text)


def parse_vector(values, field: str, *, length: int | None = None,
                 allow_symbols: bool = False) -> tuple[Exact, ...]:
    """Parse a list of scene values; errors name the element (``field[3]``)."""
    if not isinstance(values, (list, tuple)):
        raise InputError(f"expected a list of {length or 'some'} numbers, got "
                         f"{type(values).__name__} {values!r}", field=field)
    if length is not None and len(values) != length:
        raise InputError(f"expected {length} values, got {len(values)}", field=field)
    return tuple(parse_exact(v, f"{field}[{i}]", allow_symbols=allow_symbols)
                 for i, v in enumerate(values))


def to_fraction(x) -> Fraction:
    """Exact rational value of an :class:`Exact`, int, Fraction, float, fmpq or sympy Rational."""
    if isinstance(x, Exact):
        x = x.value
    if isinstance(x, Fraction):
        return x
    if isinstance(x, bool):
        raise InputError(f"expected a rational number, got {x!r}")
    if isinstance(x, int):
        return Fraction(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            raise InputError(f"expected a finite number, got {x!r}")
        return Fraction(x)
    tname = type(x).__name__
    if tname == "fmpq":
        return Fraction(int(x.p), int(x.q))
    if tname == "fmpz":
        return Fraction(int(x))
    if getattr(x, "is_Rational", False):
        return Fraction(int(x.p), int(x.q))
    raise InputError(f"expected an exactly rational number, got {tname} {x!r}",
                     hint="the certified tier needs rational data, or a value sympy can enclose")


def to_fmpq(x):
    """Exact :class:`flint.fmpq` of a rational value (see :func:`to_fraction`)."""
    import flint
    f = to_fraction(x)
    return flint.fmpq(f.numerator, f.denominator)


def to_sympy(x):
    """sympy number of an :class:`Exact` (or a plain number)."""
    import sympy
    if isinstance(x, Exact):
        x = x.value
    if isinstance(x, Fraction):
        return sympy.Rational(x.numerator, x.denominator)
    if isinstance(x, float):
        f = Fraction(x)
        return sympy.Rational(f.numerator, f.denominator)
    return sympy.sympify(x)


def sympy_to_arb(expr):
    """A certified :class:`flint.arb` enclosure of a constant sympy expression.

    Walks ``Add``, ``Mul``, ``Pow`` (integer and rational exponents), rationals and
    ``pi``; anything else raises :class:`InputError`, because it cannot be enclosed
    with certainty here.
    """
    import flint
    import sympy
    if expr.is_Rational:
        return flint.arb(flint.fmpq(int(expr.p), int(expr.q)))
    if expr is sympy.pi:
        return flint.arb.pi()
    if expr.is_Add:
        out = flint.arb(0)
        for a in expr.args:
            out += sympy_to_arb(a)
        return out
    if expr.is_Mul:
        out = flint.arb(1)
        for a in expr.args:
            out *= sympy_to_arb(a)
        return out
    if expr.is_Pow:
        base, ex = expr.args
        b = sympy_to_arb(base)
        if ex.is_Integer:
            return b ** int(ex)
        if ex.is_Rational:
            p, q = int(ex.p), int(ex.q)
            r = b.sqrt() if q == 2 else b.root(q)
            return r ** p
    raise InputError(f"cannot enclose {expr} with certainty",
                     hint="use rationals, sqrt(...) or pi")


def mp_det(rows):
    """Determinant of a small square matrix (list of rows) in mpmath at the working
    precision, by LU with partial pivoting; 0 only when a pivot is exactly 0.

    ``mpmath.det`` returns 0 as soon as a pivot falls below ``eps`` times the matrix
    norm, which on a badly scaled but regular matrix (a Cayley-Menger matrix with
    squared distances 1e40 and 1; its determinant 8e40 is computed right in float64) is
    a wrong answer, and near a singularity a tiny determinant replaced by an exact 0.
    """
    import mpmath
    a = [[mpmath.mpf(v) for v in row] for row in rows]
    n = len(a)
    det = mpmath.mpf(1)
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(a[i][k]))
        if a[p][k] == 0:
            return mpmath.mpf(0)
        if p != k:
            a[k], a[p] = a[p], a[k]
            det = -det
        det *= a[k][k]
        for i in range(k + 1, n):
            f = a[i][k] / a[k][k]
            for j in range(k + 1, n):
                a[i][j] -= f * a[k][j]
    return det


def to_tier(x, method: str, dps: int | None = None):
    """Convert an exact or plain value to the number type of a tier.

    ``fast`` -> float; ``precise`` -> ``mpmath.mpf`` (at the current mp.dps);
    ``certified`` -> ``flint.fmpq`` when rational, else ``flint.arb``.
    """
    value = x.value if isinstance(x, Exact) else x
    if method == "fast":
        return float(x) if isinstance(x, Exact) else float(value)   # Exact: range-checked
    if method == "precise":
        import mpmath
        if isinstance(value, mpmath.mpf):
            return +value  # rounded to the working precision
        if isinstance(value, Fraction):
            return mpmath.mpf(value.numerator) / value.denominator
        if isinstance(value, (int, float)):
            return mpmath.mpf(value)
        if type(value).__name__ == "fmpq":
            return mpmath.mpf(int(value.p)) / int(value.q)
        if type(value).__name__ == "fmpz":
            return mpmath.mpf(int(value))
        if type(value).__name__ == "arb":
            return mpmath.mpf(value.mid().str(mpmath.mp.dps + 5, radius=False))
        return mpmath.mpf(value.evalf(mpmath.mp.dps + 5))
    if method == "certified":
        tname = type(value).__name__
        if tname == "fmpq":
            return value
        if tname == "fmpz" or (isinstance(value, int) and not isinstance(value, bool)):
            import flint
            return flint.fmpq(int(value))
        if isinstance(value, (Fraction, float)):
            return to_fmpq(value)
        if type(value).__name__ == "arb":
            return value
        if getattr(value, "is_Rational", False):
            return to_fmpq(value)
        return sympy_to_arb(value)
    raise InputError(f"expected one of {', '.join(map(repr, METHODS))}, got {method!r}",
                     field="method")


def float_mpf(v) -> tuple[float, float]:
    """An mpmath number as floats ``(value, rounding)``: the float nearest it and
    ``|value - v|`` (at the current mpmath precision): what the error estimate of a
    precise value given as a float must add to that of the value itself."""
    import mpmath
    value = float(v)
    return value, float(abs(mpmath.mpf(value) - v))


def float_ball(b) -> tuple[float, float]:
    """An arb ball as floats ``(value, radius)`` with the ball inside ``[value - radius,
    value + radius]``: ``value`` the float nearest its midpoint, ``radius`` the ball's
    radius plus that rounding, rounded up.  The ball's own radius is not a bound about
    ``value`` once it is below half an ulp of it (a 128-bit root enclosure, ±1e-30,
    printed as a float that is itself ±1e-14 off); ``(nan, inf)`` for a ball that is not
    finite.  Exact values (``fmpq``, ints, floats) give ``(nearest float, 0 or the
    rounding)`` the same way."""
    import flint
    b = b if type(b) is flint.arb else flint.arb(b)
    if not b.is_finite():
        return math.nan, math.inf
    value = float(b.mid())
    up = (b - value).abs_upper()                # exact: an arb ending at a float's value
    r = float(up)                               # ... rounded either way: one float up
    if r or not up.is_zero():
        r = math.nextafter(r, math.inf)
    return value, r
