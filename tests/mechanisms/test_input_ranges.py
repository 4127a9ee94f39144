"""QA R 1, R 3, R 8, R 10 at the library's entry points: joint values and poses that mean
nothing are refused with an InputError naming the argument, never a ZeroDivisionError,
a NaN or a page of numpy RuntimeWarnings.

Second routes: the closed-form IK (the lengths a prismatic table really has are those
it gives, all positive) and the periodicity of R = Rz Ry Rx in each angle."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InputError
from distkin.mechanisms import preset
from distkin.mechanisms.description import MAX_REACH, MAX_ROTATION
from distkin.mechanisms.forward import forward_kinematics, gauss_newton
from distkin.mechanisms.joint_values import joint_amount

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def gough():
    """The 6-UPS example of the README (prismatic legs, strokes 350-550 mm)."""
    from distkin.app.scene import load_scene
    return load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism


def test_ik_lengths_are_positive_and_round_trip(gough):
    """The second route: the IK's joint values at home are the legs' lengths |P - B|,
    positive; the FK of them gives home back (so the check refuses nothing real)."""
    q, valid = gough.inverse_kinematics(gough.home)
    assert valid.all() and (q > 0).all()
    fk = gough.forward_kinematics(q)
    assert fk.ok and np.allclose(fk.pose, gough.home, atol=1e-12)


@pytest.mark.parametrize("value", [0.0, -0.451])
def test_zero_or_negative_length_refused_on_every_route(gough, value):
    """A length of 0 was a ZeroDivisionError (the closure divides by q), a negative one
    ended as 'not found' (or, on the octic, passed for its square)."""
    q = [0.451] * 6
    q[5] = value
    for call in (lambda: gough.forward_kinematics(q),
                 lambda: gough.forward_kinematics(q, method="precise"),
                 lambda: forward_kinematics(gough, q)):
        with pytest.raises(InputError, match="positive leg length") as exc:
            call()
        assert exc.value.field == "q[5]"
    with pytest.raises(InputError) as exc:
        gough.forward_kinematics(np.array([[0.451] * 6, q]))
    assert exc.value.field == "q[1][5]"


def test_gauss_newton_survives_a_raising_kernel():
    """The control loop's routine: a scalar kernel that raises (Python floats do where
    numpy gives inf) is a failed evaluation, not an exception."""
    def closure(q, x):
        return [[1.0 / q[0]] + [0.0] * 6]
    x, done, it, c, D, step = gauss_newton(closure, [0.0], [0, 0, 0.3, 0, 0, 0],
                                           tol=1e-12, max_iter=5)
    assert not done and step is None and it == 1


@pytest.mark.parametrize("pose", [[0, 0, 1e160, 0, 0, 0], [1e154, 0, 0.3, 0, 0, 0],
                                  [0, 0, 1e300, 0, 0, 0]])
def test_far_poses_refused_not_nan(pose):
    """q was NaN with overflow RuntimeWarnings (README: 'never NaN')."""
    m = preset("octopod")
    for call in (m.inverse_kinematics, m.jacobian, m.reachable, m.reach_margin):
        with pytest.raises(InputError, match="translation component") as exc:
            call(pose)
        assert exc.value.field.startswith("poses[")


def test_poses_at_the_bounds_are_finite_unreachable_and_quiet():
    """Right at the bounds the kernels stay finite: legs flagged, no numpy warning; the
    Jacobian of legs that do not close says so (a ConditioningWarning), nothing else."""
    for name in ("octopod", "hexa"):
        m = preset(name)
        b = MAX_REACH * m.length_scale
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            for pose in ([b, -b, b, MAX_ROTATION, -MAX_ROTATION, 0], [0, 0, b, 0, 0, 0]):
                q, valid = m.inverse_kinematics(pose)
                assert np.isfinite(q).all() and not valid.any()
                assert (m.reach_margin(pose) < 0).all()           # the margin agrees
                with pytest.warns(ConditioningWarning, match="does not close"):
                    assert np.isfinite(m.jacobian(pose)).all()


def test_meaningless_rotation_refused_moderate_one_kept():
    """1e20 deg (1.7e18 rad) has no digit left modulo 2π: refused.  15 rad is a
    legitimate angle: the same q as 15 - 4π (R = Rz Ry Rx is 2π-periodic in rx)."""
    m = preset("octopod")
    with pytest.raises(InputError, match="rotation component") as exc:
        m.inverse_kinematics([0, 0, 0.3, math.radians(1e20), 0, 0])
    assert exc.value.field == "poses[3]"
    q1, v1 = m.inverse_kinematics([0, 0, 0.3, 15.0, 0, 0])
    q2, v2 = m.inverse_kinematics([0, 0, 0.3, 15.0 - 4 * math.pi, 0, 0])
    assert np.array_equal(v1, v2) and np.allclose(q1, q2, atol=1e-12)


def test_guess_checked_as_a_pose():
    m = preset("octopod")
    q, _ = m.inverse_kinematics(m.home)
    with pytest.raises(InputError) as exc:
        m.forward_kinematics(q, [0, 0, 1e200, 0, 0, 0])
    assert exc.value.field == "guess[2]"


def test_joint_amount_names_the_unit_per_joint_type():
    """R 10: the mismatch said '(rad or m)'; now its unit, per joint type."""
    v = [0.5, 2.0, 0.01]
    assert joint_amount(v, [False, False, False]) == "2 rad"
    assert joint_amount(v, [True, True, True]) == "2 m"
    assert joint_amount(v, [False, False, True]) == "2 rad (cranks), 0.01 m (prismatic legs)"
    assert joint_amount(v, [False, False, True], length=("mm", 1e3),
                        angle=("deg", 180 / math.pi)) == "115 deg (cranks), 10 mm (prismatic legs)"
    assert joint_amount([math.nan, 1.0], [False, False]) == "inf rad"
