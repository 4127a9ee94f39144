"""Krawczyk's test (distkin.certify.krawczyk) on systems with known zeros."""

import math

import numpy as np
from flint import arb

from distkin.certify.krawczyk import krawczyk


def _circle_line(X):
    x, y = X
    return [x * x + y * y - 4, x - y]


def _circle_line_jac(X):
    x, y = X
    return [[2 * x, 2 * y], [arb(1), arb(-1)]]


def test_circle_and_line_zero_is_enclosed_and_unique():
    """x^2 + y^2 = 4, x = y: the zero (sqrt 2, sqrt 2) lies in the proved box (checked
    against the exact value at 200 bits), and the box is tight."""
    x0 = np.array([1.4142, 1.41425])                  # a poor start: still proved
    res = krawczyk(_circle_line, _circle_line_jac, x0)
    assert res.proved, res.reason
    exact = math.sqrt(2)
    assert np.all(np.abs(exact - res.centre) <= res.radii)
    assert np.all(res.radii <= res.box) and res.contraction < 1
    assert np.all(res.radii < 1e-3)
    # a good start gives a box at the rounding level
    good = krawczyk(_circle_line, _circle_line_jac, np.array([exact, exact]))
    assert good.proved and np.all(good.radii < 1e-14)
    assert np.all(np.abs(exact - good.centre) <= good.radii)


def test_far_start_is_not_certified_around_the_wrong_point():
    """From (0.3, -0.2), far from both zeros, a proof (if any) must enclose a true zero;
    from the origin, where F' is singular, the test refuses."""
    res = krawczyk(_circle_line, _circle_line_jac, np.array([0.3, -0.2]))
    if res.proved:
        r = math.sqrt(2)
        assert any(np.all(np.abs(z - res.centre) <= res.radii)
                   for z in (np.array([r, r]), np.array([-r, -r])))
    sing = krawczyk(_circle_line, _circle_line_jac, np.array([0.0, 0.0]))
    assert not sing.proved and "singular" in sing.reason


def test_double_root_is_refused_and_close_pair_is_never_merged():
    """x^2 = 0 (a double zero: F' singular there) is refused; (x - 1)(x - 1 - d) with two
    zeros d apart is either refused or proved in a box holding exactly one of them
    (from a start between them: refused; from one of them: proved while d exceeds the
    box)."""
    sq = krawczyk(lambda X: [X[0] * X[0]], lambda X: [[2 * X[0]]], np.array([1e-9]))
    assert not sq.proved
    for d in (1e-3, 1e-8, 1e-12):
        f = lambda X, d=d: [(X[0] - 1) * (X[0] - 1 - arb(d))]     # noqa: E731
        j = lambda X, d=d: [[2 * X[0] - 2 - arb(d)]]              # noqa: E731
        proved = []
        for x0 in (1.0 + 0.3 * d, 1.0):
            res = krawczyk(f, j, np.array([x0]))
            proved.append(res.proved)
            if res.proved:
                inside = [abs(z - res.centre[0]) <= res.box[0] for z in (1.0, 1.0 + d)]
                assert sum(inside) == 1, (d, res)
                assert abs(1.0 - res.centre[0]) <= res.radii[0]
        assert proved == [False, d > 1e-11], (d, proved)
