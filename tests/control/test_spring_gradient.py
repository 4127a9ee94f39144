"""The virtual rotational spring's torque is the gradient of its potential
U = ½ eᵀ diag(k) e, e = log(R R0ᵀ), for spatial rotations R <- exp(φ) R (QA: -diag(k) e
is not, for an anisotropic k: at e = (0.6, 0.3, 0) rad with k = (2, 20, 0.5) N·m/rad
it gave (-1.19, -5.82, 0.045) N·m against the gradient's (-1.52, -5.62, -1.50), and an
undamped spring swung its energy by ±25 %).  References: central differences of U with
scipy's rotations, and the energy of the stepped admittance."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from distkin.control.admittance import Admittance, Spring, rotation_log, spring_torque
from distkin.control.kinematics import _rot


def _fd_torque(R, k, eps=1e-6):
    def U(M):
        e = Rotation.from_matrix(M).as_rotvec()
        return 0.5 * e @ (k * e)
    g = np.zeros(3)
    for i in range(3):
        d = np.zeros(3)
        d[i] = eps
        g[i] = (U(Rotation.from_rotvec(d).as_matrix() @ R)
                - U(Rotation.from_rotvec(-d).as_matrix() @ R)) / (2 * eps)
    return -g


@pytest.mark.parametrize("seed", range(6))
def test_torque_is_the_gradient_of_the_potential(seed):
    rng = np.random.default_rng(seed)
    k = rng.uniform(0.2, 20.0, 3)
    for scale in (1e-5, 0.3, 1.5, 3.0):               # small, moderate, up to near π
        e = rng.normal(size=3)
        e *= min(scale, 3.1) / np.linalg.norm(e)
        R = Rotation.from_rotvec(e).as_matrix()
        got = spring_torque(rotation_log(R), k)
        np.testing.assert_allclose(got, _fd_torque(R, k), rtol=1e-6,
                                   atol=1e-8 * np.abs(k).max())


def test_the_qa_case_and_the_isotropic_spring_bit_for_bit():
    k = np.array([2.0, 20.0, 0.5])
    R = _rot([0.6, 0.3, 0.0])
    np.testing.assert_allclose(spring_torque(rotation_log(R), k), _fd_torque(R, k),
                               rtol=1e-6)
    e = rotation_log(R)
    iso = np.array([2.0, 2.0, 2.0])
    assert np.array_equal(spring_torque(e, iso), -iso * e)


@pytest.mark.parametrize("h", [1e-3, 2.5e-4])
def test_an_undamped_anisotropic_spring_keeps_its_energy(h):
    """Semi-implicit Euler keeps a modified energy: the swing shrinks with the step
    (it was ±25 % at both rates with -diag(k) e)."""
    K, inertia = np.array([2.0, 20.0, 0.5]), 0.005
    spring = Spring((0.0,) * 6, (0.0, 0.0, 0.0) + tuple(K))
    a = Admittance([1.0] * 3 + [inertia] * 3, [0.0] * 6, [spring])
    a.reset(np.array([0, 0, 0, 0.6, 0.3, 0.0]))
    a.twist = np.array([0, 0, 0, 0, 0, 5.0])

    def energy():
        e = rotation_log(_rot(a.pose[3:]))
        return 0.5 * inertia * a.twist[3:] @ a.twist[3:] + 0.5 * e @ (K * e)
    E0, E = energy(), []
    for i in range(int(2.0 / h)):
        a.commit(*a.propose(np.zeros(6), h))
        E.append(energy())
    swing = (max(E) - min(E)) / E0
    assert swing < 0.05 * (h / 1e-3) + 0.01, swing


def test_the_compiled_spring_wrench_is_the_python_one():
    from distkin.control.kinematics import load_model
    ck = load_model("octo").compiled
    rng = np.random.default_rng(4)
    for _ in range(20):
        anchor = np.concatenate([rng.normal(size=3) * 0.01, rng.normal(size=3) * 0.3])
        k = np.concatenate([rng.uniform(1, 100, 3), rng.uniform(0.1, 10, 3)])
        d = rng.uniform(0, 1, 6)
        s = Spring(tuple(anchor), tuple(k), tuple(d))
        pose = np.concatenate([rng.normal(size=3) * 0.02, rng.normal(size=3) * 0.5])
        tw = rng.normal(size=6)
        out = np.empty(6)
        ck.spring_wrench(pose, tw, s._p0, s._R0t, s._k, s._d, out)
        np.testing.assert_allclose(out, s.wrench(pose, tw), rtol=1e-12, atol=1e-14)
