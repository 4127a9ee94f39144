"""The precise tier at roots where both parts of eq. (3), G and R1·R2, vanish: a flat
tetrahedron of the bananas (Rojas et al., Sec. III).  QA round F: its relative residual
|G² − 4 R1 R2| / (G² + 4|R1 R2|) stays far from 0 there, so the tier dropped the pose
and said "cannot be assembled" without a warning (and so did ``auto`` on irrational
data).  The certified tier (exact octic, Sturm count) is the reference."""

import warnings
from fractions import Fraction as F

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InputError
from distkin.octahedral import forward_kinematics

FLAT_B = [[0, 0, 0], [10, 0, 0], [3, 8, 0]]
FLAT_Q = [[0, 0, 0], [3, 1, 0], [1, 4, 0]]


def _legs_of(base, pts):
    pairs = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (0, 2)]     # legs 1..6 (Fig. 4)
    sq = [sum((F(pts[j][k]) - F(base[i][k])) ** 2 for k in range(3)) for i, j in pairs]
    return [f"sqrt({s.numerator}/{s.denominator})" for s in sq]


def _nearest(res, true):
    return min((np.abs(p.points - np.asarray(true, float)).max() for p in res),
               default=np.inf)


def test_exactly_flat_pose():
    """Platform in the base plane (identity, t = (2, 1, 0)): s15 = 29 is a four-fold
    root; certified gives the one flat pose, precise now the same (and warns that it
    merged the cluster), at 30, 60 and 200 digits."""
    true = [[2, 1, 0], [5, 2, 0], [3, 5, 0]]
    legs = _legs_of(FLAT_B, true)
    cert = forward_kinematics(FLAT_B, FLAT_Q, legs, method="certified")
    assert len(cert) == 1 and _nearest(cert, true) == 0
    for dps in (30, 60, 200):
        with pytest.warns(ConditioningWarning, match="merged"):
            pre = forward_kinematics(FLAT_B, FLAT_Q, legs, method="precise", dps=dps)
        assert len(pre) == 1 and _nearest(pre, true) < 1e-9
        assert [r.status for r in pre.roots] == [r.status for r in cert.roots]


def test_nearly_flat_pose_at_60_digits():
    """The same platform 1e-8 above the base plane: four simple roots within ~1e-9
    relative, eight poses (certified).  At 60 digits precise separates them and finds
    the same eight poses, the true one among them; at 30 digits it cannot, and says
    so."""
    z = F(1, 10 ** 8)
    true = [[2, 1, z], [5, 2, z], [3, 5, z]]
    legs = _legs_of(FLAT_B, true)
    cert = forward_kinematics(FLAT_B, FLAT_Q, legs, method="certified")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        pre = forward_kinematics(FLAT_B, FLAT_Q, legs, method="precise", dps=60)
    assert len(pre) == len(cert) == 8
    assert _nearest(pre, [[float(v) for v in r] for r in true]) < 1e-12
    with pytest.warns(ConditioningWarning):
        forward_kinematics(FLAT_B, FLAT_Q, legs, method="precise", dps=30)


def test_singular_pose_with_a_flat_tetrahedron():
    """An exactly singular pose (the four planes meet in O = (1, 1, 4)) where the banana
    tetrahedron P1 P3 P5 P6 is flat: the double root 21/2 carries the pose and its
    mirror (certified); precise gives the same two poses."""
    base = [["0", "0", "0"], ["4", "0", "0"], ["0", "4", "0"]]
    plat = [["5/2", "1/2", "2"], ["1/2", "5/2", "2"], ["1/3", "3", "4/3"]]
    legs = ["sqrt(21/2)", "sqrt(13/2)", "sqrt(45/2)", "sqrt(13/2)", "sqrt(26/9)",
            "sqrt(98/9)"]
    true = [[float(F(v)) for v in r] for r in plat]
    cert = forward_kinematics(base, plat, legs, method="certified")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        pre = forward_kinematics(base, plat, legs, method="precise")
    assert len(pre) == len(cert) == 2
    assert _nearest(pre, true) < 1e-9 and _nearest(cert, true) < 1e-12
    for a, b in zip(sorted(p.points.ravel().tolist() for p in pre),
                    sorted(p.points.ravel().tolist() for p in cert)):
        assert np.allclose(a, b, atol=1e-9)


def test_too_few_digits_are_refused():
    """dps = 5 made the residual test 10^3 relative (anything passes) and merged the
    paper's distinct roots 10 % apart into 14 poses with leg errors of 1 (QA F 04)."""
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    legs = ["19.8", 18, 18, 17, "14.9", "17.8"]
    for method in ("precise", "auto"):
        with pytest.raises(InputError) as e:
            forward_kinematics(base, plat, legs, method=method, dps=5)
        assert e.value.field == "dps" and "got 5" in str(e.value)
    res = forward_kinematics(base, plat, legs, method="precise", dps=15)
    assert len(res) == 12         # Sec. VI: six real roots, twelve poses
    assert [round(r.value, 1) for r in res.roots] == [269.2, 328.7, 359.5, 463.6, 497.9,
                                                      513.0]
