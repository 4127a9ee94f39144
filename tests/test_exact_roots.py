"""Certified real roots (distkin.exact_roots) against analytic cases and sympy's exact
Sturm-sequence counts (an independent route)."""

from __future__ import annotations

from fractions import Fraction

import flint
import pytest
import sympy as sp

from distkin.exact_roots import (ball_ends, count_real_roots, real_roots, refine_roots,
                                   sign_at_root, working_precision)
from distkin.errors import InputError


def test_sqrt2_enclosed_and_certified_real():
    roots = real_roots([1, 0, -2])
    assert [r.multiplicity for r in roots] == [1, 1]
    for r, want in zip(roots, (-flint.arb(2).sqrt(), flint.arb(2).sqrt())):
        assert r.ball.overlaps(want)
        assert r.rad < 1e-14          # the width of the enclosure, not only its value
    assert roots[0].ball < roots[1].ball


def test_refinement_narrows_the_balls():
    roots = refine_roots([1, 0, -2], 1e-40)
    with working_precision(256):
        exact = flint.arb(2).sqrt()
        assert roots[1].ball.overlaps(exact)
    assert 0 < roots[1].rad < 1e-40 * 1.5


def test_multiplicities_of_an_exact_double_root():
    # (x - 1/3)^2 (x + 2)(x^2 + 1): one double, one simple real root, one complex pair
    x = sp.Symbol("x")
    p = sp.Poly(sp.expand((3 * x - 1) ** 2 * (x + 2) * (x ** 2 + 1)), x)
    roots = real_roots([Fraction(int(c)) for c in p.all_coeffs()])
    assert [(round(r.mid, 12), r.multiplicity) for r in roots] == [(-2.0, 1), (0.333333333333, 2)]


@pytest.mark.parametrize("eps_exp", [6, 12, 30, 60])
def test_near_double_root_is_separated(eps_exp):
    """(x - 1)(x - 1 - 10^-k) + tiny perturbation: two distinct real roots however close."""
    eps = Fraction(1, 10 ** eps_exp)
    coeffs = [1, -(2 + eps), 1 + eps]
    roots = real_roots(coeffs)
    assert len(roots) == 2
    with working_precision(400):
        second = flint.arb(flint.fmpq(1) + flint.fmpq(eps.numerator, eps.denominator))
        assert roots[0].ball.contains(1) and roots[1].ball.overlaps(second)
    assert roots[0].ball < roots[1].ball
    # and a complex pair just as close is counted as no real root
    roots_c = real_roots([1, -2, 1 + eps])
    assert roots_c == []


def test_counts_agree_with_sympy_sturm():
    rng_polys = [
        [3, -7, 0, 5, -1, 2, -8, 1, 1],
        [1, 0, -10, 0, 9],
        [2, -3, Fraction(1, 7), 11, -4],
        [1, -6, 15, -20, 15, -6, 1],          # (x - 1)^6: one root of multiplicity 6
    ]
    x = sp.Symbol("x")
    for c in rng_polys:
        p = sp.Poly([sp.Rational(str(v)) for v in c], x)
        distinct = len(sp.real_roots(p, multiple=False)) if p.degree() < 7 else len(
            set(sp.real_roots(p)))
        assert len(real_roots(c)) == distinct
        assert count_real_roots(c, -1, 1) == sp.Poly(p, x).sqf_part().count_roots(-1, 1)


def test_count_in_a_closed_interval_with_a_root_on_the_end():
    assert count_real_roots([1, -3, 2], 1, 2) == 2       # roots 1, 2 on the ends
    assert count_real_roots([1, -3, 2], Fraction(3, 2), 2) == 1
    assert count_real_roots([1, -3, 2], Fraction(3, 2), Fraction(19, 10)) == 0


@pytest.mark.parametrize("eps_exp", [20, 30, 60, 200])
def test_count_decides_roots_closer_to_an_end_than_its_float_rounding(eps_exp):
    """A root 10^-k from a rational end point: its ball is far narrower than the end
    point's rounding to 53 bits, which made the root count as inside whichever side it
    was on (QA).  Reference: sympy's exact count (Sturm) on the same interval."""
    x = sp.Symbol("x")
    third, eps = Fraction(1, 3), Fraction(1, 10 ** eps_exp)
    for a in (third - eps, third + eps):
        lin = [a.denominator, -a.numerator]                    # the root a only
        quad = sp.Poly((x - sp.Rational(a.numerator, a.denominator)) * (x - 5), x)
        for lo, hi in ((third, 1), (0, third), (third, 10)):
            ref = sp.Poly(lin, x).count_roots(sp.Rational(lo), sp.Rational(hi))
            assert count_real_roots(lin, lo, hi) == ref, (a > third, lo, hi)
            ref2 = quad.count_roots(sp.Rational(lo), sp.Rational(hi))
            coeffs = [sp.Rational(c) for c in quad.all_coeffs()]
            assert count_real_roots(coeffs, lo, hi) == ref2, (a > third, lo, hi)


