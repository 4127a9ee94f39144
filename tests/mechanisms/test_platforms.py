"""The platforms of Rojas et al. as leg mechanisms (distkin.mechanisms.platforms): the
Griffis-Duffy octahedral manipulator and the Δ 6-6 platform of Sec. VI (docs/design.md
§5), checked against independent routes: the certified octic FK of distkin.octahedral
(leg lengths), the Plücker Jacobian of distkin.singularity (eq. (5)), the Δ 6-6 FK of
distkin.delta (eq. (8): its m-legs) and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from distkin.delta import equivalent_platform, forward_kinematics66
from distkin.delta.approximations import approximation
from distkin.errors import InputError
from distkin.mechanisms.platforms import platform_mechanism, symmetric_home
from distkin.octahedral import forward_kinematics as octic_fk
from distkin.singularity.conditions import plucker_jacobian
from distkin.spatial import pose_from, rotation_matrix

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
LEGS = ["19.8", "18", "18", "17", "14.9", "17.8"]
OFFSETS = ["12/5", "6/5"] * 3
M_LEGS = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
          "1/25*sqrt(136210)", "1/5*sqrt(8153)"]          # Sec. VI, printed
CM = 0.01
FLIP = np.diag([1.0, -1.0, -1.0])                          # the platform turned over


def _gd(**kw):
    return platform_mechanism((BASE, PLAT), unit=CM, height=17, name="gd_test", **kw)


def _our_pose(R, t, origin):
    """The octahedral pose (R, t: P = R p + t, platform units) as our pose (m, rad): the
    end-effector frame sits at ``origin`` and is turned over (FLIP)."""
    R = np.asarray(R, dtype=float)
    x = (np.asarray(t, dtype=float) + R @ origin) * CM
    M = np.eye(4)
    M[:3, :3], M[:3, 3] = R @ FLIP, x
    return pose_from(M)


def test_symmetric_home_has_equal_legs_and_zero_rotation():
    m = _gd(stroke=(14, 22), force=50)
    assert np.allclose(m.home, [0.06, 0.02 * math.sqrt(3), 0.17, 0, 0, 0], atol=1e-15)
    q, ok = m.inverse_kinematics(m.home)
    assert ok.all() and np.allclose(q, CM * math.sqrt(6**2 + 17**2), rtol=1e-14)
    assert m.octahedral() is not None
    assert all(leg.limit == (-50.0, 50.0) and leg.range == pytest.approx((0.14, 0.22))
               for leg in m.leg_table)
    assert symmetric_home((BASE, PLAT), 17, unit=CM) == pytest.approx(tuple(m.home))


def test_ik_reproduces_the_sec6_legs_at_the_12_certified_poses():
    """The certified octic FK (distkin.octahedral) of the Sec. VI legs gives 12 poses; our
    IK at each returns the legs, in cm -> m, to 1e-13 m."""
    m = _gd()
    origin = np.array([3.0, math.sqrt(3), 0.0])            # the platform centroid
    res = octic_fk(BASE, PLAT, LEGS, method="certified")
    assert len(res) == 12
    want = np.array([float(v) for v in LEGS]) * CM
    for p in res:
        X = _our_pose(p.rotation, p.translation, origin)
        q, _ = m.inverse_kinematics(X)
        assert np.max(np.abs(q - want)) < 1e-13


def test_delta66_ik_gives_the_printed_m_legs():
    """The Δ 6-6 platform: its FK (distkin.delta, through the octic, eq. (8)) from the
    printed m-legs, and our IK at those poses, agree to 1e-13 m."""
    plat = equivalent_platform((BASE, PLAT), OFFSETS)
    m = platform_mechanism(plat, unit=CM, height=17, name="d66_test")
    b, p = plat.joints("fast")
    origin = p.mean(axis=0)
    res = forward_kinematics66((BASE, PLAT), OFFSETS, M_LEGS, method="fast")
    want = np.array([float(__import__("sympy").sympify(s)) for s in M_LEGS]) * CM
    assert len(res.poses) == 12
    for pose in res.poses:
        X = _our_pose(pose.rotation, pose.translation, origin)
        q, _ = m.inverse_kinematics(X)
        assert np.max(np.abs(q - want)) < 1e-12


@pytest.mark.parametrize("kind", ["octahedral", "delta66", "standard", "stoughton_arai"])
def test_jacobian_is_the_plucker_jacobian_of_eq5(kind):
    """J of the generated kernels = the Plücker Jacobian of distkin.singularity with the
    end-effector origin as reference, at random poses; and = finite differences of IK."""
    plat = {"octahedral": (BASE, PLAT), "delta66": equivalent_platform((BASE, PLAT), OFFSETS),
            "standard": approximation((BASE, PLAT), "standard", 1),
            "stoughton_arai": approximation((BASE, PLAT), "stoughton_arai", 1)}[kind]
    m = platform_mechanism(plat, unit=CM, height=17, name=f"pl_{kind}", route="numpy")
    rng = np.random.default_rng(7)
    X = m.home + rng.uniform(-1, 1, (20, 6)) * [0.02, 0.02, 0.02, 0.3, 0.3, 0.3]
    J = m.jacobian(X)
    d = m.arrays()
    for x, Jx in zip(X, J):
        P = x[:3] + d["p"] @ rotation_matrix(x[3:]).T
        ref = plucker_jacobian(d["B"], P, reference=x[:3])
        assert np.max(np.abs(Jx - ref)) < 1e-13
    # finite differences of the IK along (v, omega)
    x, h = X[0], 1e-7
    q0 = m.inverse_kinematics(x)[0]
    for j in range(6):
        dx = np.zeros(6)
        dx[j] = h
        if j < 3:
            xp = x + dx
        else:
            from distkin.spatial import rotation_angles
            from scipy.spatial.transform import Rotation
            R = Rotation.from_rotvec(dx[3:]).as_matrix() @ rotation_matrix(x[3:])
            xp = np.concatenate([x[:3], rotation_angles(R)])
        fd = (m.inverse_kinematics(xp)[0] - q0) / h
        assert np.max(np.abs(fd - J[0][:, j])) < 1e-5


def test_bad_input_names_the_field():
    with pytest.raises(InputError, match="unit"):
        platform_mechanism((BASE, PLAT), unit=-1.0, height=17)
    with pytest.raises(InputError, match="home"):
        platform_mechanism((BASE, PLAT), unit=CM)
    with pytest.raises(InputError, match="leg_type"):
        platform_mechanism((BASE, PLAT), unit=CM, height=17, leg_type="RSS")
