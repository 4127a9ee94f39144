"""6-6 platforms given with bare floats (docs/design.md §3: a bare float is its exact
binary value), at many scales.

Independent routes:

* the m-legs → l-legs map of eq. (8) (Rojas, Borràs, Thomas, *The Octahedral
  Manipulator Revisited*, ICRA 2012, Sec. V; rows as printed in eq. (9)) written out
  here and solved by hand in :class:`fractions.Fraction`, or in mpmath at 60 digits when
  the sides are irrational;
* the six real roots of the Griffis-Duffy example printed in Sec. VI (docs/design.md §5)
  for the data in inches (QA's scene), scaled;
* the tiers against each other (fast, auto, precise, certified) and against the pose
  the m-legs were measured at.
"""

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp

from distkin.delta import delta_transform, forward_kinematics66
from distkin.errors import InputError

#: eq. (9), row by row: (side, l-leg whose end stays at the start of the edge, l-leg at
#: the end); m_i^2 = (d - delta)/d l_s^2 + delta/d l_e^2 - delta (d - delta)   (eq. (7))
ROWS = (("d12", 1, 2), ("d45", 2, 3), ("d23", 3, 4), ("d56", 4, 5), ("d13", 5, 6),
        ("d46", 6, 1))
#: the real roots s15 printed in Sec. VI for the Griffis-Duffy example (unitless)
PRINTED_ROOTS = [269.2, 328.7, 359.5, 463.6, 497.9, 513.0]
#: m-legs of the Sec. VI example (6/25*sqrt(6170), ...) as floats, QA's data
M_GD = [18.85184341118926, 17.839282496782207, 17.145261736118233, 16.426868234694037,
        14.762655587664437, 18.058792872171715]
SCALES = [1e-4, 0.01, 7.29, 1000, 1e6] + list(10 ** np.random.default_rng(7).uniform(-3, 5, 2))


def _solve(M, v):
    """Gauss-Jordan elimination in the numbers of ``M`` and ``v`` (Fraction or mpf)."""
    n = len(v)
    a = [list(row) + [x] for row, x in zip(M, v)]
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(a[i][k]))
        a[k], a[p] = a[p], a[k]
        for i in range(n):
            if i != k and a[i][k] != 0:
                f = a[i][k] / a[k][k]
                a[i] = [x - f * y for x, y in zip(a[i], a[k])]
    return [a[i][n] / a[i][i] for i in range(n)]


def _by_hand(sides, offsets, m_sq):
    """l^2 from eq. (8) written out: rows of eq. (9), solved (numbers of ``sides``)."""
    A = [[0] * 6 for _ in range(6)]
    rhs = []
    for i, ((name, s, e), delta, msq) in enumerate(zip(ROWS, offsets, m_sq)):
        d = sides[name]
        A[i][s - 1] = (d - delta) / d
        A[i][e - 1] = delta / d
        rhs.append(msq + delta * (d - delta))
    return _solve(A, rhs)


def _sides_exact(base, plat):
    pts = [[Fraction(x) for x in p] for p in list(base) + list(plat)]
    sq = lambda i, j: sum((a - b) ** 2 for a, b in zip(pts[i - 1], pts[j - 1]))  # noqa: E731
    return {f"d{i}{j}": sq(i, j) for i, j in ((1, 2), (4, 5), (2, 3), (5, 6), (1, 3), (4, 6))}


def _qa_inch(scale):
    """QA's data (the Sec. VI example in inches), every length times ``scale``."""
    k = 25.4 * scale
    base = [[0, 0, 0], [6 * k, math.sqrt(108) * k, 0], [12 * k, 0, 0]]
    plat = [[0, 0, 0], [6 * k, 0, 0], [3 * k, math.sqrt(27) * k, 0]]
    return k, (base, plat), [2.4 * k, 1.2 * k] * 3, [x * k for x in M_GD]


# ------------------------------------------------- irrational sides (QA's example)

@pytest.mark.parametrize("scale", SCALES)
def test_float_data_map_exactly_and_every_tier_finds_the_twelve_poses(scale):
    """Floats whose sides are square roots: the exact l^2 equals the map of eq. (8)
    evaluated in mpmath at 60 digits from the floats' exact binary values (nothing
    snapped to a nice rational, nothing collapsed to 0); fast, auto and precise find
    the 12 assembly modes of Sec. VI, whose roots are the printed ones times k^2."""
    k, gd, offs, m = _qa_inch(scale)
    tr = delta_transform(gd, offs)
    l_sq, _ = tr.map_legs(m)
    with mpmath.workdps(60):
        sq = _sides_exact(*gd)
        sides = {n: mpmath.sqrt(mpmath.mpf(v.numerator) / v.denominator) for n, v in sq.items()}
        mp = lambda x: mpmath.mpf(Fraction(x).numerator) / Fraction(x).denominator  # noqa: E731
        ref = _by_hand(sides, [mp(o) for o in offs], [mp(x) ** 2 for x in m])
        for mine, want in zip(l_sq, ref):
            assert abs(mpmath.mpf(sp.N(mine, 55)) / want - 1) < mpmath.mpf(10) ** -45
    l_fast = tr.map_legs_float(m)[0]
    np.testing.assert_allclose(l_fast, [float(x) for x in ref], rtol=1e-12)
    counts = {}
    for method in ("fast", "auto", "precise"):
        res = forward_kinematics66(gd, offs, m, method=method)
        counts[method] = len(res.poses)
        roots = sorted({round(float(p.octahedral_pose.s15) / k ** 2, 1) for p in res.poses})
        assert roots == PRINTED_ROOTS, method
        assert res.max_leg_error < 1e-9 * max(m)
    assert counts == {"fast": 12, "auto": 12, "precise": 12}


