r"""Exact checks of the octahedral input (:mod:`.problem`): squared lengths computed
exactly, a triangle refused only when collinear (the exact tiers), the sign of a parsed
value, and which inputs make a squared length irrational (what the certified tier needs
rational: the coefficients of Rojas, Borràs and Thomas, *The Octahedral Manipulator
Revisited*, ICRA 2012, eq. (3), are the squared sides and legs).
"""

from __future__ import annotations

from fractions import Fraction

from ..errors import DegenerateGeometryError, InputError
from ..exact import Exact
from .banana import SIDE_PAIRS
from .scaling import MIN_EXP

__all__ = ["square_distance", "square", "check_triangle_exact", "positive", "tiny_leg",
           "irrational_inputs"]


def square_distance(a, b):
    """The squared distance of the points ``a``, ``b`` (:class:`~distkin.exact.Exact`
    coordinates), exactly: a Fraction when rational, else a sympy expression."""
    vals = [x.value - y.value for x, y in zip(a, b)]
    if all(isinstance(v, Fraction) for v in vals):
        return sum(v * v for v in vals)
    import sympy
    from ..exact import to_sympy
    # exact simplification only: nsimplify would snap a small irrational part to the
    # nearest "simple" number (2 + sqrt(3)/10^20 -> 2) and certify a neighbouring problem
    e = sympy.radsimp(sympy.expand(sum(to_sympy(v) ** 2 for v in vals)))
    if e.is_Rational:
        return Fraction(int(e.p), int(e.q))
    return e


def square(x: Exact):
    """``x`` squared, exactly: a Fraction when rational, else a sympy expression."""
    if isinstance(x.value, Fraction):
        return x.value * x.value
    import sympy
    from ..exact import to_sympy
    e = sympy.expand(to_sympy(x) ** 2)
    if e.is_Rational:
        return Fraction(int(e.p), int(e.q))
    return e


def check_triangle_exact(sq, names, field):
    """:func:`.problem.check_triangle` for the precise and certified tiers, which compute with
    the exact data: a triangle is refused only when it is collinear, 16 area^2 = 0
    (rational squared sides: exactly; irrational ones: within 1e-60 relative at 80
    digits, said so).  A thin but proper triangle, which float64 refuses, is solved
    there (QA N 2)."""
    if all(isinstance(v, (int, Fraction)) for v in sq):
        a, b, c = (Fraction(v) for v in sq)
        if 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c) > 0:
            return
        raise DegenerateGeometryError(
            f"expected a proper triangle {names}, got collinear or coincident points "
            "(16 area^2 = 0 exactly, from the exact squared sides)", field=field)
    import sympy as sp
    a, b, c = (sp.sympify(v) for v in sq)
    a16 = sp.N(2 * (a * b + b * c + c * a) - (a * a + b * b + c * c), 80)
    scale = sp.N((a + b + c) ** 2, 80)
    if a16 > sp.Float("1e-60", 80) * scale:
        return
    raise DegenerateGeometryError(
        f"expected a proper triangle {names}, got collinear or coincident points, or "
        f"within 1e-60 of that relative at 80 digits (16 area^2 / (sum of squared "
        f"sides)^2 = {float(a16 / scale) if scale else 0.0:.3g})", field=field)


def positive(value) -> bool:
    """The exact sign of a parsed value (Fraction or sympy number): > 0."""
    if isinstance(value, Fraction):
        return value > 0
    import sympy
    return bool(sympy.N(value, 30) > 0)


def tiny_leg(text: str, field: str) -> InputError:
    """The error of a leg that is positive but rounds to 0 in float64 (``"1e-400"``),
    the same in every tier: below the supported range of lengths (:mod:`.scaling`), not
    "not positive" (QA)."""
    return InputError(f"expected a leg length within the supported range (lengths of at "
                      f"least 2^{MIN_EXP}, about {2.0 ** MIN_EXP:.1e}, which float64 and "
                      f"the squared lengths hold), got {text}: positive, but it rounds to "
                      f"0 in float64", field=field)


def irrational_inputs(B, Q, L, sides2, legs2):
    """:attr:`.problem.Problem.irrational`: per irrational input that makes a squared
    length irrational, ``(field, text, squares)`` (``squares``: ``"|P1P2|^2"``,
    ``"l1^2"``), from the parsed points ``B``, ``Q`` and legs ``L`` and their exact
    squares."""
    pts = {1: ("base", 0, B), 2: ("base", 1, B), 3: ("base", 2, B),
           4: ("platform", 0, Q), 5: ("platform", 1, Q), 6: ("platform", 2, Q)}
    found = {}
    for (a, b), sq in zip(SIDE_PAIRS, sides2):
        if isinstance(sq, Fraction):
            continue
        for j in range(3):          # the coordinates whose squared difference is not
            ends = (pts[a], pts[b])   # rational (their sum is not: one at least is)
            if isinstance(square_distance((ends[0][2][ends[0][1]][j],),
                                          (ends[1][2][ends[1][1]][j],)), Fraction):
                continue
            for name, i, rows in ends:
                v = rows[i][j]
                if not v.is_rational:
                    found.setdefault((f"{name}[{i}][{j}]", v.text), []).append(
                        f"|P{a}P{b}|^2")
    for i, (v, sq) in enumerate(zip(L, legs2)):
        if not isinstance(sq, Fraction):
            found.setdefault((f"legs[{i}]", v.text), []).append(f"l{i + 1}^2")
    return tuple((f, t, tuple(sq)) for (f, t), sq in found.items())
