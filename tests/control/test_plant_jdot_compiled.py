"""The rotors' J̇V of the simulated device in one compiled call (distkin.control.plant).

The compiled ``jdot_v`` (:mod:`distkin.control.cycle_kernels`) replaced six calls through
the model (two rotations, two IKs, two Jacobians: ~30 µs of a ~48 µs plant step, which
held the lock-stepped 4 kHz loop over the pty below 4 kHz).  References: the numpy
route of :meth:`Plant.jdot_v` (a model with ``compiled=False``), in the interior, within
a step of the reach boundary (the one-sided differences) and beyond it; and an
independent derivative, J̇V from the Jacobian along the exact screw motion by a
five-point difference in the time."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.control.kinematics import load_model
from distkin.control.plant import Plant
from distkin.spatial import rotate_pose_scalar as rotate_pose


@pytest.fixture(scope="module")
def plants():
    fast, ref = load_model("octo"), load_model("octo", compiled=False)
    return Plant(fast), Plant(ref)


def _both(plants, pose, twist):
    out = []
    for p in plants:
        p.pose, p.twist = np.array(pose, float), np.array(twist, float)
        out.append(p.jdot_v())
    return out


def test_interior_poses_against_the_numpy_route(plants):
    fast, ref = plants
    assert fast._ck is not None and ref._ck is None
    rng = np.random.default_rng(5)
    home = fast.model.home
    for _ in range(60):
        pose = home + rng.normal(0, [0.02, 0.02, 0.02, 0.1, 0.1, 0.1])
        twist = rng.normal(0, [0.3, 0.3, 0.3, 2.0, 2.0, 2.0])
        a, b = _both(plants, pose, twist)
        assert fast.model.ik(pose)[1]
        scale = np.abs(b).max()
        assert scale > 0
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * scale)


def test_zero_twist_is_zero(plants):
    a, b = _both(plants, plants[0].model.home, np.zeros(6))
    assert not a.any() and not b.any()


def _boundary(model, d):
    """The last reachable pose from home along the unit translation ``d`` (bisection)."""
    lo, hi = 0.0, 1.0
    assert not model.ik(model.home + np.r_[hi * d, 0, 0, 0])[1]
    for _ in range(80):
        t = 0.5 * (lo + hi)
        lo, hi = (t, hi) if model.ik(model.home + np.r_[t * d, 0, 0, 0])[1] else (lo, t)
    return lo


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_one_sided_and_beyond_the_reach_boundary(plants, sign):
    """Within half a difference step of the boundary one displaced pose is out of
    reach: both routes take the same one-sided difference (and zero beyond it)."""
    fast, _ = plants
    m = fast.model
    d = np.array([0.0, 0.0, 1.0])
    edge = _boundary(m, d)
    h = Plant.JDOT_STEP
    twist = np.r_[sign * 0.4 * d, 0, 0, 0]
    pose = m.home + np.r_[(edge - 0.5 * h) * d, 0, 0, 0]
    plus = rotate_pose(pose, twist[:3] * h / 0.4, twist[3:] * h / 0.4)
    minus = rotate_pose(pose, -twist[:3] * h / 0.4, -twist[3:] * h / 0.4)
    assert m.ik(pose)[1] and (m.ik(plus)[1] != m.ik(minus)[1])     # one side only
    a, b = _both(plants, pose, twist)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * np.abs(b).max())
    # one-sided: what the reachable side gives
    J0 = m.jacobian(pose)
    side = plus if m.ik(plus)[1] else minus
    want = (m.jacobian(side) - J0) @ twist / (h if side is plus else -h) * 0.4
    np.testing.assert_allclose(a, want, rtol=1e-9, atol=1e-12 * np.abs(want).max())
    # beyond the boundary by more than a step: neither side in reach, zero
    far = m.home + np.r_[(edge + 3 * h) * d, 0, 0, 0]
    a, b = _both(plants, far, twist)
    assert not a.any() and not b.any()


def test_against_the_derivative_along_the_screw_motion(plants):
    """J̇V = d/dt J(x(t)) V at t = 0 for the motion x(t) = rotate_pose(x, V t): a
    five-point difference in t (error O(t⁴)) agrees with the compiled central
    difference to its own O(h²)."""
    fast, _ = plants
    m = fast.model
    rng = np.random.default_rng(11)
    for _ in range(10):
        pose = m.home + rng.normal(0, [0.01, 0.01, 0.01, 0.05, 0.05, 0.05])
        V = rng.normal(0, [0.2, 0.2, 0.2, 1.0, 1.0, 1.0])
        fast.pose, fast.twist = pose, V
        got = fast.jdot_v()
        dt = 1e-3

        def JV(t):
            return m.jacobian(rotate_pose(pose, V[:3] * t, V[3:] * t)) @ V
        want = (JV(-2 * dt) - 8 * JV(-dt) + 8 * JV(dt) - JV(2 * dt)) / (12 * dt)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-5 * np.abs(want).max())
