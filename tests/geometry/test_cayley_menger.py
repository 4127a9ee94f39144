"""Cayley-Menger core against coordinates (independent route) in every number type.

References: Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, eq. (1)
(the banana identity) and the determinant notation there.
"""

from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from flint import arb, fmpq

from distkin.errors import InputError
from distkin.geometry import (cayley_menger, squared_distances, tetrahedron_volume_squared,
                              triangle_area_squared)

RNG = np.random.default_rng(20261121)


def _vol2(P):
    """Squared volume of a tetrahedron from coordinates: (det[v1 v2 v3] / 6)^2."""
    M = np.array([P[1] - P[0], P[2] - P[0], P[3] - P[0]], dtype=float)
    return (np.linalg.det(M) / 6) ** 2


def _area2(P):
    """Squared area of a triangle from coordinates: |cross| ^ 2 / 4."""
    c = np.cross(P[1] - P[0], P[2] - P[0])
    return float(c @ c) / 4


def test_unit_regular_tetrahedron_volume_exact():
    # analytic: V = 1/(6 sqrt 2) for unit edges, so V^2 = 1/72 and D = 288 V^2 = 4
    sq = {(i, j): 1 for i in range(1, 5) for j in range(i + 1, 5)}
    assert cayley_menger(sq, (1, 2, 3, 4)) == 4
    assert tetrahedron_volume_squared(sq, 1, 2, 3, 4) == Fraction(1, 72)
    V = sp.sqrt(sp.Rational(1, 72))
    assert sp.simplify(V - 1 / (6 * sp.sqrt(2))) == 0
    # unit equilateral triangle: A^2 = 3/16
    assert triangle_area_squared(sq, 1, 2, 3) == Fraction(3, 16)


def test_two_point_convention():
    # analytic: det [[0,1,1],[1,0,s],[1,s,0]] = 2 s
    assert cayley_menger({(1, 2): 5}, (1, 2)) == 10


@pytest.mark.parametrize("trial", range(20))
def test_random_tetra_and_triangles_float(trial):
    P = RNG.normal(size=(4, 3)) * 10 ** RNG.uniform(-3, 3)
    S = squared_distances(P)
    v2 = _vol2(P)
    assert tetrahedron_volume_squared(S, 1, 2, 3, 4) == pytest.approx(v2, rel=1e-9, abs=0)
    for tri in [(1, 2, 3), (2, 3, 4), (1, 3, 4)]:
        a2 = _area2(P[[t - 1 for t in tri]])
        assert triangle_area_squared(S, *tri) == pytest.approx(a2, rel=1e-9)


def _rational_points(n, rng):
    return [[Fraction(int(rng.integers(-40, 41)), int(rng.integers(1, 9))) for _ in range(3)]
            for _ in range(n)]


def _exact_vol2(P):
    a = [[P[k][c] - P[0][c] for c in range(3)] for k in (1, 2, 3)]
    det = sp.Matrix(a).det()
    return sp.Rational(det) ** 2 / 36


@pytest.mark.parametrize("trial", range(6))
def test_random_tetra_all_number_types(trial):
    rng = np.random.default_rng(trial)
    P = _rational_points(4, rng)
    exact_v2 = _exact_vol2([[sp.Rational(x.numerator, x.denominator) for x in p] for p in P])
    # Fraction (plain exact)
    v = tetrahedron_volume_squared(squared_distances(P), 1, 2, 3, 4)
    assert isinstance(v, Fraction) and sp.Rational(v.numerator, v.denominator) == exact_v2
    # fmpq
    Pq = [[fmpq(x.numerator, x.denominator) for x in p] for p in P]
    vq = tetrahedron_volume_squared(squared_distances(Pq), 1, 2, 3, 4)
    assert type(vq).__name__ == "fmpq" and sp.Rational(int(vq.p), int(vq.q)) == exact_v2
    # sympy
    Ps = [[sp.Rational(x.numerator, x.denominator) for x in p] for p in P]
    vs = tetrahedron_volume_squared(squared_distances(Ps), 1, 2, 3, 4)
    assert isinstance(vs, sp.Basic) and sp.simplify(vs - exact_v2) == 0
    # mpmath
    with mpmath.workdps(40):
        Pm = [[mpmath.mpf(x.numerator) / x.denominator for x in p] for p in P]
        vm = tetrahedron_volume_squared(squared_distances(Pm), 1, 2, 3, 4)
        assert isinstance(vm, mpmath.mpf)
        assert abs(vm - mpmath.mpf(exact_v2.p) / exact_v2.q) <= mpmath.mpf(10) ** -30 * (1 + abs(vm))
    # arb: the ball must contain the exact value, and be narrow
    Pa = [[arb(fmpq(x.numerator, x.denominator)) + arb(0, 1e-20) for x in p] for p in P]
    va = tetrahedron_volume_squared(squared_distances(Pa), 1, 2, 3, 4)
    assert type(va).__name__ == "arb"
    assert va.contains(fmpq(int(exact_v2.p), int(exact_v2.q)))
    assert float(va.rad()) < 1e-6 * (1 + abs(float(va.mid())))
    # float
    vf = tetrahedron_volume_squared(squared_distances(np.array(P, dtype=float)), 1, 2, 3, 4)
    assert vf == pytest.approx(float(exact_v2), rel=1e-9)


