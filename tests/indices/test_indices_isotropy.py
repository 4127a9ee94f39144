"""κ, GII and Stocco's culling (exactly the brute-force answer, fewer evaluations)."""

import numpy as np
import pytest
from indices_helpers import random_reachable_poses

from distkin.errors import InputError
from distkin.indices.isotropy import (brute_force_sweep, condition_number, culling_sweep, gii,
                                      scaled_singular_values)


def test_condition_number_analytic():
    """J = diag(a) stacked: σ of ST⁻¹Jᵀ are a_i / st_i."""
    a = np.array([30.0, 15, 45, 2, 1, 0.5])
    J = np.diag(a)
    smin, smax = scaled_singular_values(J)
    assert smin == pytest.approx(0.5) and smax == pytest.approx(3.0)
    assert condition_number(J) == pytest.approx(0.5 / 3.0)
    assert condition_number(J, ST=(1, 1, 1, 1, 1, 1)) == pytest.approx(0.5 / 45)
    assert condition_number(np.zeros((6, 6))) == 0.0


def test_a_length_unit_scales_sigma_and_keeps_kappa():
    """J in rad/mm (translational columns / 1000) with ST in N and N·mm gives W/1000: σ
    1000× smaller, κ unchanged (the docstring claimed W exactly; QA round H 9)."""
    J = np.random.default_rng(1).normal(size=(3, 8, 6))
    Jmm = J.copy()
    Jmm[..., :3] /= 1000.0
    a = scaled_singular_values(J, (15, 15, 15, 1, 1, 1))
    b = scaled_singular_values(Jmm, (15, 15, 15, 1000, 1000, 1000))
    for x, y in zip(a, b):
        np.testing.assert_allclose(y, x / 1000, rtol=1e-12)
    np.testing.assert_allclose(condition_number(Jmm, (15, 15, 15, 1000, 1000, 1000)),
                               condition_number(J), rtol=1e-12)


def test_fewer_than_six_legs_have_kappa_zero():
    """L = 4: W = ST⁻¹Jᵀ is 6 × 4 of rank 4, so a wrench direction is unreachable:
    σmin = 0 (six singular values padded with zeros, as numpy's full SVD of the 6 × 6
    Wᵀ W shows), κ = 0; σmax is numpy's (QA round H 5: κ was σ4/σ1 > 0)."""
    J = np.random.default_rng(0).normal(size=(2, 4, 6))
    W = np.swapaxes(J, 1, 2) / np.array([15, 15, 15, 1, 1, 1.0])[:, None]
    ev = np.linalg.eigvalsh(W @ np.swapaxes(W, 1, 2))          # 6 eigenvalues of W Wᵀ
    assert np.all(ev[:, :2] < 1e-12 * ev[:, -1:])
    smin, smax = scaled_singular_values(J)
    assert np.array_equal(smin, np.zeros(2))
    np.testing.assert_allclose(smax, np.sqrt(ev[:, -1]), rtol=1e-12)
    assert np.array_equal(condition_number(J), np.zeros(2))


def test_bad_input_names_its_argument():
    """Text for a Jacobian or scaling, or a negative singular value, is an InputError
    naming the argument (a bare numpy ValueError, or a silently negative GII, before)."""
    with pytest.raises(InputError) as err:
        condition_number("x")
    assert err.value.field == "J"
    with pytest.raises(InputError) as err:
        condition_number(np.eye(6), ST="abc")
    assert err.value.field == "ST"
    with pytest.raises(InputError, match=">= 0") as err:
        gii([0.1, 0.2], [-1.0, 3.0])
    assert err.value.field == "smax"
    assert gii([0.1, 0.2], [1.0, 4.0]) == (0.025, 0.1, 4.0)     # min σmin / max σmax


def test_table4_gii_is_min_sigma_over_max_sigma():
    """Kühne et al. Table IV prints GII = σmin / σmax: 0.0127/20.0052, 0.2230/27.8186,
    0.1910/26.6404 (rounded to 4 decimals)."""
    for g, lo, hi in ((0.0006, 0.0127, 20.0052), (0.0080, 0.2230, 27.8186),
                      (0.0072, 0.1910, 26.6404)):
        assert gii([lo, 1.0], [hi, 1.0])[0] == pytest.approx(g, abs=5e-5)


def test_scaling_input_errors():
    with pytest.raises(InputError, match="L, 6"):
        scaled_singular_values(np.ones((6, 5)))
    with pytest.raises(InputError, match="positive"):
        scaled_singular_values(np.ones((6, 6)), ST=(1, 1, 1, 1, 1, 0))