def test_count_refuses_bad_end_points():
    with pytest.raises(InputError, match=r"lo <= hi, got lo = 2 and hi = 1"):
        count_real_roots([1, 0, -2], 2, 1)
    for bad in (float("nan"), float("inf"), True, "x"):
        with pytest.raises(InputError, match="end point"):
            count_real_roots([1, 0, -2], bad, 2)
    assert count_real_roots([1, 0, -2], -1.5, 1.5) == 2          # floats: exact binary values


def test_sign_at_root_decides_zero_exactly():
    r = real_roots([1, 0, -2])[1]                 # sqrt(2)
    assert sign_at_root([1, 0, -2], [1, 0, -2], r) == 0
    assert sign_at_root([1, 0, -2], [1, 0, 0, -2, 0], r) == 1      # x^4 - 2x: 4 - 2 sqrt2 > 0
    assert sign_at_root([1, 0, -2], [-1, 0, 2], r) == 0
    assert sign_at_root([1, 0, -2], [1, -1], r) == 1
    # a value equal to zero only to 40 digits is still decided (nonzero)
    q = Fraction(14142135623730950488016887242096980785697, 10 ** 40)
    assert sign_at_root([1, 0, -2], [1, -q], r) == -1


def test_bad_input():
    with pytest.raises(InputError, match="rational"):
        real_roots([1.5, float("nan")] + [sp.sqrt(2)])
    with pytest.raises(InputError, match="zero polynomial"):
        real_roots([0, 0])


# QA T 6: numpy integers and numeric strings are exact, as everywhere in distkin; a float
# (coefficient or end point alike) is its exact binary value, and the roots say so.
def test_numpy_integers_and_strings_are_exact_coefficients():
    import numpy as np
    ref = [r.ball for r in real_roots([1, 0, -2])]
    for coeffs in (np.array([1, 0, -2]), ["1", "0", "-2"], [np.int32(1), 0, "-4/2"]):
        got = real_roots(coeffs)
        assert [r.from_float for r in got] == [(), ()]
        assert all(ball_ends(a) == ball_ends(b) for a, b in zip((r.ball for r in got), ref))
    assert count_real_roots(np.array([1, 0, -2]), np.int64(0), "3/2") == 1
    assert len(refine_roots(["1", "0", "-2"], 1e-30)) == 2
    with pytest.raises(InputError, match=r"coefficients\[1\].*rational.*sqrt\(2\)"):
        real_roots(["1", "sqrt(2)"])


def test_float_coefficients_are_their_exact_binary_values_and_flagged():
    from fractions import Fraction
    [root] = real_roots([1.0, -0.1])
    assert root.from_float == (0, 1)
    tenth = Fraction(0.1)                                    # 3602879701896397 / 2**55
    lo, hi = (Fraction(int(x.p), int(x.q)) for x in ball_ends(root.ball))
    assert lo <= tenth <= hi and not lo <= Fraction(1, 10) <= hi
    assert refine_roots([1.0, 0, -2], 1e-20)[0].from_float == (0,)      # -2 is an int
    [exact] = real_roots(["1", "-0.1"])                      # the string is 1/10
    lo, hi = (Fraction(int(x.p), int(x.q)) for x in ball_ends(exact.ball))
    assert lo <= Fraction(1, 10) <= hi and exact.from_float == ()
    for bad in (float("nan"), float("inf"), True):
        with pytest.raises(InputError, match=r"coefficients\[1\]"):
            real_roots([1, bad])


@pytest.mark.parametrize("coeffs, exact", [
    ([3, -1], Fraction(1, 3)),                                  # an ordinary root
    ([1, -Fraction(1, 3 * 10 ** 400)], Fraction(1, 3 * 10 ** 400)),   # below float64's range
    ([3, -10 ** 400], Fraction(10 ** 400, 3)),                   # above float64's range
])
def test_refined_relative_radius_holds_beyond_float_range(coeffs, exact):
    """The relative radius promised by refine_roots, checked exactly against the known
    rational root (QA: the test ran in float64, where the radius of a root below 1e-308
    underflowed to 0 and the midpoint of one above 1e308 overflowed to inf: both passed
    rel_tol = 1e-60 at 64 bits with relative radii of about 1e-38)."""
    (root,) = refine_roots(coeffs, 1e-60)
    lower, upper = ball_ends(root.ball)
    q = flint.fmpq(exact.numerator, exact.denominator)
    assert lower <= q <= upper
    assert (upper - lower) / 2 <= flint.fmpq(Fraction(1e-60).numerator,
                                             Fraction(1e-60).denominator) * q


@pytest.mark.parametrize("call, field", [
    (lambda: refine_roots([1, 0, -2], 0), "rel_tol"),        # was: answered, as if exact
    (lambda: refine_roots([1, 0, -2], -1e-9), "rel_tol"),
    (lambda: refine_roots([1, 0, -2], float("nan")), "rel_tol"),
    (lambda: real_roots([1, 0, -2], bits=0), "bits"),           # was: FLINT's ValueError
    (lambda: real_roots([1, 0, -2], bits=2.5), "bits"),         # was: kept as RealRoot.bits
    (lambda: count_real_roots([1, 0, -2], 0, 2, max_bits=1), "max_bits"),
    (lambda: refine_roots([1, 0, -2], 1e-9, max_bits=True), "max_bits"),
])
def test_precision_and_tolerance_arguments_refused_by_name(call, field):
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == field
