"""Stability at the extremes (issue 8): Δ offsets approaching the architecturally
singular locus.

Rojas et al., Sec. VI: base side 12, platform side 6, offsets Δ1 = δ1 = δ3 = δ5 and
Δ2 = δ2 = δ4 = δ6.  On the (Δ1, Δ2) family det A has the linear factor
Δ1 + 2Δ2 − 12 (tests/delta/test_delta_algebra.py); on that line the equivalent 6-6
platform is architecturally singular.  The extreme: Δ2 = 6/5 (the paper's value) and
Δ1 = 48/5 − ε with ε = 10^-1 ... 10^-12, exact rationals, so that the distance to the
locus is ε; and ε = 0 exactly.

Independent route throughout: the matrix A rebuilt here from Stewart's theorem (the
squared distance from a point dividing a side of a triangle to the opposite vertex),
not from the module's Cayley-Menger derivation.
"""

import warnings

import numpy as np
import pytest
import sympy as sp

from distkin.delta import delta_transform, equivalent_platform, forward_kinematics66
from distkin.errors import ConditioningWarning, DegenerateGeometryError

from stability_helpers import GD, GD_L_LEGS

EPS = np.finfo(float).eps
EPSILONS = [sp.Rational(1, 10 ** k) for k in range(1, 13)]
D2 = sp.Rational(6, 5)
ON_LOCUS = sp.Rational(48, 5)                  # Δ1 with Δ1 + 2·Δ2 = 12
L_SQ = [sp.Rational(x) ** 2 for x in GD_L_LEGS]
#: row i of eq. (9): (l-leg at the moving end's start, l-leg at its end, side, offset)
#: (Rojas et al., Fig. 6 and eq. (9), transcribed from the paper)
_STEWART_ROWS = ((1, 2, 12, "D1"), (2, 3, 6, "D2"), (3, 4, 12, "D1"), (4, 5, 6, "D2"),
                 (5, 6, 12, "D1"), (6, 1, 6, "D2"))


def _offsets(d1):
    return [d1, D2] * 3


def _stewart(d1, d2=D2):
    """A and b by Stewart's theorem: a point at δ from P_s on a side of length d sees
    the opposite vertex at m² = (d−δ)/d·l_s² + δ/d·l_e² − δ(d−δ)."""
    A, b = sp.zeros(6, 6), sp.zeros(6, 1)
    for i, (s, e, d, name) in enumerate(_STEWART_ROWS):
        delta = d1 if name == "D1" else d2
        A[i, s - 1] = (d - delta) / sp.Integer(d)
        A[i, e - 1] = delta / sp.Integer(d)
        b[i] = delta * (d - delta)
    return A, b


def test_det_A_vanishes_linearly_with_the_jacobi_slope():
    """Extreme: distance ε = 1e-1 ... 1e-12 to the locus (exact arithmetic).

    Expected: det A (the module's, exact) equals det of Stewart's A exactly, and
    det A / ε tends to c = −∂det A/∂Δ1 at the locus, computed by Jacobi's formula
    tr(adj(A₀) ∂A/∂Δ1) on Stewart's singular A₀: |det A/(cε) − 1| <= ε (the
    remainder is O(ε) because det A is a polynomial in Δ1).
    """
    D1 = sp.Symbol("D1")
    A0, _ = _stewart(ON_LOCUS)
    assert A0.det() == 0
    dA = _stewart(D1)[0].diff(D1)
    c = -(A0.adjugate() * dA).trace()
    assert c != 0
    for eps in EPSILONS:
        tr = delta_transform(GD, _offsets(ON_LOCUS - eps))
        assert tr.det == _stewart(ON_LOCUS - eps)[0].det()
        assert abs(tr.det / (c * eps) - 1) <= eps


def test_leg_map_round_trip_loses_no_more_than_cond_times_eps():
    """Extreme: ε = 1e-1 ... 1e-12, the l-legs of Sec. VI mapped to m-legs by
    Stewart's A (exact), then back by the module.

    Expected: the exact map (:meth:`DeltaTransform.map_legs`) returns the l-legs
    exactly at every ε; the float64 map (:meth:`map_legs_float`, the fast tier)
    returns them with relative error <= 10·κ(A)·eps, κ the 2-norm condition number
    of A (κ grows like 1/ε, to about 1.6e13 at ε = 1e-12), and never NaN.
    """
    l_exact = np.array([float(sp.sqrt(x)) for x in L_SQ])
    kappas = []
    for eps in EPSILONS:
        A, b = _stewart(ON_LOCUS - eps)
        m_sq = A * sp.Matrix(L_SQ) - b
        m_sym = [sp.sqrt(x) for x in m_sq]
        tr = delta_transform(GD, _offsets(ON_LOCUS - eps))
        if eps in (EPSILONS[0], EPSILONS[5], EPSILONS[-1]):     # exact: a few suffice
            l_sq, _ = tr.map_legs(m_sym)
            assert list(l_sq) == L_SQ
        _, l_fast = tr.map_legs_float([float(x) for x in m_sym])
        assert np.all(np.isfinite(l_fast))
        kappa = np.linalg.cond(np.array(A.tolist(), dtype=float))
        kappas.append(kappa)
        err = np.max(np.abs(l_fast - l_exact)) / np.max(l_exact)
        assert err <= 10 * kappa * EPS, (eps, err, kappa)
    # κ ∝ 1/ε: log-log slope −1 within 0.05 over the sweep
    slope = np.polyfit(np.log10([float(e) for e in EPSILONS]), np.log10(kappas), 1)[0]
    assert abs(slope + 1) < 0.05