def _synthetic(nd, npo, seed):
    rng = np.random.default_rng(seed)
    A, B = rng.uniform(0.5, 1.5, nd), rng.uniform(0.5, 1.5, nd)
    P, Q = rng.uniform(0.01, 1, npo), rng.uniform(1, 3, npo)
    calls = []

    def evaluate(d, p):
        calls.append(len(d) * len(p))
        return (np.outer(A[d], P[p]) + 0.01 * (1 + np.sin(np.add.outer(d, p))),
                np.outer(B[d], Q[p]))
    return evaluate, calls


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_culling_equals_brute_force_exactly(seed):
    ev, calls = _synthetic(80, 3000, seed)
    ref, g = brute_force_sweep(ev, 80, 3000, block=512)
    res = culling_sweep(ev, 80, 3000, block=512)
    assert res.best == ref.best == int(np.argmax(g))
    assert res.gii == ref.gii and res.smin == ref.smin and res.smax == ref.smax
    assert res.evaluations < ref.evaluations / 3
    for k, v in res.exact.items():       # every complete design has its exact GII
        assert v == g[k]
    assert np.all(res.bounds >= g * (1 - 1e-15))   # the bounds are upper bounds


def test_culling_keeps_ties_like_argmax():
    def evaluate(d, p):                 # designs 3 and 5 tie for the optimum
        base = np.where(np.isin(d, [3, 5]), 2.0, 1.0)[:, None]
        return np.broadcast_to(base, (len(d), len(p))).copy(), np.ones((len(d), len(p)))
    res = culling_sweep(evaluate, 8, 50)
    ref, _ = brute_force_sweep(evaluate, 8, 50)
    assert res.best == ref.best == 3
    assert set(res.exact) >= {3, 5}


def test_design_sweep_culling_equals_brute_force_on_real_designs():
    """Four RSS designs of Table I on a coarse grid: same optimum and GII bit for bit."""
    from distkin.indices.design import DesignSpace, sweep_designs
    from distkin.indices.workspace import table2_grid
    grid = table2_grid(step=0.075, rot_deg=20, rot_step_deg=20)
    poses = grid.poses(np.arange(grid.n_positions))
    space = DesignSpace("hunt", (("l2", (0.0, 0.01)), ("ld", (0.02, 0.03))))
    r = sweep_designs(space, poses, algorithm="both", progress=False, block=200)
    assert r["agree"]
    assert r["culling"]["evaluations"] <= r["brute_force"]["evaluations"]
    assert r["parameters"] == r["designs"][int(np.argmax(r["brute_force"]["gii_all"]))]


def test_numpy_route_matches_the_generated_kernels(presets):
    """The plain-numpy IK/Jacobian used by design sweeps against the generated kernels."""
    from distkin.mechanisms.reference import ik_jacobian
    for name, mech in presets.items():
        poses = random_reachable_poses(mech, 200, 30, seed=7)
        q, valid = mech.inverse_kinematics(poses)
        q2, valid2, J2 = ik_jacobian(mech, poses)
        assert np.array_equal(valid, valid2)
        assert np.max(np.abs(q - q2)) < 1e-12
        J = mech.jacobian(poses)
        assert np.max(np.abs(J - J2)) < 1e-10 * np.max(np.abs(J))


def test_numpy_jacobian_by_finite_differences(presets):
    """q̇ = J (v, ω) against central differences of the numpy IK along a twist."""
    from distkin.mechanisms.reference import ik_jacobian
    mech = presets["octo"]
    pose = random_reachable_poses(mech, 1, 20, seed=8)[0]
    _, _, J = ik_jacobian(mech, pose[None])
    h = 1e-6
    for k in range(6):
        tw = np.zeros(6)
        tw[k] = 1.0
        plus, minus = _moved(pose, tw, h), _moved(pose, tw, -h)
        dq = (ik_jacobian(mech, plus[None])[0] - ik_jacobian(mech, minus[None])[0]) / (2 * h)
        assert np.allclose(dq[0], J[0][:, k], rtol=1e-6, atol=1e-6)


def _moved(pose, twist, h):
    """The pose after moving with the twist (v, ω in the base frame) for time h."""
    from scipy.spatial.transform import Rotation
    R0 = Rotation.from_euler("ZYX", pose[[5, 4, 3]])
    R1 = Rotation.from_rotvec(h * twist[3:]) * R0
    rz, ry, rx = R1.as_euler("ZYX")
    return np.r_[pose[:3] + h * twist[:3], rx, ry, rz]
