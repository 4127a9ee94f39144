"""The 6-6 forward kinematics gives the fields docs/design.md §4 promises a
forward-kinematics result: ``real_roots {count, certified, values, radii}``, ``octic
{coefficients}`` and per pose ``points {P4, P5, P6}`` (QA: ``platform66`` and the nested
``forward_kinematics`` of ``delta_transform`` had none of them).  The 6-6 solve goes
through the equivalent octahedron (Rojas et al., eq. (8)), so these are its octic, roots
and platform vertices.  References: a second route, the octahedral query on that
octahedron (the l-legs 19.8, 18, 18, 17, 14.9, 17.8 of Sec. VI), and the paper's six
real roots (Sec. VI: 269.2, 328.7, 359.5, 463.6, 497.9, 513.0)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene

GEOMETRY = """
[mechanism]
kind = "{kind}"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
"""
OFFSETS = 'offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]\n'
M_LEGS = ('["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)", '
          '"1/25*sqrt(136210)", "1/5*sqrt(8153)"]')
L_LEGS = '["19.8", "18", "18", "17", "14.9", "17.8"]'


def _result(text):
    records, texts, worst = run_scene(loads_scene(text), progress=False)
    assert worst == 0, records
    return records, texts


@pytest.fixture(scope="module")
def routes():
    octa, _ = _result(GEOMETRY.format(kind="octahedral") + '[[query]]\ntype = '
                      f'"forward_kinematics"\nlegs = {L_LEGS}\nmethod = "certified"\n')
    p66, p66_text = _result(GEOMETRY.format(kind="platform66") + OFFSETS + '[[query]]\ntype = '
                            f'"forward_kinematics"\nlegs = {M_LEGS}\nmethod = "certified"\n')
    delta, _ = _result(GEOMETRY.format(kind="octahedral") + '[[query]]\ntype = '
                       f'"delta_transform"\n{OFFSETS}m_legs = {M_LEGS}\nsolve = true\n'
                       'method = "certified"\n')
    return (octa[0]["result"], p66[0]["result"], delta[0]["result"]["forward_kinematics"],
            p66_text[0])


@pytest.mark.parametrize("which", [1, 2], ids=["platform66", "delta_transform"])
def test_the_6_6_result_has_the_octahedral_fields(routes, which):
    octa, got = routes[0], routes[which]
    # the octic: the same exact coefficients, highest degree first, as strings
    coef = got["octic"]["coefficients"]
    assert len(coef) == 9 and all(isinstance(c, str) for c in coef)
    assert coef == octa["octic"]["coefficients"]
    # the real roots: the paper's six, as the octahedral route finds them
    rr = got["real_roots"]
    assert set(rr) >= {"count", "certified", "values", "radii"}
    assert rr == octa["real_roots"] and rr["count"] == 6 and rr["certified"] is True
    assert np.allclose(rr["values"], [269.2, 328.7, 359.5, 463.6, 497.9, 513.0], atol=0.05)
    # each pose: the equivalent octahedron's P4 P5 P6, as the octahedral route places them
    assert len(got["poses"]) == len(octa["poses"]) == 12
    for pose in got["poses"]:
        twin = min(octa["poses"], key=lambda q: abs(q["s15"] - pose["s15"])
                   + np.abs(np.subtract(q["translation"], pose["translation"])).sum())
        for k in ("P4", "P5", "P6"):
            assert np.allclose(pose["points"][k], twin["points"][k], atol=1e-9)
        # the existing keys stay, and the six joints lie on the triangle's edges
        # (Fig. 6: joint 1 at delta1 = 12/5 from P4 towards P5, |P4P5| = 6)
        assert {"platform_joints", "det_J66", "max_leg_error", "rotation"} <= set(pose)
        P = {k: np.array(v) for k, v in pose["points"].items()}
        joints = np.array(pose["platform_joints"])
        on_edges = [min(np.linalg.norm(np.cross(j - P[a], P[b] - P[a])) / 6
                        for a, b in (("P4", "P5"), ("P5", "P6"), ("P6", "P4")))
                    for j in joints]
        assert max(on_edges) < 1e-9
    if "unit" in got:                       # platform66 (delta_transform: at its top)
        assert got["unit"]["points"] == octa["unit"]["points"] == "m"


def test_the_6_6_text_says_the_roots_the_json_gives(routes):
    got, text = routes[1], routes[3]
    assert "real roots of the equivalent octahedron's octic in s15 (degree 8): 6 (certified)" in text
    for v in got["real_roots"]["values"]:
        assert f"s15 = {v:.10g}" in text


def test_no_real_l_leg_gives_null_octic_fields():
    """m-legs that eq. (8) maps to a negative squared l-leg: no octahedral solve runs, so
    the octic fields are null (the keys are there).  The m-legs of
    tests/delta/test_delta_scene.py, whose l^2 (sympy's LU) has a negative entry."""
    records, _ = _result(GEOMETRY.format(kind="platform66") + OFFSETS + '[[query]]\ntype = '
                         '"forward_kinematics"\nlegs = ["1", "1", "1", "1", "1", "30"]\n'
                         'method = "certified"\n')
    res = records[0]["result"]
    assert res["count"] == 0 and res["poses"] == []
    assert res["real_roots"] is None and res["octic"] is None and res["root_status"] is None


@pytest.mark.parametrize("which", [1, 2], ids=["platform66", "delta_transform"])
def test_max_leg_error_bounds_the_printed_joints(routes, which):
    # docs/design.md §3: an accuracy statement is of the float beside it.  Reference: the
    # m-leg residual of the JSON's float64 joints at 60 digits (mpmath), against the
    # scene's exact base joints and m-legs.  The solver's own figure is of its pose
    # enclosures (certified: arb balls about R and t, ~1e-23 wide), another quantity: it
    # read ~2.5e-14 m while the joints were enclosed at the context's 53 bits.
    import mpmath
    import sympy
    got = routes[which]
    legs = [sympy.sympify(m) for m in eval(M_LEGS)]
    base = got["base_joints"]
    worst = 0.0
    with mpmath.workdps(60):
        for pose in got["poses"]:
            true = max(abs(mpmath.sqrt(sum((mpmath.mpf(str(sympy.sympify(b).evalf(70)))
                                             - mpmath.mpf(float(p))) ** 2
                                            for b, p in zip(bk, pk)))
                           - mpmath.mpf(str(m.evalf(70))))
                       for bk, pk, m in zip(base, pose["platform_joints"], legs))
            assert true <= pose["max_leg_error"] <= 1.01 * true + 1e-30
            assert pose["max_leg_error_solver"] < 1e-18 < true
            worst = max(worst, pose["max_leg_error"])
    assert got["max_leg_error"] == worst
    assert got["max_leg_error_solver"] == max(q["max_leg_error_solver"] for q in got["poses"])
