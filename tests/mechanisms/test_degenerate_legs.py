"""Legs where J has no value, in every tier: a prismatic leg of zero length (its line,
Rojas et al. eq. (5), is 0/0) and a revolute leg fully stretched (Jq_ii = 0, a serial
singularity, Kühne et al. eqs. (1)-(2)).  The fast tier flags them (not valid, a
ConditioningWarning, never numpy's RuntimeWarning), the precise tier raises
SingularConfigurationError naming the leg, the certified tier refuses them and its hint
is true.  References: the analytic leg lengths and Plücker lines, finite differences of
the precise IK, the certified enclosure."""

from __future__ import annotations

import warnings

import mpmath
import numpy as np
import pytest

from distkin.errors import ConditioningWarning, SingularConfigurationError, UncertifiedError
from distkin.mechanisms import LegMechanism
from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier
from distkin.spatial import rotation_matrix


def _ups_table():
    """A UPS hexapod (m): base joints on a circle of 0.5, platform joints of 0.3; leg 1
    replaced by base (0.5, 0, 0), platform (0.25, 0, 0): zero length at pose ZERO_POSE."""
    B, P = [], []
    for k in range(3):
        c = np.deg2rad(120 * k)
        B += [0.5 * np.array([np.cos(c + 0.2), np.sin(c + 0.2), 0]),
              0.5 * np.array([np.cos(c + 2.0944 - 0.2), np.sin(c + 2.0944 - 0.2), 0])]
        P += [0.3 * np.array([np.cos(c + 0.9), np.sin(c + 0.9), 0]),
              0.3 * np.array([np.cos(c + 1.2), np.sin(c + 1.2), 0])]
    B[0], P[0] = np.array([0.5, 0, 0]), np.array([0.25, 0, 0])
    return np.array(B), np.array(P)


B_UPS, P_UPS = _ups_table()
ZERO_POSE = np.array([0.25, 0, 0, 0, 0, 0.0])


def _ups(route="generated"):
    return LegMechanism("zero-leg", tuple(dict(type="UPS", base=tuple(b), platform=tuple(p))
                                          for b, p in zip(B_UPS, P_UPS)),
                        (0, 0, 0.6, 0, 0, 0), route=route)


def _plucker(X):
    """The analytic rows of J (Rojas et al. eq. (5)): (n, Rp x n), n the unit leg."""
    r = rotation_matrix(X[3:]) @ P_UPS.T
    w = X[:3] + r.T - B_UPS
    with np.errstate(invalid="ignore"):                  # 0/0 on a zero-length leg
        n = w / np.linalg.norm(w, axis=1)[:, None]
    return np.concatenate([n, np.cross(r.T, n)], axis=1)


