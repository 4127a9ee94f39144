"""The forward kinematics verifies its answer (distkin.mechanisms.forward.round_trip):
Gauss-Newton on the closures Phi_i(q_i, x) = 0 alone can land on a pose where the
cranks are on the other branch of the IK (both branches close the legs) or on a
least-squares minimum that closes none.  The reference is independent of the check: the
closed-form IK at the returned pose, and the other branch written out in the test
(A cos q + B sin q = C has the roots atan2(B, A) +- delta)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InputError, NotFoundError
from distkin.mechanisms import preset
from distkin.mechanisms.forward_tiers import forward_tier
from distkin.spatial import pose_error

from rss_sampling import reachable_poses

POSE = np.array([0.02, -0.01, 0.31, 0.1, 0, -0.05])


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def test_qa_least_squares_minimum_below_the_base_is_not_ok():
    """From a guess 0.6 m below the workspace Gauss-Newton stops at z = -0.193 m with a
    63 um closure residual: every crank of the IK there is 1.3-1.57 rad off."""
    m = preset("octopod")
    q, _ = m.inverse_kinematics(POSE)
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        fk = m.forward_kinematics(q, [0, 0, -0.3, 0, 0, 0])
    back = _wrap(m.inverse_kinematics(fk.pose)[0] - q)
    assert fk.converged and np.abs(back).min() > 1.0          # independent: not a solution
    assert not fk.ok and not fk.verified and not fk.round_trip
    assert fk.q_mismatch == pytest.approx(np.abs(back).max())
    assert fk.residual > fk.residual_tol
    assert "does not give back the joint values" in fk.message
    with pytest.raises(NotFoundError, match="gives back the joint values"):
        m.forward_kinematics(q, [0, 0, -0.3, 0, 0, 0], strict=True)
    for method in ("fast", "precise", "certified"):
        with pytest.raises(NotFoundError, match="other branch of the IK"):
            forward_tier(m, q, [0, 0, -0.3, 0, 0, 0], method=method)
    good = m.forward_kinematics(q, POSE + 0.005)              # a guess near the device
    assert good.ok and pose_error(good.pose, POSE)[0] < 1e-12


def test_qa_cranks_at_200_degrees_are_the_other_branch():
    """All cranks at 200 deg close the legs exactly (residual 2e-17 m) at z = 0.292 m,
    where the device's IK branch gives 16.7 deg: not the device's configuration."""
    m = preset("octopod")
    q = np.full(8, np.radians(200))
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        fk = m.forward_kinematics(q)
    assert fk.converged and fk.residual < 1e-15                # the closures hold ...
    ik = m.inverse_kinematics(fk.pose)[0]
    assert np.all(np.abs(_wrap(ik - q)) > 2.5)                 # ... on the other branch
    assert not fk.ok and not fk.round_trip and fk.q_mismatch > 2.5
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        batched = m.forward_kinematics(q[None])
    assert not batched.ok[0] and not batched.verified[0]
    with pytest.raises(NotFoundError):
        m.forward_kinematics(q, strict=True)
    with pytest.raises(NotFoundError, match="other branch"):
        forward_tier(m, q, method="certified")


@pytest.mark.parametrize("name", ["octopod", "hunt"])
def test_every_leg_on_its_other_branch_is_refused(name):
    """The other root of each leg's A cos q + B sin q = C, q' = 2 atan2(B, A) - q (A, B
    from the leg table, written out here): its closures vanish at the pose (so Gauss-Newton
    from the pose stays there), and the answer is refused."""
    m = preset(name)
    P = reachable_poses(m, 20, seed=31)
    q, _ = m.inverse_kinematics(P)
    pts = m.points(P, q)
    d = m.leg_description().arrays()
    w = pts["P"] - d["B"] - d["offset"]
    A, B = np.einsum("nli,li->nl", w, d["u"]), np.einsum("nli,li->nl", w, d["v"])
    other = _wrap(2 * np.arctan2(B, A) - q)
    phi = m.kernels("batched").closure(other, P)[..., 0]
    assert np.abs(phi).max() < 1e-15 and np.abs(_wrap(other - q)).min() > 0.1
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        fk = m.forward_kinematics(other, P)
    assert fk.converged.all() and not fk.round_trip.any() and not fk.ok.any()
    assert fk.residual.max() < 1e-15 and np.all(fk.q_mismatch > 0.1)


@pytest.mark.parametrize("name", ["octopod", "octo", "hexa"])
def test_random_round_trips_verify(name):
    """IK -> FK from a guess 5 mm / 5 deg off -> the pose (1e-10), verified, ok, and the
    fast tier's stated error covers the distance to the pose."""
    m = preset(name)
    P = reachable_poses(m, 300, seed=32, max_angle_deg=25.0, min_margin=0.0)
    q, valid = m.inverse_kinematics(P)
    rng = np.random.default_rng(32)
    G = P + np.c_[rng.uniform(-5e-3, 5e-3, (300, 3)), rng.uniform(-0.087, 0.087, (300, 3))]
    fk = m.forward_kinematics(q, G)
    dpos, dang = pose_error(fk.pose, P)
    assert fk.ok.all() and fk.verified.all() and dpos.max() < 1e-10 and dang.max() < 1e-10
    assert fk.residual.max() <= fk.residual_tol
    back = _wrap(m.inverse_kinematics(fk.pose)[0] - q)
    assert np.all(np.abs(back) <= 1e-9) and np.all(fk.q_mismatch <= 1e-9)
    for i in range(0, 300, 60):
        tier = forward_tier(m, q[i], G[i])
        assert np.all(np.abs(tier.pose - P[i]) <= tier.error + 1e-15)


def test_inconsistent_angles_need_a_residual_tolerance():
    """L = 8, one crank 1e-4 rad off: the least-squares pose is on the device's branch
    (round trip within the closure residual over the crank's lever) but not a float64
    solution; residual_tol accepts measured angles."""
    m = preset("octopod")
    q, _ = m.inverse_kinematics(POSE)
    q[2] += 1e-4
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        fk = m.forward_kinematics(q, POSE)
    assert fk.converged and fk.round_trip and not fk.verified and not fk.ok
    assert "residual above residual_tol" in fk.message
    loose = m.forward_kinematics(q, POSE, residual_tol=1e-4)
    assert loose.ok and loose.residual == fk.residual
    assert np.abs(_wrap(m.inverse_kinematics(fk.pose)[0] - q)).max() < 2e-4
    assert forward_tier(m, q, POSE).residual == pytest.approx(fk.residual)
    with pytest.raises(InputError, match="residual_tol"):
        m.forward_kinematics(q, POSE, residual_tol=-1.0)