def test_certified_tier_refuses_irrational_mapped_legs_naming_why():
    """The certified octahedral tier needs rational squared legs; with sides that are
    square roots the mapped l^2 are not rational: an InputError naming m_legs, the
    irrational sides and the way out (never a float answer called certified)."""
    _, gd, offs, m = _qa_inch(1.0)
    with pytest.raises(InputError, match=r"rational squared l-legs.*d12, d23, d56, d46") as err:
        forward_kinematics66(gd, offs, m, method="certified")
    assert err.value.field == "m_legs" and "precise" in err.value.hint


# ------------------------------------------------- rational sides from floats

def _rational_sides_platform(scale):
    """Floats with a 30-bit mantissa near ``scale`` (so that 3u, 4u, 1.5u are exact):
    base triangle 5u, 5u, 6u and platform triangle 3u, 2.5u, 2.5u have rational sides;
    offsets and the pose are full 53-bit floats."""
    mant, e = math.frexp(scale)
    u = math.ldexp(round(mant * 2 ** 30), e - 30)
    base = [[0.0, 0.0, 0.0], [3 * u, 4 * u, 0.0], [6 * u, 0.0, 0.0]]
    plat = [[0.0, 0.0, 0.0], [3 * u, 0.0, 0.0], [1.5 * u, 2 * u, 0.0]]
    sides = [5 * u, 3 * u, 5 * u, 2.5 * u, 6 * u, 2.5 * u]          # row order of eq. (9)
    offs = [f * d for f, d in zip([0.21, 0.17, 0.23, 0.19, 0.22, 0.18], sides)]
    return u, (base, plat), offs


def _m_legs_at_pose(gd, offs, R, t):
    """The 6-6 leg lengths at the pose (R, t), computed here in float64 from the joints
    moved along the edges (Fig. 6), independently of the package."""
    base, plat = (np.array(x, dtype=float) for x in gd)
    pts = {i + 1: p for i, p in enumerate(list(base) + list(plat))}
    legs = {1: (1, 4), 2: (2, 4), 3: (2, 5), 4: (3, 5), 5: (3, 6), 6: (1, 6)}
    edges = [(1, 2), (4, 5), (2, 3), (5, 6), (3, 1), (6, 4)]
    bj, pj = {}, {}
    for row, ((s, e), delta) in enumerate(zip(edges, offs), start=1):
        new = pts[s] + delta / np.linalg.norm(pts[e] - pts[s]) * (pts[e] - pts[s])
        b, p = legs[row]
        if s <= 3:      # a base joint moves; the platform end is the shared point
            bj[row], pj[row] = new, pts[p]
        else:
            bj[row], pj[row] = pts[b], new
    return [float(np.linalg.norm(R @ pj[k] + t - bj[k])) for k in range(1, 7)]


@pytest.mark.parametrize("scale", SCALES)
def test_float_data_with_rational_sides_map_to_the_exact_binary_rationals(scale):
    """Floats with rational sides: l^2 is exactly the rational of eq. (8) solved by hand
    in Fractions from the floats' exact binary values (a snapped value differs); all
    four tiers, certified included, find the same poses, one of them the pose the
    m-legs were measured at."""
    u, gd, offs = _rational_sides_platform(scale)
    # a generic pose (a platform parallel to the base is singular for the octahedron)
    c, s, ca, sa = math.cos(0.4), math.sin(0.4), math.cos(0.25), math.sin(0.25)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]]) @ np.array([[1, 0, 0], [0, ca, -sa],
                                                                  [0, sa, ca]])
    t = np.array([3.2, 1.4, 4.1]) * u
    m = _m_legs_at_pose(gd, offs, R, t)
    tr = delta_transform(gd, offs)
    assert all(d.is_Rational for d in tr.sides)
    l_sq, _ = tr.map_legs(m)
    sides = {n: Fraction(math.isqrt(v.numerator), math.isqrt(v.denominator))
             for n, v in _sides_exact(*gd).items()}
    assert all(d * d == v for d, v in zip(sides.values(), _sides_exact(*gd).values()))
    want = _by_hand(sides, [Fraction(o) for o in offs], [Fraction(x) ** 2 for x in m])
    assert [Fraction(int(x.p), int(x.q)) for x in l_sq] == want
    # and back: A l^2 - b gives the squares of the floats' exact values
    assert [Fraction(int(x.p), int(x.q)) for x in tr.forward(l_sq)] == [Fraction(x) ** 2
                                                                        for x in m]
    found = {}
    for method in ("fast", "auto", "precise", "certified"):
        res = forward_kinematics66(gd, offs, m, method=method)
        found[method] = len(res.poses)
        Rs = [np.array([[float(x.mid()) if hasattr(x, "mid") else float(x) for x in row]
                        for row in p.rotation]) for p in res.poses]
        ts = [np.array([float(x.mid()) if hasattr(x, "mid") else float(x)
                        for x in p.translation]) for p in res.poses]
        assert min(np.abs(Ri - R).max() + np.abs(ti - t).max() / u
                   for Ri, ti in zip(Rs, ts)) < 1e-8, method
    assert len(set(found.values())) == 1 and found["fast"] >= 2, found
