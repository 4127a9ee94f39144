"""The fast 6-6 tier's leg map (eq. (8), l^2 = A^-1 (m^2 + b), Rojas, Borràs, Thomas,
*The Octahedral Manipulator Revisited*, Sec. V) never calls a rounding error a proof
of infeasibility: where float64's sign of a squared l-leg is not proved by its error
bound, the exact map decides (QA: 6-6 fast tier infeasible from float64 rounding).

Independent references: the l-legs the m-legs are built from (exact rationals), the
certified tier's count and roots, and sympy's exact sign of l^2.
"""

import warnings

import numpy as np
import pytest
import sympy as sp

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene
from distkin.delta import delta_transform, forward_kinematics66
from distkin.errors import ConditioningWarning, InfeasibleError

R = sp.Rational
BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
GEOM = ('base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]\n'
        'platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]\n')
#: 1e-16 off the architecturally singular line delta1 + 2 delta2 = 12 (cond(A) ~ 1e16)
NEAR_SING = ["6", "3-1/10**16"] * 3
#: the l-legs of Sec. VI (12 poses)
SEC6_L_SQ = [R(99, 5) ** 2, 18 ** 2, 18 ** 2, 17 ** 2, R(149, 10) ** 2, R(89, 5) ** 2]
PAPER = ["12/5", "6/5"] * 3
#: a real pose with P4 on P1 (l1 = 1e-8): l^2 rational
EDGE_L_SQ = [R(1, 10 ** 16), R(144), R(2504723635481357, 2 ** 48) ** 2,
             R(563178773710481, 2 ** 46) ** 2, R(7000840798466487, 2 ** 49) ** 2, R(36)]


def _m_legs(offsets, l_sq):
    """m-legs (exact strings) whose exact l^2 are ``l_sq``: m^2 = A l^2 - b (eq. (8))."""
    m_sq = delta_transform((BASE, PLAT), offsets).forward(l_sq)
    assert all(x > 0 for x in m_sq)
    return [str(sp.sqrt(x)) for x in m_sq]


def _float_map(offsets, m):
    """The plain float64 map A^-1 m^2 + c of the m-legs rounded once (the old fast path)."""
    tr = delta_transform((BASE, PLAT), offsets)
    Ainv, c = tr.inverse()
    mf = np.array([float(sp.sympify(x)) for x in m])
    return np.array(Ainv.tolist(), dtype=float) @ (mf * mf) + np.array(c, dtype=float).ravel()


def _fast(offsets, m):
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        res = forward_kinematics66((BASE, PLAT), offsets, m, method="fast")
    warned = any(issubclass(w.category, ConditioningWarning) for w in said)
    return res, warned


def test_near_architectural_singularity_fast_finds_the_certified_poses():
    """cond(A) ~ 1e16: float64 maps a squared l-leg of 392.04 to a negative number (it
    raised InfeasibleError); the exact map decides, and the fast tier finds the
    certified tier's 12 poses at its roots, the l^2 those the m-legs were built from."""
    m = _m_legs(NEAR_SING, SEC6_L_SQ)
    assert np.min(_float_map(NEAR_SING, m)) <= 0        # what the old code tested
    fast, warned = _fast(NEAR_SING, m)
    np.testing.assert_allclose(fast.l_sq, [float(x) for x in SEC6_L_SQ], rtol=2.0 ** -52)
    cert = forward_kinematics66((BASE, PLAT), NEAR_SING, m, method="certified")
    assert warned == (not fast.octahedral.conditioning.trusted)
    assert len(fast.poses) == len(cert.poses) == 12
    roots = sorted(float(p.octahedral_pose.s15) for p in fast.poses)
    want = sorted(float(p.octahedral_pose.s15) for p in cert.poses)
    np.testing.assert_allclose(roots, want, rtol=1e-9)
    assert fast.max_leg_error < 1e-9 * 20
    from distkin.delta.leg_map_rounding import EXACT_MAP_RHO, map_legs_fast
    _, _, rho, exact = map_legs_fast(delta_transform((BASE, PLAT), NEAR_SING), m)
    assert exact and rho == EXACT_MAP_RHO


def test_tiny_l_leg_fast_warns_or_agrees_with_certified():
    """l1^2 = 1e-16 (P4 on P1): float64 gave l1^2 = -3.6e-15 and called it infeasible;
    now the exact l^2 are used, and the fast answer either agrees with the certified
    count (8) or warns that it cannot vouch for it (fast or warn)."""
    m = _m_legs(PAPER, EDGE_L_SQ)
    assert np.min(_float_map(PAPER, m)) <= 0
    fast, warned = _fast(PAPER, m)
    cert = forward_kinematics66((BASE, PLAT), PAPER, m, method="certified")
    assert len(cert.poses) == 8 and cert.octahedral.certified
    assert fast.l_sq[0] == 1e-16
    assert warned == (not fast.octahedral.conditioning.trusted)
    assert warned or len(fast.poses) == 8
    auto = forward_kinematics66((BASE, PLAT), PAPER, m, method="auto")
    assert len(auto.poses) == 8


