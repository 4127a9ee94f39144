"""cayley_menger(method=...) in the three tiers, the fast tier's cancellation warning, and
batched integer point sets (QA T 5, T 10).  References: exact Fractions of the binary
inputs (an independent determinant by fraction-free expansion), mpmath at 50 digits."""

import itertools
import warnings
from fractions import Fraction

import flint
import mpmath
import numpy as np
import pytest
from distkin.geometry import cayley_menger, squared_distances
from distkin.geometry.cm_float import CancellationWarning, FloatRangeWarning

P = np.random.default_rng(0).normal(size=(6, 3))


def _det(M):
    """Leibniz expansion in Fractions (independent of LU and of flint)."""
    n = len(M)
    total = Fraction(0)
    for perm in itertools.permutations(range(n)):
        sign = (-1) ** sum(1 for a in range(n) for b in range(a + 1, n) if perm[a] > perm[b])
        term = Fraction(sign)
        for r, c in enumerate(perm):
            term *= M[r][c]
        total += term
    return total


def _exact_cm(points, labels):
    Q = [[Fraction(float(x)) for x in points[i - 1]] for i in labels]
    s = [[sum((a - b) ** 2 for a, b in zip(p, q)) for q in Q] for p in Q]
    k = len(labels)
    return _det([[0] + [1] * k] + [[1] + s[i] for i in range(k)])


def test_certified_is_the_exact_determinant_of_the_float_data():
    S = squared_distances(P)
    labels = (5, 4, 1, 2)
    s = [[Fraction(float(S[i - 1, j - 1])) for j in labels] for i in labels]
    ref = _det([[0, 1, 1, 1, 1]] + [[1] + row for row in s])
    got = cayley_menger(S, labels, method="certified")
    assert type(got).__name__ == "fmpq" and Fraction(int(got.p), int(got.q)) == ref


def test_precise_agrees_with_the_exact_value_to_its_digits():
    S = squared_distances(P)
    ref = _exact_cm(P, (1, 2, 3, 4))
    got = cayley_menger(squared_distances([[Fraction(float(x)) for x in r] for r in P]),
                        (1, 2, 3, 4), method="precise", dps=50)
    assert isinstance(got, mpmath.mpf)
    with mpmath.workdps(60):
        assert abs(got - mpmath.mpf(ref.numerator) / ref.denominator) < 1e-45 * abs(got)
    assert abs(float(cayley_menger(S, (1, 2, 3, 4), method="fast")) - float(ref)) < 1e-13


def test_certified_ball_for_irrational_data_and_fast_of_exact_data():
    sq = {(1, 2): "sqrt(2)", (1, 3): 1, (2, 3): 1}
    ball = cayley_menger(sq, (1, 2, 3), method="certified")
    # D(1,2,3) = a^2 + b^2 + c^2 - 2ab - 2bc - 2ca with a = sqrt(2), b = c = 1: 2 - 4 sqrt(2)
    ref = 2 - 4 * flint.arb(2).sqrt()
    assert isinstance(ball, flint.arb) and ball.overlaps(ref) and float(ball.rad()) < 1e-13
    assert cayley_menger(sq, (1, 2, 3), method="fast") == pytest.approx(2 - 4 * 2 ** 0.5,
                                                                         rel=1e-15)


def test_precise_and_certified_batch_one_matrix_at_a_time():
    B = np.stack([squared_distances(P), 4 * squared_distances(P)])
    cert = cayley_menger(B, (1, 2, 3, 4), method="certified")
    assert cert.shape == (2,) and cert[1] == 64 * cert[0]          # D(4 s) = 4^3 D(s)


def test_fast_warns_where_cancellation_eats_the_digits():
    Q = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 1e-7]])
    with pytest.warns(CancellationWarning, match=r"D\(1,2,3,4\)") as rec:
        d = cayley_menger(squared_distances(Q), (1, 2, 3, 4))
    exact = float(_exact_cm(Q, (1, 2, 3, 4)))
    est = rec[0].message.estimate
    assert abs(d - exact) / exact <= est                          # the estimate covers it
    with pytest.warns(CancellationWarning, match=r"D\(1,2,3,4,5\)"):
        cayley_menger(squared_distances(P), (1, 2, 3, 4, 5))     # 0 exactly in 3-D
    # the rounded float squared distances are not exactly those of a 3-D set; exact
    # coordinates give exactly 0
    exact = squared_distances([[Fraction(float(x)) for x in r] for r in P])
    assert cayley_menger(exact, (1, 2, 3, 4, 5), method="certified") == 0


def test_fast_is_silent_on_well_shaped_simplices_and_batches():
    rng = np.random.default_rng(3)
    with warnings.catch_warnings():
        warnings.simplefilter("error", CancellationWarning)
        regular = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
        B = squared_distances(regular + 0.2 * rng.normal(size=(1000, 4, 3)))
        cayley_menger(B, (1, 2, 3, 4))
        cayley_menger(squared_distances(P), (5, 4, 1, 2), (5, 4, 1, 6))


def test_range_warning_points_to_a_method_that_exists():
    with pytest.warns(FloatRangeWarning, match="method='certified'"):
        cayley_menger(squared_distances(P * 1e100), (1, 2, 3, 4))
    big = cayley_menger(squared_distances(P * 1e100), (1, 2, 3, 4), method="certified")
    small = cayley_menger(squared_distances(P), (1, 2, 3, 4), method="certified")
    assert float(flint.arb(big) / flint.arb(small)) == pytest.approx(1e600, rel=1e-12)


def test_integer_point_sets_are_batched_exactly():
    pts = np.arange(24).reshape(2, 4, 3) ** 2 % 7
    S = squared_distances(pts)
    assert S.shape == (2, 4, 4)
    for b in range(2):
        ref = _exact_cm(pts[b], (1, 2, 3, 4))
        assert cayley_menger(S, (1, 2, 3, 4))[b] == ref
        assert S[b, 0, 1] == sum((int(x) - int(y)) ** 2 for x, y in zip(pts[b, 0], pts[b, 1]))
