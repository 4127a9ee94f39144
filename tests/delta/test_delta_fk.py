"""Forward kinematics of the 6-6 platform equivalent to the Griffis-Duffy octahedral
example (Rojas et al., Sec. VI; docs/design.md §5).

Independent routes: the octahedral solver called directly with the *printed* l-legs
(not the mapped ones), and the 6-6 leg lengths measured on the 6-6 joints in the test.
"""

import numpy as np
import pytest
import sympy as sp

from distkin.delta import equivalent_platform, forward_kinematics66
from distkin.octahedral import forward_kinematics

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
M_LEGS = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
          "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
L_PRINTED = ["19.8", "18", "18", "17", "14.9", "17.8"]


@pytest.fixture(scope="module")
def fk66():
    return forward_kinematics66(GD, ["12/5", "6/5"] * 3, M_LEGS, method="fast")


def test_same_twelve_poses_as_the_octahedral_solver(fk66):
    octa = forward_kinematics(*GD, L_PRINTED, method="fast")
    assert len(octa.poses) == 12 and len(fk66.poses) == 12
    # the six real roots printed in Sec. VI, each with two mirror poses
    assert sorted({round(p.s15, 1) for p in octa.poses}) == [269.2, 328.7, 359.5, 463.6,
                                                             497.9, 513.0]
    for mine, ref in zip(fk66.poses, octa.poses):
        np.testing.assert_allclose(mine.rotation, ref.rotation, atol=1e-12)
        np.testing.assert_allclose(mine.translation, ref.translation, atol=1e-11)


def test_each_pose_reproduces_the_m_legs_on_the_6_6_geometry(fk66):
    plat = equivalent_platform(GD, ["12/5", "6/5"] * 3)
    bj = np.array([[float(x) for x in p] for p in plat.base_joints])
    qj = np.array([[float(x) for x in p] for p in plat.platform_joints])
    m = np.array([float(sp.sympify(x)) for x in M_LEGS])
    for pose in fk66.poses:
        lengths = np.linalg.norm(qj @ pose.rotation.T + pose.translation - bj, axis=1)
        assert np.max(np.abs(lengths - m)) < 1e-12
        assert pose.max_leg_error < 1e-12
        np.testing.assert_allclose(pose.rotation @ pose.rotation.T, np.eye(3), atol=1e-13)
    assert fk66.max_leg_error < 1e-12


def test_fast_tier_maps_legs_in_float_to_the_printed_l_legs(fk66):
    # the fast tier maps with the exact inverse rounded once; the printed l-legs of
    # Sec. VI are the reference (the exact map is tested in test_delta_algebra.py)
    printed = np.array([19.8, 18, 18, 17, 14.9, 17.8])
    np.testing.assert_allclose(fk66.l_legs, printed, rtol=1e-14)


def test_higher_tiers_map_legs_exactly():
    res = forward_kinematics66(GD, ["12/5", "6/5"] * 3, M_LEGS, method="certified")
    assert [str(x) for x in res.l_legs] == ["99/5", "18", "18", "17", "149/10", "89/5"]


@pytest.mark.parametrize("method, bound", [("precise", 1e-25), ("certified", 1e-12)])
def test_higher_tiers(method, bound):
    res = forward_kinematics66(GD, ["12/5", "6/5"] * 3, M_LEGS, method=method)
    assert len(res.poses) == 12
    # precise: mpmath residual at 30 digits; certified: a rigorous arb upper bound
    assert res.max_leg_error < bound
    ref = forward_kinematics(*GD, L_PRINTED, method="fast")
    for mine, p in zip(res.poses, ref.poses):
        R = np.vectorize(float, otypes=[float])(np.asarray(mine.rotation, dtype=object)) \
            if method == "precise" else \
            np.array([[float(x.mid()) for x in row] for row in mine.rotation])
        np.testing.assert_allclose(R, p.rotation, atol=1e-12)


def test_auto_tier_answers_fast_on_the_example_and_states_it():
    """method="auto": the Sec. VI example is well conditioned, so the octahedral solver
    keeps its fast answer (tier "fast", with the reason); the 12 poses reproduce the
    m-legs on the 6-6 joints to 1e-12, as the fast tier does."""
    res = forward_kinematics66(GD, ["12/5", "6/5"] * 3, M_LEGS, method="auto")
    assert res.octahedral.tier == "fast" and "proved its assembly roots" in res.octahedral.tier_reason
    assert [str(x) for x in res.l_legs] == ["99/5", "18", "18", "17", "149/10", "89/5"]
    assert len(res.poses) == 12 and res.max_leg_error < 1e-12


# ------------------------------------------------ QA J 1: the fast proof covers the map

@pytest.mark.parametrize("gap", ["1/1000", "1/1000000", "1/1000000000", "1/1000000000000"])
def test_fast_proof_covers_rounding_of_the_leg_map_near_singular_line(gap):
    """Offsets ``gap`` from the singular line Δ1 + 2Δ2 = 12 (det A -> 0): the float64 map
    of eq. (8) moves l^2 by cond(A)·u.  Every "proved" fast radius must hold the exact
    root of the certified tier (exact l^2, FLINT); where it cannot, the fast tier warns
    and does not claim ``trusted`` (QA J 1)."""
    import warnings

    from distkin.errors import ConditioningWarning
    from scipy.spatial.transform import Rotation
    gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    offs = [f"6+{gap}", "3"] * 3
    b, q = equivalent_platform(gd, offs).joints("fast")
    R = Rotation.from_euler("xyz", [170, 5, 80], degrees=True).as_matrix()
    m = np.linalg.norm(q @ R.T + np.array([5.0, 3.0, 12.0]) - b, axis=1).tolist()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fast = forward_kinematics66(gd, offs, m, method="fast")
    exact = sorted({float(p.octahedral_pose.s15)
                    for p in forward_kinematics66(gd, offs, m, method="certified").poses})
    cond = fast.octahedral.conditioning
    warned = any(issubclass(w.category, ConditioningWarning) for w in caught)
    assert cond.trusted != warned
    for r in fast.octahedral.roots:
        if r.status == "assembly" and r.radius_kind == "proved":
            assert min(abs(r.value - e) for e in exact) <= r.radius
    if cond.trusted:
        assert len({round(v, 6) for v in exact}) == len(
            [r for r in fast.octahedral.roots if r.status == "assembly"])


def test_fast_proof_refuses_the_qa_case_one_nanometre_from_the_line():
    """QA J 1, F1: offsets 1e-9 from the line; the float map is off by 1e-3 in s15, far
    beyond the radius the octahedral proof alone gave (4e-10)."""
    from distkin.errors import ConditioningWarning
    gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    m = ["12.362163462176191", "12.562613339076515", "12.414288910343549",
         "14.42770622465102", "14.385605990896536", "15.12961841911694"]
    with pytest.warns(ConditioningWarning, match="eq. \\(8\\)"):
        fast = forward_kinematics66(gd, ["6.000000001", "3"] * 3, m, method="fast")
    assert not fast.octahedral.conditioning.trusted
    assert all(r.radius_kind != "proved" for r in fast.octahedral.roots)
