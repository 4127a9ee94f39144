"""Degenerate poses and bad input of the singularity tests (Rojas, Borràs, Thomas,
*The Octahedral Manipulator Revisited*, Sec. IV).

Independent references: the analytic flat pose (every point in z = 0, so the columns
u_z, m_x, m_y of Ĵ vanish and det Ĵ = 0; P4, P5 midpoints of P1P2, P2P3 and P6 on
P1P3, so those planes are undefined and the tetrahedra P1P2P4P5, ... flat), the exact
identity det Ĵ = -216 (a + b) from signed volumes, and the other tiers.
"""

from fractions import Fraction

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, DegenerateGeometryError, InputError, UncertifiedError
from distkin.singularity import (certified_sign, cm_pure_condition, four_planes,
                                 jacobian_det, octahedral_joints, plucker_jacobian,
                                 signed_cm_condition, volume_factors)

S3 = np.sqrt(3)
#: the platform lying in the base plane, P4, P5, P6 the midpoints of P1P2, P2P3, P1P3
FLAT = np.array([[0, 0, 0], [6, 6 * S3, 0], [12, 0, 0], [3, 3 * S3, 0], [9, 3 * S3, 0],
                 [6, 0, 0]])
#: a regular pose (det J != 0)
REG = np.array([[0, 0, 0], [6, 6 * S3, 0], [12, 0, 0], [3, 3, 10], [8, 4, 11], [6, -1, 12]])
TIERS = ("fast", "precise", "certified")


def _arb_flat():
    import flint
    r3 = flint.arb(3).sqrt()
    rows = [[0, 0, 0], [6, 6 * r3, 0], [12, 0, 0], [3, 3 * r3, 0], [9, 3 * r3, 0], [6, 0, 0]]
    return np.array([[flint.arb(v) for v in r] for r in rows], dtype=object)


def test_flat_pose_det_is_zero_in_every_tier_and_certified_exactly():
    # fast and precise: det J = 0 (three zero columns); exact rationals: -216 (a + b) = 0
    with pytest.warns(ConditioningWarning, match="within its rounding-error estimate"):
        assert float(jacobian_det(*octahedral_joints(FLAT), method="fast")) == 0.0
    assert float(jacobian_det(*octahedral_joints(FLAT), method="precise")) == 0.0
    Q = np.vectorize(lambda v: Fraction(v), otypes=[object])(FLAT)
    a, b = volume_factors(Q)
    dj = jacobian_det(*octahedral_joints(Q), normalised=False)
    assert dj == -216 * (a + b) == 0
    # arb balls (irrational sqrt(3)): the zero columns make the ball an exact 0, a
    # certified sign 0 instead of an undecided ball
    d = jacobian_det(*octahedral_joints(_arb_flat()), normalised=False, method="certified")
    assert d.is_zero() and certified_sign(d) == 0
    # a ball of non-zero radius around 0 is still undecided
    import flint
    with pytest.raises(UncertifiedError):
        certified_sign(flint.arb(0, 1e-30))


@pytest.mark.parametrize("tier", TIERS)
def test_flat_pose_relative_cm_forms_name_the_flat_tetrahedra(tier):
    for f in (cm_pure_condition, signed_cm_condition):
        with pytest.raises(DegenerateGeometryError, match="P1P2P4P5") as exc:
            f(FLAT, relative=True, method=tier)
        assert exc.value.field == "points"
    # the unscaled condition is defined and 0, as C = -110592 (a - b) det Jhat = 0 says
    assert float(cm_pure_condition(FLAT, method=tier)) == 0.0


@pytest.mark.parametrize("tier", TIERS)
def test_flat_pose_four_planes_names_the_collinear_planes(tier):
    with pytest.raises(DegenerateGeometryError) as exc:
        four_planes(FLAT, method=tier)
    msg = str(exc.value)
    for plane in ("P1P2P4", "P2P3P5", "P3P1P6"):             # P4, P5, P6 on the edges
        assert plane in msg
    assert "P4P5P6" not in msg


def test_degenerate_member_of_a_batch_is_named_and_regular_ones_match_the_identity():
    X = np.stack([REG, FLAT])
    with pytest.raises(DegenerateGeometryError, match=r"batch index \(1,\)"):
        cm_pure_condition(X, relative=True)
    with pytest.raises(DegenerateGeometryError, match=r"batch index \(1,\)"):
        four_planes(X)
    # the regular pose alone: the four-planes F equals det Jhat = -216 (a + b)
    a, b = volume_factors(REG)
    fp = four_planes(REG)
    assert fp.det == pytest.approx(-216 * (a + b), rel=1e-12)
    assert np.isfinite(fp.relative) and np.all(np.isfinite(fp.point))


