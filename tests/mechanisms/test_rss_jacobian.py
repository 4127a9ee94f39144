"""J = Jq^-1 Jx (Kühne et al., eqs. (1)-(2)) against finite differences, and eq. (7)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.mechanisms import preset
from distkin.spatial import exp_so3, omega_map, rotation_angles, rotation_matrix

from rss_sampling import PRESET_NAMES, reachable_poses


@pytest.mark.parametrize("name", PRESET_NAMES)
def test_jacobian_matches_central_differences(name):
    """Acceptance: 1000 random reachable poses of every preset, 1e-7 relative."""
    m = preset(name)
    P = reachable_poses(m, 1000, seed=11)
    Jp = m.pose_jacobian(P)
    h = 1e-7
    fd = np.empty_like(Jp)
    for j in range(6):
        e = np.zeros(6)
        e[j] = h
        fd[..., j] = (m.inverse_kinematics(P + e)[0] - m.inverse_kinematics(P - e)[0]) / (2 * h)
    rel = np.linalg.norm(fd - Jp, axis=(1, 2)) / np.linalg.norm(Jp, axis=(1, 2))
    assert rel.max() < 1e-7, rel.max()


def test_angular_velocity_convention():
    """q̇ = J (v, ω) along a motion with constant (v, ω) (a twist), by differences of IK."""
    m = preset("octo")
    P = reachable_poses(m, 100, seed=12)
    rng = np.random.default_rng(2)
    v, w = rng.normal(size=(100, 3)) * 0.1, rng.normal(size=(100, 3))
    h = 1e-7
    R = rotation_matrix(P[:, 3:])

    def moved(t):
        X = P.copy()
        X[:, :3] += t * v
        X[:, 3:] = rotation_angles(exp_so3(t * w) @ R)
        return X
    qdot = (m.inverse_kinematics(moved(h))[0] - m.inverse_kinematics(moved(-h))[0]) / (2 * h)
    pred = np.einsum("nij,nj->ni", m.jacobian(P), np.hstack([v, w]))
    assert np.abs(qdot - pred).max() < 1e-7 * np.abs(pred).max()


def test_jq_jx_compose(any_preset):
    m = any_preset
    P = reachable_poses(m, 100, seed=13)
    Jq, Jx = m.jq_jx(P)
    np.testing.assert_allclose(Jx / Jq[..., None], m.jacobian(P), rtol=1e-12, atol=1e-12)
    # omega map: pose_jacobian = J blockdiag(I, E)
    E = omega_map(P[:, 3:])
    np.testing.assert_allclose(m.pose_jacobian(P)[..., 3:], m.jacobian(P)[..., 3:] @ E,
                               rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("name", ["hunt", "octopod"])
def test_mass_matrices(name):
    """Mq = J#ᵀ M̂ J#: kinetic energy agrees; eq. (7): J# Mq⁺ = M̂⁻¹ Jᵀ."""
    m = preset(name)
    P = reachable_poses(m, 50, seed=14)
    J = m.jacobian(P)
    Mq = m.joint_mass_matrix(P)
    Mh = m.cartesian_mass_matrix()
    xdot = np.random.default_rng(3).normal(size=(50, 6))
    qdot = np.einsum("nij,nj->ni", J, xdot)
    e_cart = np.einsum("ni,ij,nj->n", xdot, Mh, xdot)
    e_joint = np.einsum("ni,nij,nj->n", qdot, Mq, qdot)
    np.testing.assert_allclose(e_joint, e_cart, rtol=1e-9)
    inv = np.linalg.inv if m.L == 6 else np.linalg.pinv
    A = np.linalg.pinv(J) @ inv(Mq)
    np.testing.assert_allclose(m.acceleration_map(P), A, rtol=1e-6,
                               atol=1e-9 * np.abs(A).max())
    assert np.linalg.matrix_rank(Mq[0]) == 6


def test_wrench_duality():
    """Virtual work: τ·q̇ = (f, τ_ee)·(v, ω) with (f, τ_ee) = Jᵀ τ (eq. (3))."""
    m = preset("octopod")
    P = reachable_poses(m, 20, seed=15)
    J = m.jacobian(P)
    rng = np.random.default_rng(4)
    tau, xdot = rng.normal(size=(20, 8)), rng.normal(size=(20, 6))
    wrench = np.einsum("nji,nj->ni", J, tau)
    lhs = np.einsum("ni,ni->n", tau, np.einsum("nij,nj->ni", J, xdot))
    np.testing.assert_allclose(lhs, np.einsum("ni,ni->n", wrench, xdot), rtol=1e-12)
