"""Accuracy of the relative Cayley-Menger conditions (Rojas et al., Sec. IV) in the fast
and precise tiers (QA V 2, 3): where both products are exactly 0 the relative value is
0/0, and the float64 one is reported undefined (NaN and a CancellationWarning), not a
ratio of rounding errors; the precise tier works at its own ``dps`` (default 30), not
at ``mpmath.mp.dps``, and states an error estimate that covers the exact value.

The reference is exact: the bordered Cayley-Menger determinants of the float points
(their exact binary values) in rational arithmetic (Fractions, computed here by
cofactor expansion, independent of distkin)."""

from __future__ import annotations

import warnings
from fractions import Fraction
from itertools import permutations

import mpmath
import numpy as np
import pytest

from distkin.errors import InputError
from distkin.geometry.cm_float import CancellationWarning
from distkin.singularity import cm_pure_condition, signed_cm_condition

S3 = np.sqrt(3)
BASE = [[0, 0, 0], [6, 6 * S3, 0], [12, 0, 0]]
PLAT = np.array([[0, 0, 0], [6, 0, 0], [3, 3 * S3, 0]])


def _points(t, z=0.0):
    pts = np.array(BASE + (PLAT + np.array(t, dtype=float)).tolist(), dtype=float)
    pts[3:, 2] += z
    return pts


def _perm_det(M):
    n = len(M)
    total = Fraction(0)
    for p in permutations(range(n)):
        sign = 1
        for i in range(n):
            for j in range(i + 1, n):
                if p[i] > p[j]:
                    sign = -sign
        term = Fraction(sign)
        for i in range(n):
            term *= M[i][p[i]]
            if term == 0:
                break
        total += term
    return total


def _D(X, rows, cols=None):
    cols = rows if cols is None else cols
    sq = lambda i, j: sum((X[i - 1][k] - X[j - 1][k]) ** 2 for k in range(3))  # noqa: E731
    M = [[Fraction(0)] + [Fraction(1)] * 4]
    M += [[Fraction(1)] + [sq(i, j) for j in cols] for i in rows]
    return _perm_det(M)


def _exact(pts):
    """(paper relative, signed relative) in exact rationals, None for 0/0."""
    X = [[Fraction(float(v)) for v in row] for row in pts]
    a = _D(X, (1, 2, 4, 5)) * _D(X, (3, 4, 5, 6)) * _D(X, (1, 2, 3, 6))
    b = _D(X, (1, 2, 3, 4)) * _D(X, (2, 4, 5, 6)) * _D(X, (1, 3, 5, 6))
    k = (_D(X, (1, 2, 4, 5), (1, 2, 3, 4)) * _D(X, (3, 4, 5, 6), (2, 4, 5, 6))
         * _D(X, (1, 2, 3, 6), (1, 3, 5, 6)))
    return (None if a + b == 0 else (a - b) / (a + b),
            None if abs(a) + abs(k) == 0 else (a + k) / (abs(a) + abs(k)))


@pytest.mark.parametrize("pts", [_points([3, 1, 0]),
                                 np.array([[0, 0, 0], [6, 0, 0], [12, 0, 0], [3, 1, 10],
                                           [9, 1, 10.5], [6, 4, 9]], dtype=float)])
def test_fast_relative_is_undefined_where_both_products_vanish(pts):
    # all points in z = 0 (QA V 2: 0.9796 and -1), and a collinear base (-0.9997)
    ex = _exact(pts)
    if pts[:, 2].any():                   # collinear base: the signed form's a vanishes
        assert ex[1] is None
    else:
        assert ex == (None, None)
    for f, ref in ((cm_pure_condition, ex[0]), (signed_cm_condition, ex[1])):
        if ref is not None:
            continue
        with pytest.warns(CancellationWarning, match="may be 0/0"):
            v = f(pts, method="fast", relative=True)
        assert np.isnan(v)


def test_fast_relative_flags_a_near_flat_exactly_singular_pose():
    # QA V 3: platform translated to (3, 1, 1e-6): exactly singular, exact value 0;
    # fast read 0.00461 silently
    pts = _points([3, 1, 0], z=1e-6)
    assert _exact(pts)[0] == 0
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        v, e = cm_pure_condition(pts, method="fast", relative=True, with_error=True)
    assert np.isnan(v) or abs(v) <= e
    assert any(issubclass(x.category, CancellationWarning) for x in w)


@pytest.mark.parametrize("dps", [None, 30, 60])
def test_precise_works_at_its_own_dps_and_its_error_covers_the_exact_value(dps):
    pts = _points([3, 1, 0], z=1e-6)
    exact = _exact(pts)
    kw = {} if dps is None else {"dps": dps}
    old = mpmath.mp.dps
    try:
        vals = []
        for ambient in (15, 50):
            mpmath.mp.dps = ambient
            vals.append(cm_pure_condition(pts, method="precise", relative=True,
                                          with_error=True, **kw))
    finally:
        mpmath.mp.dps = old
    (v, e), (v2, e2) = vals
    assert v == v2 and e == e2                     # the ambient precision is not used
    digits = dps or 30
    assert e < mpmath.mpf(10) ** (18 - digits)     # QA V 3: 0.00198 at mp.dps 15
    assert abs(v - mpmath.mpf(exact[0].numerator) / exact[0].denominator) <= e
    ks, ke = signed_cm_condition(pts, method="precise", relative=True, with_error=True, **kw)
    assert abs(ks - mpmath.mpf(exact[1].numerator) / exact[1].denominator) <= ke


def test_fast_error_estimate_covers_the_exact_value_at_a_regular_pose():
    pts = np.array([[0, 0, 0], [6, 6 * S3, 0], [12, 0, 0], [1.3, 2.1, 9.7], [7.2, 0.4, 10.6],
                    [3.9, 5.5, 11.2]])
    ex = _exact(pts)
    for f, ref in ((cm_pure_condition, ex[0]), (signed_cm_condition, ex[1])):
        v, e = f(pts, method="fast", relative=True, with_error=True)
        assert abs(Fraction(v) - ref) <= Fraction(e) and e < 1e-10


@pytest.mark.parametrize("method,dps", [("fast", 30), ("certified", 30), (None, 30),
                                        ("precise", 3), ("precise", 2000), ("precise", 30.0)])
def test_dps_is_refused_out_of_range_or_with_another_method(method, dps):
    with pytest.raises(InputError) as exc:
        cm_pure_condition(_points([3, 1, 10]), method=method, relative=True, dps=dps)
    assert exc.value.field == "dps"