@pytest.mark.parametrize("tier", TIERS)
def test_zero_length_leg_is_named_in_every_tier(tier):
    Z = REG.copy()
    Z[3] = Z[0]                                              # leg 1 = P1-P4 of length 0
    with pytest.raises(DegenerateGeometryError, match="leg 1 of length 0") as exc:
        jacobian_det(*octahedral_joints(Z), method=tier)
    assert exc.value.field == "platform_joints"
    with pytest.raises(DegenerateGeometryError, match="leg 1 "):
        plucker_jacobian(*octahedral_joints(Z), method=tier)
    # Jhat = diag(l) J is defined there: its row is 0, det Jhat = -216 (a + b) = 0
    assert float(jacobian_det(*octahedral_joints(Z), normalised=False, method=tier)) == 0.0
    a, b = volume_factors(Z)
    assert a == 0 and b == 0


def test_zero_length_leg_in_a_batch_and_an_undecided_arb_length():
    X = np.stack([REG, REG])
    X[1, 5] = X[1, 0]                                        # leg 6 = P1-P6 in pose 1
    with pytest.raises(DegenerateGeometryError, match=r"leg 6 .*batch index \(1,\)"):
        jacobian_det(*octahedral_joints(X))
    import flint
    b, p = octahedral_joints(REG)
    ba = np.vectorize(flint.arb, otypes=[object])(b)
    pa = ba.copy()
    pa[0, 0] = ba[0, 0] + flint.arb(0, 1e-20)               # leg 1: a ball around length 0
    with pytest.raises(UncertifiedError, match="leg 1"):
        jacobian_det(ba, pa, method="certified")


@pytest.mark.parametrize("tier", TIERS)
@pytest.mark.parametrize("bad", [-1, 0, -2.5, float("inf"), float("nan"), True, "x", [2]])
def test_length_scale_must_be_a_finite_positive_number(tier, bad):
    b, p = octahedral_joints(REG)
    with pytest.raises(InputError) as exc:
        jacobian_det(b, p, length_scale=bad, method=tier)
    assert exc.value.field == "length_scale"
    with pytest.raises(InputError) as exc:
        four_planes(REG, length_scale=bad, method=tier)
    assert exc.value.field == "length_scale"


def test_length_scale_divides_by_L_cubed_in_every_tier():
    b, p = octahedral_joints(REG)
    d = float(jacobian_det(b, p))
    for tier in TIERS:
        for L in (2, 0.5, Fraction(7, 3)):
            got = float(jacobian_det(b, p, length_scale=L, method=tier))
            assert got == pytest.approx(d / float(L) ** 3, rel=1e-12)
    # certified: the ball encloses the fast value (two routes)
    # certified: a narrow ball about the fast value (two routes; value and width)
    ball = jacobian_det(b, p, length_scale=Fraction(7, 3), method="certified")
    assert float(ball.mid()) == pytest.approx(d / (7 / 3) ** 3, rel=1e-12)
    assert float(ball.rad()) < 1e-9 * abs(d)


@pytest.mark.parametrize("tier", TIERS)
@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinates_are_refused_naming_the_entry(tier, value):
    X = REG.astype(float).copy()
    X[4, 0] = value                                          # P5: leg 3 (P2-P5) row 2
    b, p = octahedral_joints(X)
    with pytest.raises(InputError) as exc:
        jacobian_det(b, p, method=tier)
    assert exc.value.field == "platform_joints[2][0]"
    for f in (cm_pure_condition, four_planes, volume_factors):
        with pytest.raises(InputError) as exc:
            f(X, method=tier)
        assert exc.value.field == "points[4][0]"


def test_booleans_wrong_shapes_and_reference_are_refused():
    b, p = octahedral_joints(REG)
    with pytest.raises(InputError) as exc:
        jacobian_det(np.ones((6, 3), bool), np.zeros((6, 3), bool))
    assert exc.value.field.startswith("base_joints[")
    rows = p.tolist()
    rows[2][1] = True
    with pytest.raises(InputError) as exc:
        jacobian_det(b, rows)
    assert exc.value.field == "platform_joints[2][1]"
    with pytest.raises(InputError) as exc:
        plucker_jacobian(b, p, reference=[1, 2])
    assert exc.value.field == "reference" and "(3,)" in str(exc.value)
    with pytest.raises(InputError) as exc:
        plucker_jacobian(b, p, reference=[1, np.nan, 2])
    assert exc.value.field == "reference[1]"
    with pytest.raises(InputError) as exc:
        plucker_jacobian(b, p[:5])
    assert exc.value.field == "platform_joints"
    with pytest.raises(InputError) as exc:
        plucker_jacobian(np.stack([b] * 3), np.stack([p] * 2))
    assert exc.value.field == "platform_joints"


@pytest.mark.parametrize("tier", TIERS)
def test_reference_point_leaves_det_J_unchanged_in_every_tier(tier):
    # J(c) = J(0) [[I, 0], [-[c]x, I]]-type unimodular map: det unchanged (analytic)
    b, p = octahedral_joints(REG)
    d0 = np.linalg.det(plucker_jacobian(b, p))
    J = plucker_jacobian(b, p, reference=[1, -2, 3], method=tier)
    Jf = np.vectorize(lambda v: float(v.mid()) if hasattr(v, "mid") else float(v),
                      otypes=[float])(J)
    assert np.linalg.det(Jf) == pytest.approx(d0, rel=1e-10)
