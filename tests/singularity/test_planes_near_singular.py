"""The four-planes test and the signed-volume factors near a singularity (Rojas et al.,
Sec. IV; QA 24): the exact tiers' ``relative`` in their own numbers (it was a float64
computation from rounded rows: 0.0 or the wrong sign near the singular surface, in the
certified tier too), and the fast tier's rounding-error estimates with a
ConditioningWarning where float64 does not resolve the sign (a wrong sign was silent).

References: F and the volumes exactly (Fractions of the float coordinates; the
certified F is fmpq), the relative value at 80 digits (mpmath), from the formula
written out here."""

from __future__ import annotations

import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.singularity import PLANES, four_planes, volume_factors

from near_singular import bisected_sign_change, moved


def _sets(n=12, seed=24):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        P = rng.normal(size=(6, 3))
        P[:3, 2] = 0.0
        P[3:, 2] += 2.0
        d = rng.normal(size=3)
        t = bisected_sign_change(P, d)
        if t is not None:
            out.append(moved(P, d, t))
    return out


SETS = _sets()


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _exact_F(P):
    Q = [[Fraction(float(x)) for x in row] for row in P]
    rows = []
    for i, j, k in PLANES:
        a = Q[i - 1]
        n = _cross([Q[j - 1][c] - a[c] for c in range(3)], [Q[k - 1][c] - a[c] for c in range(3)])
        rows.append(n + [-sum(n[c] * a[c] for c in range(3))])
    import sympy
    return Fraction(str(sympy.Matrix(rows).det()))


def _relative_80(P):
    with mpmath.workdps(80):
        Q = [[mpmath.mpf(float(x)) for x in row] for row in P]
        L = max(mpmath.sqrt(sum((q[c] - Q[0][c]) ** 2 for c in range(3))) for q in Q[1:])
        rows = []
        for i, j, k in PLANES:
            a = Q[i - 1]
            n = _cross([Q[j - 1][c] - a[c] for c in range(3)],
                       [Q[k - 1][c] - a[c] for c in range(3)])
            nn = mpmath.sqrt(sum(x * x for x in n))
            rows.append([x / nn for x in n] + [-sum(n[c] * a[c] for c in range(3)) / nn / L])
        return mpmath.det(mpmath.matrix(rows))


@pytest.mark.parametrize("method", ["precise", "certified"])
def test_exact_tiers_relative_has_the_sign_and_digits_of_F(method):
    signs = []
    for P in SETS:
        F = _exact_F(P)
        ref = _relative_80(P)
        with warnings.catch_warnings():
            warnings.simplefilter("error", ConditioningWarning)
            got = four_planes(P, method=method).relative
        assert isinstance(got, float)
        assert np.sign(got) == np.sign(F), (got, float(F))
        assert abs(got - float(ref)) <= 1e-14 * abs(float(ref)), (got, ref)
        signs.append(np.sign(F))
    assert len(set(signs)) == 2          # both sides of the surface, near it


def test_fast_det_error_covers_and_an_unresolved_sign_warns():
    warned = 0
    for P in SETS + [P + 1e3 for P in SETS[:4]]:       # far from the origin too
        F = _exact_F(P)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConditioningWarning)
            fp = four_planes(P, method="fast")
        said = any(issubclass(w.category, ConditioningWarning) for w in caught)
        err = abs(Fraction(fp.det) - F)
        assert err <= Fraction(fp.det_error), (fp.det, float(F), fp.det_error)
        if np.sign(fp.det) != np.sign(F) or err >= abs(F):      # the sign: det J's rule
            assert said, (fp.det, float(F))
        warned += said
        if not said:         # resolved: the relative value has the same relative error
            ref = float(_relative_80(P))
            assert abs(fp.relative - ref) <= 2 * fp.det_error / abs(fp.det) * abs(ref)
    assert warned                                       # these sets are at the surface
    rng = np.random.default_rng(1)
    with warnings.catch_warnings():                     # a generic set: no warning
        warnings.simplefilter("error", ConditioningWarning)
        fp = four_planes(rng.normal(size=(6, 3)), method="fast")
    assert fp.det_error < 1e-10 * abs(fp.det)
    assert four_planes(SETS[0], method="certified").det_error is None


def _exact_vol(Q, i, j, k, m):
    a = Q[i - 1]
    d = [[Q[q - 1][c] - a[c] for c in range(3)] for q in (j, k, m)]
    n = _cross(d[1], d[2])
    return sum(d[0][c] * n[c] for c in range(3)) / 6


@pytest.mark.parametrize("tilt", [0.0, 1e-16, 1e-14, 1e-12, 1e-9, 1e-3])
def test_fast_volume_factors_of_a_nearly_flat_tetrahedron(tilt):
    rng = np.random.default_rng(0)
    flagged = 0
    for _ in range(20):
        P = rng.normal(size=(6, 3))
        P[4] = P[0] + 0.3 * (P[1] - P[0]) + 0.4 * (P[3] - P[0]) + tilt * rng.normal(size=3)
        Q = [[Fraction(float(x)) for x in row] for row in P]
        a = (_exact_vol(Q, 1, 2, 4, 5) * _exact_vol(Q, 3, 4, 5, 6)
             * _exact_vol(Q, 1, 2, 3, 6))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConditioningWarning)
            fa, fb, ea, eb = volume_factors(P, with_error=True)
        said = any(issubclass(w.category, ConditioningWarning) for w in caught)
        assert abs(Fraction(fa) - a) <= Fraction(ea)
        if np.sign(fa) != np.sign(a) or abs(Fraction(fa) - a) > Fraction(1, 10**6) * abs(a):
            assert said, (fa, float(a), ea)      # the Cayley-Menger conditions' rule
        flagged += said
    assert flagged if tilt <= 1e-14 else True
    if tilt == 1e-3:                     # resolved to ~1e-13: no warning on these
        assert flagged == 0, flagged
