"""Exact parsing of scene values and the tier conversions."""

from fractions import Fraction

import mpmath
import pytest
import sympy as sp
from flint import arb, fmpq

from distkin.errors import InputError
from distkin.exact import (check_method, float_ball, parse_exact, parse_vector, to_fmpq,
                           to_tier)


@pytest.mark.parametrize("text, expected", [
    ("19.8", Fraction(99, 5)),
    ("12/5", Fraction(12, 5)),
    ("-3e-2", Fraction(-3, 100)),
    ("1.5e3", Fraction(1500)),
    (" 7 ", Fraction(7)),
    ("(1+2)*3/4", Fraction(9, 4)),
    ("2^3/5", Fraction(8, 5)),
    ("sqrt(4)", Fraction(2)),   # rational after simplification
    (7, Fraction(7)),
])
def test_rationals_are_exact(text, expected):
    e = parse_exact(text, "legs[0]")
    assert e.is_rational and e.value == expected and not e.from_float


def test_irrational_is_a_sympy_expression():
    e = parse_exact("sqrt(108)", "base[1][1]")
    assert not e.is_rational
    assert sp.simplify(e.value - 6 * sp.sqrt(3)) == 0
    # certified tier: an arb ball containing 6 sqrt 3
    b = to_tier(e, "certified")
    assert isinstance(b, arb) and b.overlaps(6 * arb(3).sqrt()) and float(b.rad()) < 1e-13
    with mpmath.workdps(50):
        assert abs(to_tier(e, "precise") - 6 * mpmath.sqrt(3)) < mpmath.mpf(10) ** -45


def test_bare_float_is_exact_binary_and_flagged():
    e = parse_exact(0.1, "legs[2]")
    assert e.from_float and e.value == Fraction(0.1) and e.value != Fraction(1, 10)


def test_tiers():
    e = parse_exact("19.8", "x")
    assert to_tier(e, "fast") == 19.8
    assert to_tier(e, "certified") == fmpq(99, 5)
    assert to_fmpq(Fraction(3, 7)) == fmpq(3, 7)
    # values already in a tier's type pass through
    q = fmpq(2, 3)
    assert to_tier(q, "certified") is q
    with mpmath.workdps(40):
        x = mpmath.mpf(1) / 3
        assert to_tier(x, "precise") == x
        assert abs(to_tier(q, "precise") - mpmath.mpf(2) / 3) < mpmath.mpf(10) ** -39


@pytest.mark.parametrize("bad", ["19,8", "abc", "", "1/0", "sqrt(", "import os", "x+1",
                                 "__import__('os')", "nan", "inf", "[1]", "sqrt(-1)"])
def test_malformed_number_names_text_and_field(bad):
    with pytest.raises(InputError) as info:
        parse_exact(bad, "query[0].legs[3]")
    assert info.value.field == "query[0].legs[3]"
    assert repr(bad) in str(info.value) or bad == ""


@pytest.mark.parametrize("bad", [True, None, [1], float("nan"), float("inf")])
def test_wrong_types(bad):
    with pytest.raises(InputError):
        parse_exact(bad, "f")


def test_symbols_only_when_allowed():
    e = parse_exact("Delta1", "offsets[0]", allow_symbols=True)
    assert e.value == sp.Symbol("Delta1")
    with pytest.raises(InputError):
        parse_exact("Delta1", "offsets[0]")


def test_vector_length_and_element_field():
    with pytest.raises(InputError) as info:
        parse_vector(["1", "2"], "legs", length=6)
    assert "expected 6 values, got 2" in str(info.value)
    with pytest.raises(InputError) as info:
        parse_vector(["1", "oops"], "legs")
    assert info.value.field == "legs[1]"


def test_check_method():
    assert check_method("precise") == "precise"
    with pytest.raises(InputError, match="'fast', 'precise', 'certified'"):
        check_method("quick")


def _exact(a) -> Fraction:
    m, e = a.man_exp()
    return Fraction(int(m)) * Fraction(2) ** int(e)


def test_float_ball_encloses_the_ball_about_the_float():
    """A ball far narrower than an ulp (sqrt(2) at 200 bits) as floats: the float
    nearest its midpoint and a radius that covers the rounding (the ball's own radius,
    ~1e-60, does not); exact values give their rounding; a non-finite ball (nan, inf)."""
    from distkin.exact_roots import working_precision
    with working_precision(200):
        b = arb(2).sqrt()
        v, r = float_ball(b)
        lo, hi = _exact(b.lower()), _exact(b.upper())
    assert v == 2 ** 0.5 and float(b.rad()) < 1e-55
    assert 0 < r <= 2 ** -53 * 2 and Fraction(v) - Fraction(r) <= lo and hi <= Fraction(v) + Fraction(r)
    v, r = float_ball(fmpq(1, 3))
    assert v == 1 / 3 and abs(Fraction(1, 3) - Fraction(v)) <= Fraction(r) <= 2 ** -53
    assert float_ball(0.5) == (0.5, 0.0)
    v, r = float_ball(arb("nan"))
    assert v != v and r == float("inf")


def test_cbrt_is_the_real_cube_root():
    """cbrt(-8) is -2, as numpy.cbrt says (sympy.cbrt's principal root is complex and
    the value was refused as not real; QA); its float is numpy's cbrt."""
    import numpy as np
    for text, x in (("cbrt(-8)", -8.0), ("cbrt(-2)", -2.0), ("cbrt(27/8)", 27 / 8)):
        v = parse_exact(text).value
        assert float(v) == pytest.approx(float(np.cbrt(x)), rel=1e-15)
    assert parse_exact("cbrt(-8)").value == -2


def test_irrational_strings_are_parsed_once_and_failures_never_cached():
    """The sympy parse of an irrational scene string is cached (the 6-6 forward
    kinematics parsed the same m-legs on every call, ~1 ms each): a second parse gives
    the identical value without calling sympy's parser again, and an input that fails
    fails every time.  Reference: sqrt(108) = 6 sqrt(3) by hand."""
    import sympy

    from distkin.exact import _sympy_from_text
    from distkin.errors import InputError
    _sympy_from_text.cache_clear()
    a = parse_exact("sqrt(108)")
    b = parse_exact(" sqrt(108) ")
    assert a.value == b.value == 6 * sympy.sqrt(3)
    info = _sympy_from_text.cache_info()
    assert info.misses == 1 and info.hits == 1
    for _ in range(2):
        with pytest.raises(InputError, match="not a finite number"):
            parse_exact("sqrt(2)/0*pi", "legs[0]")