def test_a_proved_negative_l_leg_is_still_infeasible_in_the_fast_tier():
    """l1^2 = -1e-16 exactly (sympy's sign): float64 cannot tell its sign, the exact map
    proves it negative, so the fast tier raises InfeasibleError (as certified does)."""
    l_sq = [-R(1, 10 ** 16)] + EDGE_L_SQ[1:]
    m = _m_legs(PAPER, l_sq)
    for method in ("fast", "certified"):
        with pytest.raises(InfeasibleError, match=r"l1\^2 = -1/10000000000000000") as err:
            forward_kinematics66((BASE, PLAT), PAPER, m, method=method)
        assert err.value.margin < 0


def test_the_ordinary_fast_path_does_no_algebra():
    """The Sec. VI example: float64's signs are proved, the exact map is not consulted."""
    m = _m_legs(PAPER, SEC6_L_SQ)
    from distkin.delta.leg_map_rounding import map_legs_fast
    tr = delta_transform((BASE, PLAT), PAPER)
    l_sq, _, rho, exact = map_legs_fast(tr, m)
    assert not exact and rho < 1e-14
    np.testing.assert_allclose(l_sq, [float(x) for x in SEC6_L_SQ], rtol=1e-14)


def _run(text):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        records, texts, worst = run_scene(loads_scene(text))
    return records, texts, worst


def _q(kind, legs, method):
    if kind == "platform66":
        return f'[[query]]\ntype = "forward_kinematics"\nlegs = {legs}\nmethod = "{method}"\n'
    return (f'[[query]]\ntype = "delta_transform"\nm_legs = {legs}\nmethod = "{method}"\n')


def _scene(offsets, queries, unit="mm"):
    return (f'[units]\nlength = "{unit}"\n[mechanism]\nkind = "platform66"\n{GEOM}'
            f'offsets = {offsets}\n'.replace("'", '"') + "".join(queries))


@pytest.mark.parametrize("kind", ["platform66", "delta_transform"])
def test_cli_fast_near_singularity_answers_as_certified(kind):
    """``distkin run`` with method fast exited 2 "infeasible" on the near-singular
    scene; now status ok with the certified tier's count, in both queries."""
    legs = str(_m_legs(NEAR_SING, SEC6_L_SQ)).replace("'", '"')
    records, texts, worst = _run(_scene(NEAR_SING, [_q(kind, legs, "fast"),
                                                    _q(kind, legs, "certified")]))
    assert worst == 0, texts
    res = [r["result"] for r in records]
    if kind == "delta_transform":
        res = [r["forward_kinematics"] for r in res]
    assert res[1]["certified"] and res[0]["count"] == res[1]["count"] == 12
    assert "infeasible" not in texts[0]


@pytest.mark.parametrize("unit", ["mm", "m"])
@pytest.mark.parametrize("kind", ["platform66", "delta_transform"])
def test_cli_no_assembly_reason_in_the_scene_unit(kind, unit):
    """A negative exact l^2 (sympy's LU solve of A l^2 = m^2 + b, l1^2 = -23181/455)
    is reported in the scene's unit, as the rest of the report, not "squared length
    units"."""
    tr = delta_transform((BASE, PLAT), PAPER)
    l1 = tr.A.LUsolve(sp.Matrix([1, 18 ** 2, 18 ** 2, 17 ** 2, 14 ** 2, 17 ** 2])
                      + sp.Matrix(tr.b))[0]
    assert l1 == R(-23181, 455)
    records, texts, worst = _run(_scene(PAPER, [_q(kind, "[1, 18, 18, 17, 14, 17]",
                                                   "fast")], unit))
    assert worst == 0
    reason = records[0]["result"]["reason"]
    assert f"l1^2 = -23181/455 (= -50.9473) {unit}^2 after" in reason
    assert "squared length units" not in reason and "squared length units" not in texts[0]


def test_cli_no_assembly_reason_unitless_keeps_the_apis_words():
    """A unitless scene has no unit to name: the API's "squared length units" stay."""
    records, _, worst = _run(_scene(PAPER, [_q("platform66", "[1, 18, 18, 17, 14, 17]",
                                              "fast")], "none"))
    assert worst == 0
    assert "l1^2 = -23181/455 (= -50.9473) squared length units after" in \
        records[0]["result"]["reason"]