@pytest.mark.parametrize("trial", range(10))
def test_banana_identity_exact_rationals(trial):
    """Rojas et al., eq. (1) squared: D(5,4,1,2;5,4,1,6)^2 = D(5,4,1,2) D(5,4,1,6)."""
    rng = np.random.default_rng(100 + trial)
    P = [[sp.Rational(x.numerator, x.denominator) for x in p] for p in _rational_points(6, rng)]
    S = squared_distances(P)
    lhs = cayley_menger(S, (5, 4, 1, 2), (5, 4, 1, 6)) ** 2
    rhs = cayley_menger(S, (5, 4, 1, 2)) * cayley_menger(S, (5, 4, 1, 6))
    assert sp.expand(lhs - rhs) == 0
    assert lhs != 0  # a non-trivial instance


def test_banana_identity_symbolic_is_not_an_identity_in_4d():
    """The identity needs 3-D: in 4-D it fails, so the test above is not vacuous."""
    rng = np.random.default_rng(7)
    P = [[sp.Rational(int(rng.integers(-9, 10)), 1) for _ in range(4)] for _ in range(6)]
    S = squared_distances(P)
    lhs = cayley_menger(S, (5, 4, 1, 2), (5, 4, 1, 6)) ** 2
    rhs = cayley_menger(S, (5, 4, 1, 2)) * cayley_menger(S, (5, 4, 1, 6))
    assert lhs != rhs


@pytest.mark.parametrize("trial", range(50))
def test_banana_identity_float(trial):
    rng = np.random.default_rng(1000 + trial)
    P = rng.normal(size=(6, 3)) * 10 ** rng.uniform(-2, 2)
    S = squared_distances(P)
    lhs = cayley_menger(S, (5, 4, 1, 2), (5, 4, 1, 6)) ** 2
    rhs = cayley_menger(S, (5, 4, 1, 2)) * cayley_menger(S, (5, 4, 1, 6))
    assert lhs == pytest.approx(rhs, rel=1e-10)


def test_batched_float_matches_loop():
    P = RNG.normal(size=(50, 5, 3))
    S = squared_distances(P)
    batch = cayley_menger(S, (1, 2, 3, 4), (1, 2, 3, 5))
    loop = [cayley_menger(S[i], (1, 2, 3, 4), (1, 2, 3, 5)) for i in range(50)]
    np.testing.assert_allclose(batch, loop, rtol=1e-13)


def test_symbolic_four_points_in_plane_vanish():
    # analytic: four coplanar points span no volume, D(1,2,3,4) = 0 identically
    x = sp.symbols("x1:9")
    P = [(x[2 * i], x[2 * i + 1], 0) for i in range(4)]
    d = cayley_menger(squared_distances(P), (1, 2, 3, 4))
    assert d == 0


def test_bad_inputs():
    with pytest.raises(InputError, match="missing"):
        cayley_menger({(1, 2): 1}, (1, 2, 3))
    with pytest.raises(InputError, match="out of range"):
        cayley_menger(np.zeros((3, 3)), (1, 2, 4))
    with pytest.raises(InputError, match="as many row labels"):
        cayley_menger(np.zeros((3, 3)), (1, 2), (1, 2, 3))
    with pytest.raises(InputError, match="square"):
        cayley_menger(np.zeros((3, 2)), (1, 2))
    with pytest.raises(InputError, match="1-based"):
        cayley_menger(np.zeros((3, 3)), (0, 1))


def test_an_mpmath_matrix_is_its_rows():
    """QA 2026-11-29: a 6x6 mpmath.matrix was refused as "shape (36,)" (numpy reads it
    as one flat sequence) while the nested lists of mpf it equals were taken.  Now the
    same mpf as those lists, and within float rounding of the float64 route."""
    S = squared_distances(np.random.default_rng(0).normal(size=(6, 3)))
    rows = [[mpmath.mpf(x) for x in r] for r in S]
    for args in (((1, 2, 3, 4),), ((5, 4, 1, 2), (5, 4, 1, 6))):
        got = cayley_menger(mpmath.matrix(S.tolist()), *args)
        assert isinstance(got, mpmath.mpf) and got == cayley_menger(rows, *args)
        assert float(got) == pytest.approx(float(cayley_menger(S, *args)), rel=1e-12)
    with pytest.raises(InputError, match=r"shape \(2, 3\)"):
        cayley_menger(mpmath.matrix(2, 3), (1, 2))