@pytest.mark.parametrize("route", ["generated", "numpy"])
def test_zero_length_leg_fast_tier_flags_it(route):
    m = _ups(route)
    q, valid = m.inverse_kinematics(ZERO_POSE)
    lengths = np.linalg.norm(ZERO_POSE[:3] + P_UPS - B_UPS, axis=1)    # analytic
    assert q[0] == 0.0 and np.allclose(q, lengths, rtol=1e-15, atol=1e-16)
    assert list(valid) == [False] + [True] * 5
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)          # no numpy warning
        with pytest.warns(ConditioningWarning, match=r"pose 0, leg 1\)"):
            J = m.jacobian(ZERO_POSE)
        with pytest.warns(ConditioningWarning, match="leg 1"):
            Jq, Jx = m.jq_jx(ZERO_POSE)
    assert not np.isfinite(J[0]).any()
    np.testing.assert_allclose(J[1:], _plucker(ZERO_POSE)[1:], atol=1e-15)
    assert np.all(Jq == -1.0) and np.isfinite(Jx[1:]).all()
    # off the degenerate pose every row is finite and no warning is given
    X = ZERO_POSE + [0, 0, 1e-3, 0, 0, 0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_allclose(m.jacobian(X), _plucker(X), atol=1e-14)
        assert m.inverse_kinematics(X)[1].all()


def test_zero_length_leg_tiers_agree():
    m = _ups()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.warns(ConditioningWarning, match="zero length"):
            res = jacobian_tier(m, ZERO_POSE, "fast")
    assert res.inaccurate[0] and np.isinf(res.J_error[0, 0]).all()
    assert not res.valid[0, 0]
    with pytest.raises(SingularConfigurationError, match=r"leg 1 \(prismatic\) of zero length"):
        m.jacobian(ZERO_POSE, method="precise")
    with pytest.raises(UncertifiedError, match="leg 1 uncertified") as exc:
        m.jacobian(ZERO_POSE, method="certified")
    assert "SingularConfigurationError" in exc.value.hint    # the hint says precise raises
    q, valid = m.inverse_kinematics(ZERO_POSE, method="precise")
    assert q[0] == 0 and not valid[0] and valid[1:].all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        ik = ik_tier(m, ZERO_POSE, "fast")
    assert np.isfinite(ik.q_error).all() and ik.q_error[0, 0] < 1e-15
    assert list(ik.valid[0]) == list(valid)


def _rus_stretched():
    """Six RUS legs (m); leg 1 (crank 0.125 + distal 0.25 = 0.375) fully stretched at the
    zero pose, its crank and distal link aligned along x."""
    legs = [dict(type="RUS", base=(0, 0, 0), platform=(0.375, 0, 0), axis=(0, 0, 1),
                 crank0=(1, 0, 0), crank90=(0, 1, 0), crank=0.125, distal=0.25,
                 branch=1)]     # out of reach at home: its branch is given, not chosen there
    for i in range(1, 6):
        th = 2 * np.pi * i / 6
        e, t = np.array([np.cos(th), np.sin(th), 0]), np.array([-np.sin(th), np.cos(th), 0])
        p = 0.1 * np.array([np.cos(th + 0.3 * (-1) ** i), np.sin(th + 0.3 * (-1) ** i), 0])
        legs.append(dict(type="RUS", base=tuple(0.2 * e), platform=tuple(p), axis=tuple(t),
                         crank0=tuple(e), crank90=tuple(np.cross(t, e)), crank=0.08,
                         distal=0.25))
    from distkin.mechanisms import GeometryWarning
    with pytest.warns(GeometryWarning, match=r"1 of 6 legs do not reach: leg 1 margin"):
        return LegMechanism("stretched", tuple(legs), (0, 0, 0.22, 0, 0, 0))


def test_stretched_leg_precise_raises_certified_hint_true():
    m = _rus_stretched()
    X = np.zeros(6)
    assert m.reach_margin(X)[0] == 0.0
    with pytest.raises(SingularConfigurationError, match=r"leg 1 at a serial singularity, "
                                                         r"Jq_ii = 0") as exc:
        m.jacobian(X, method="precise")
    assert exc.value.field == "poses"
    with pytest.raises(UncertifiedError, match="leg 1 uncertified") as unc:
        m.jacobian(X, method="certified")
    assert "unless J is unbounded" in unc.value.hint
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.warns(ConditioningWarning, match="does not close"):   # legs 2..6
            with pytest.warns(ConditioningWarning, match="leg 1"):
                J = m.jacobian(X)
    assert not np.isfinite(J[0]).all()


def test_near_stretched_leg_precise_against_finite_differences_and_certified():
    """1e-4 m inside the reach boundary the precise J of leg 1 is an estimate: it agrees
    with central differences of the precise IK (float steps of 1e-8 m and rad, O(1e-8)
    relative) and lies in the certified ball."""
    m = _rus_stretched()
    X = np.array([-1e-4, 2e-5, 1e-5, 0, 0, 0])
    assert m.reach_margin(X)[0] > 0
    J = m.jacobian(X, method="precise", dps=40)
    h = 1e-8
    fd = []
    for k in range(6):
        e = np.zeros(6)
        e[k] = h
        qp = m.inverse_kinematics(X + e, method="precise", dps=40)[0][0]
        qm = m.inverse_kinematics(X - e, method="precise", dps=40)[0][0]
        fd.append(float((qp - qm) / (mpmath.mpf(X[k] + h) - mpmath.mpf(X[k] - h))))
    row = np.array([float(v) for v in J[0]])     # at r = 0, omega = rdot (E(0) = I)
    np.testing.assert_allclose(row, fd, rtol=1e-6, atol=1e-9 * np.abs(row).max())
    cert = jacobian_tier(m, X, "certified")
    assert cert.certified[0, 0]
    for v, ball in zip(J[0], cert.values[0, 0]):
        assert ball.contains(float(v)) or abs(float(ball.mid()) - float(v)) <= float(
            ball.rad()) + 1e-25 * abs(float(v))