@pytest.mark.parametrize("k", [2, 5, 8, 11])
def test_fk66_reproduces_its_m_legs_within_cond_eps(k):
    """Extreme: ε = 10^-k; the 6-6 platform's forward kinematics (fast tier) from the
    m-legs of the Sec. VI l-legs.

    Expected: still the twelve assembly modes of the example (six real roots, two
    mirror poses each), and every pose reproduces the m-legs on the 6-6 platform's
    own joints with max |leg error| <= max(10·κ(A)·eps, 1e-12)·max m (the fast tier's
    own accuracy is about 1e-12 relative; the map adds κ(A)·eps).
    """
    eps = sp.Rational(1, 10 ** k)
    A, b = _stewart(ON_LOCUS - eps)
    m = [float(sp.sqrt(x)) for x in A * sp.Matrix(L_SQ) - b]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = forward_kinematics66(GD, _offsets(ON_LOCUS - eps), m, method="fast")
    kappa = np.linalg.cond(np.array(A.tolist(), dtype=float))
    # fast or warn: where its proof cannot cover the map's rounding (near the locus) the
    # fast tier says so, and only there (QA J 1)
    warned = any(issubclass(w.category, ConditioningWarning) for w in said)
    assert warned == (not res.octahedral.conditioning.trusted)
    assert len(res.poses) == 12
    assert np.isfinite(res.max_leg_error)
    assert res.max_leg_error <= max(10 * kappa * EPS, 1e-12) * max(m)


def test_on_the_locus_a_clear_distkin_error():
    """Extreme: ε = 0 exactly (Δ1 + 2Δ2 = 12).

    Expected: det A == 0 exactly (also for Stewart's A); building the 6-6 platform,
    its forward kinematics (every tier's entry point) and the float leg map raise
    :class:`DegenerateGeometryError` naming the factor Δ1 + 2Δ2 − 12 — not a
    ZeroDivisionError, numpy LinAlgError or a NaN result.
    """
    offs = _offsets(ON_LOCUS)
    tr = delta_transform(GD, offs)
    assert tr.det == 0 and _stewart(ON_LOCUS)[0].det() == 0
    pattern = r"delta1 \+ 2\*delta2 - 12"
    with pytest.raises(DegenerateGeometryError, match=pattern):
        equivalent_platform(GD, offs)
    with pytest.raises(DegenerateGeometryError, match=pattern):
        tr.map_legs_float([20.0] * 6)
    for method in ("fast", "precise", "certified"):
        with pytest.raises(DegenerateGeometryError, match=pattern):
            forward_kinematics66(GD, offs, [20.0] * 6, method=method)


def test_on_the_locus_the_cli_exits_2_with_one_line(tmp_path, capsys):
    """Extreme: ε = 0 through a scene file and ``distkin run``.

    Expected: the scene is rejected when it is loaded (queries validate their fields
    at load time): exit code 2, one line on stderr naming the field and the vanishing
    factor Δ1 + 2Δ2 − 12, no traceback, nothing on stdout.
    """
    from distkin.app.cli import main
    scene = tmp_path / "locus.toml"
    scene.write_text(
        '[units]\nlength = "none"\n\n[mechanism]\nkind = "octahedral"\n'
        'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
        'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n\n'
        '[[query]]\ntype = "delta_transform"\n'
        'offsets = ["48/5", "6/5", "48/5", "6/5", "48/5", "6/5"]\n'
        'm_legs = ["20", "20", "20", "20", "20", "20"]\nmethod = "fast"\n',
        encoding="utf-8")
    code = main(["run", str(scene), "--json", str(tmp_path / "out.json")])
    err = capsys.readouterr()
    assert code == 2
    assert err.out == ""
    lines = err.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err.err
    assert "query[0].offsets" in lines[0] and "delta1 + 2*delta2 - 12" in lines[0]
