"""Δ-transform algebra against the paper's printed formulas and against coordinates.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, eqs. (7)-(9) and the
example of Sec. VI (docs/design.md §5).
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from distkin.delta import (ROWS, delta_matrices, delta_transform, derive_eq7,
                           equivalent_platform)
from distkin.errors import DegenerateGeometryError, InfeasibleError, InputError

from delta_printed import printed_det

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
# Sec. VI, the printed m-legs and l-legs
M_LEGS = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
          "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
L_LEGS = [sp.Rational(198, 10), 18, 18, 17, sp.Rational(149, 10), sp.Rational(178, 10)]
R = sp.Rational


def test_eq7_is_the_square_root_of_the_cayley_menger_determinant():
    eq = derive_eq7()
    d, delta, s13, s23, s34 = (eq.symbols[k] for k in ("d", "delta", "s13", "s23", "s34"))
    printed = delta * s23 + (d - delta) * s13 - d * s34 - d * delta * (d - delta)   # eq. (7)
    assert sp.expand(eq.relation - printed) == 0
    assert sp.expand(eq.cm + 2 * eq.relation**2) == 0


def test_eq7_against_stewarts_theorem_on_coordinates():
    # independent route: P4 on segment P1P2 in coordinates, s34 computed directly
    rng = np.random.default_rng(1)
    eq = derive_eq7()
    for _ in range(5):
        P1, P2, P3 = (sp.Matrix([R(int(v), 11) for v in rng.integers(-50, 50, 3)]) for _ in range(3))
        d = sp.sqrt(sum(x**2 for x in P2 - P1))
        t = R(int(rng.integers(1, 10)), 10)
        P4 = P1 + t * (P2 - P1)
        sq = lambda a, b: sp.expand(sum(x**2 for x in a - b))  # noqa: E731
        val = eq.s34.subs({eq.symbols["d"]: d, eq.symbols["delta"]: t * d,
                           eq.symbols["s13"]: sq(P1, P3), eq.symbols["s23"]: sq(P2, P3)})
        assert sp.simplify(val - sq(P3, P4)) == 0


def test_A_and_b_equal_printed_eq9_for_symbolic_offsets_and_sides():
    sides = sp.symbols("d12 d45 d23 d56 d13 d46", positive=True)
    offs = sp.symbols("delta1:7")
    A, b = delta_matrices(sides, offs)
    for i, (d, de) in enumerate(zip(sides, offs)):
        for j in range(6):
            want = (d - de) / d if j == i else (de / d if j == (i + 1) % 6 else 0)
            assert sp.simplify(A[i, j] - want) == 0
        assert sp.expand(b[i] - de * (d - de)) == 0


def test_affine_map_matches_coordinates_of_the_built_platform():
    # second route: the 6-6 joints moved by a pose, legs measured directly, against A l^2 - b
    plat = equivalent_platform(GD, ["12/5", "6/5"] * 3)
    rng = np.random.default_rng(3)
    from distkin.singularity import rotation_from_vector
    base = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]])
    pl = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
    bj, qj = plat.joints("fast")
    A = np.array(plat.transform.A.tolist(), dtype=float)
    b = np.array(plat.transform.b.tolist(), dtype=float).ravel()
    for _ in range(20):
        Rm = rotation_from_vector(rng.normal(size=3))
        t = rng.normal(size=3) * 5 + [6, 3, 10]
        P = pl @ Rm.T + t
        l2 = np.array([np.sum((P[p - 4] - base[q - 1]) ** 2) for q, p in
                       ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))])
        m2 = np.sum((qj @ Rm.T + t - bj) ** 2, axis=1)
        np.testing.assert_allclose(m2, A @ l2 - b, rtol=1e-12, atol=1e-10)


def test_printed_m_legs_map_exactly_onto_the_l_legs():
    tr = delta_transform(GD, ["12/5", "6/5"] * 3)
    l_sq, l = tr.map_legs(M_LEGS)
    assert list(l) == [sp.nsimplify(x) for x in L_LEGS]
    assert all(x.is_Rational for x in l)
    # and back: m^2 = A l^2 - b (eq. (8), the minus sign)
    m_sq = tr.forward(l_sq)
    assert list(m_sq) == [sp.expand(sp.sympify(m) ** 2) for m in M_LEGS]
    A, b = tr.A, tr.b
    assert A * sp.Matrix(l_sq) + b != sp.Matrix(m_sq)       # eq. (4)'s "+ b" would not hold


def test_det_equals_printed_polynomial_exactly():
    fam = delta_transform(GD, ["Delta1", "Delta2"] * 3)
    D1, D2 = fam.free_symbols
    assert sp.expand(fam.det - printed_det(D1, D2)) == 0


def test_det_factors_and_singular_locus():
    fam = delta_transform(GD, ["Delta1", "Delta2"] * 3)
    D1, D2 = fam.free_symbols
    const, factors = fam.det_factors()
    assert sp.expand(const * sp.prod([f**k for f, k in factors]) - fam.det) == 0
    linear = [f for f, _ in factors if sp.Poly(f, D1, D2).total_degree() == 1]
    assert len(linear) == 1 and sp.expand(linear[0] - (D1 + 2 * D2 - 12)) == 0
    # numerically along the line: det A = 0 and A rank-deficient (rank 5; 3 at the ends)
    for t in np.linspace(0.5, 11.5, 7):
        sub = {D1: sp.nsimplify(t), D2: (12 - sp.nsimplify(t)) / 2}
        An = np.array(fam.A.subs(sub).tolist(), dtype=float)
        assert abs(np.linalg.det(An)) < 1e-15
        sv = np.linalg.svd(An, compute_uv=False)
        assert sv[-1] < 1e-14 * sv[0] and sv[-2] > 1e-3
    # off the line the quadratic factor does not vanish on a real grid
    quad = [f for f, _ in factors if sp.Poly(f, D1, D2).total_degree() > 1][0]
    g = sp.lambdify((D1, D2), quad, "numpy")
    X, Y = np.meshgrid(np.linspace(-5, 20, 101), np.linspace(-5, 12, 101))
    Z = g(X, Y)
    near_end = np.minimum(np.hypot(X - 0, Y - 6), np.hypot(X - 12, Y - 0)) < 1.0
    assert np.all(Z[~near_end] > 0)


def test_paper_line_delta1_plus_delta2_is_not_singular_for_this_example():
    fam = delta_transform(GD, ["Delta1", "Delta2"] * 3)
    D1, D2 = fam.free_symbols
    vals = [fam.det.subs({D1: x, D2: 12 - x}) for x in (R(3), R(6), R(9))]
    assert all(v != 0 for v in vals)
    # at (6, 6) on that line: the printed polynomial of Sec. VI gives -1/8
    assert fam.det.subs({D1: 6, D2: 6}) == printed_det(R(6), R(6)) == R(-1, 8)


def test_singular_offsets_raise_naming_the_factor():
    # the midpoints: the architecturally singular Griffis-Duffy platform
    with pytest.raises(DegenerateGeometryError, match=r"delta1 \+ 2\*delta2 - 12"):
        delta_transform(GD, [6, 3] * 3).check_regular()
    with pytest.raises(DegenerateGeometryError, match="det"):
        delta_transform(GD, ["4", "4"] * 3).inverse()
    # six different rows: the factor is the whole numerator of det A
    offs = [3, 2, "9/2", 4, 6, sp.nsimplify(0)]
    tr0 = delta_transform(GD, [3, 2, "9/2", 4, 6, 1])
    assert tr0.det != 0 and tr0.vanishing_factors() == []
    t = [Fraction(3, 12), Fraction(2, 6), Fraction(9, 24), Fraction(4, 6), Fraction(6, 12)]
    prod1 = np.prod([1 - x for x in t])
    prod2 = np.prod(t)
    # choose delta6/d46 = x with (1-x) prod1 = x prod2
    x = prod1 / (prod1 + prod2)
    offs[5] = str(x * 6)
    tr = delta_transform(GD, offs)
    assert tr.det == 0
    with pytest.raises(DegenerateGeometryError) as err:
        tr.check_regular()
    assert "delta6" in str(err.value) and "delta1" in str(err.value)


def test_negative_mapped_squares_are_infeasible():
    tr = delta_transform(GD, ["12/5", "6/5"] * 3)
    with pytest.raises(InfeasibleError) as err:
        tr.map_legs([1, 1, 1, 1, 1, 30])
    assert err.value.margin < 0


def test_bad_input():
    with pytest.raises(InputError, match="6 offsets"):
        delta_transform(GD, [1, 2, 3])
    with pytest.raises(InputError):
        delta_transform(GD, ["1/0"] * 6)
    tr = delta_transform(GD, ["12/5", "6/5"] * 3)
    with pytest.raises(InputError, match="positive"):
        tr.map_legs([0, 1, 1, 1, 1, 1])
    with pytest.raises(DegenerateGeometryError, match="single"):
        equivalent_platform(GD, [0, "6/5"] * 3)


def test_built_platform_joints_lie_on_the_edges():
    plat = equivalent_platform(GD, ["12/5", "6/5"] * 3)
    pts = {1: (0, 0, 0), 2: (6, 6 * sp.sqrt(3), 0), 3: (12, 0, 0),
           4: (0, 0, 0), 5: (6, 0, 0), 6: (3, 3 * sp.sqrt(3), 0)}
    for spec, bj, pj, delta in zip(ROWS, plat.base_joints, plat.platform_joints,
                                   plat.transform.offsets):
        moved = bj if spec.moved == "base" else pj
        s, e = (sp.Matrix(pts[k]) for k in spec.edge)
        M = sp.Matrix(moved)
        assert sp.simplify((M - s).norm() - delta) == 0
        assert sp.simplify((M - s).cross(e - s).norm()) == 0     # on the edge line
    # twelve distinct joints: a 6-6 platform
    assert len(set(plat.base_joints)) == 6 and len(set(plat.platform_joints)) == 6
