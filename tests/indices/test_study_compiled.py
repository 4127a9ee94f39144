"""The compiled study kernel (distkin.indices.study_compiled, the split-sign vertex
enumeration of distkin.indices.slice_farthest) against the numpy route, which is the
reference (zonotope._facets, numpy's SVD and pinv, the Gray-code enumeration)."""

import numpy as np
import pytest
from indices_helpers import random_reachable_poses, rel_err

from distkin.indices import worst_case_output
from distkin.indices.slice_farthest import slice_farthest_unit
from distkin.indices.study import QUANTITIES, evaluate_poses
from distkin.indices.study_compiled import study_indices
from distkin.indices.zonotope import zonotope_best

#: stated tolerance of the compiled route against the numpy route (relative); measured
#: differences are a few 1e-13 (σmin of ST·Jᵀ, the worst conditioned reading)
TOL = 1e-10


@pytest.mark.parametrize("name", ["ergin", "hunt", "octopod", "octo"])
def test_compiled_study_agrees_with_the_numpy_route(presets, name):
    mech = presets[name]
    P = random_reachable_poses(mech, 300, 30 if mech.L == 8 else 20, seed=21)
    ok1, v1 = evaluate_poses(mech, P)
    ok2, v2 = evaluate_poses(mech, P, compiled=False)
    assert np.array_equal(ok1, ok2) and ok1.all()
    for q in QUANTITIES:
        assert rel_err(v1[q], v2[q]) < TOL, q


@pytest.mark.filterwarnings(
    "ignore:maximum sensitivities.*Moore-Penrose:distkin.errors.ConditioningWarning")
def test_a_singular_pose_is_flagged_and_computed_by_the_numpy_route(presets):
    """σmin/σmax of Jᵀ below RANK_TOL: the kernel flags the pose; the study's values
    there are those of the numpy route (the flat route of zonotope._flat_worst)."""
    mech = presets["octopod"]
    P = random_reachable_poses(mech, 5, 20, seed=3)
    Jq, Jx = mech.jq_jx(P)
    J = Jx / Jq[..., None]
    J[2, :, 5] = 0.0                                   # a pure-torque null wrench
    M = np.array([mech.mass] * 3 + [mech.inertia] * 3)
    act = {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0}
    *_, flag = study_indices(J, Jq, M, act, (15, 15, 15, 1, 1, 1))
    assert flag.tolist() == [False, False, True, False, False]
    # the study's values at the flagged pose are the numpy route's, bit for bit; there
    # the zero-torque force slice is finite (docs/design.md §6: the plain formula gives
    # inf) and equals the public zonotope kernel on Jᵀ
    from distkin.indices.study import _indices_compiled, _indices_numpy
    out = _indices_compiled(J, Jq, M, act, (15, 15, 15, 1, 1, 1), "slice")
    ref = _indices_numpy(J[2:3], Jq[2:3], M, act, (15, 15, 15, 1, 1, 1), "slice")
    assert set(ref) <= set(out)
    for q, v in ref.items():
        assert np.array_equal(out[q][2:3], v, equal_nan=True), q
    f = worst_case_output(J[2].T, -2.5, 2.5, [0, 1, 2])
    assert np.isfinite(f) and f > 0
    assert out["force"][2] == pytest.approx(f, rel=1e-12)


@pytest.mark.filterwarnings(
    "ignore:maximum sensitivities.*Moore-Penrose:distkin.errors.ConditioningWarning")
def test_an_exactly_zero_column_of_J_is_flagged(presets):
    """J e_z = 0 exactly (QA round H 3): the Householder QR of the lanes divides 0 by 0
    and its σ came out (inf, 0), which passed the rank test, so the L = 8 capabilities
    and sensitivities came from NaN (a rotational sensitivity of -inf).  The pose is
    flagged and its values are the numpy route's."""
    from distkin.indices.study import _indices_compiled, _indices_numpy
    mech = presets["octopod"]
    P = random_reachable_poses(mech, 3, 20, seed=8)
    Jq, Jx = mech.jq_jx(P)
    J = Jx / Jq[..., None]
    J[1, :, 2] = 0.0
    M = np.array([mech.mass] * 3 + [mech.inertia] * 3)
    act = {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0}
    *_, flag = study_indices(J, Jq, M, act, (15, 15, 15, 1, 1, 1))
    assert flag.tolist() == [False, True, False]
    out = _indices_compiled(J, Jq, M, act, (15, 15, 15, 1, 1, 1), "slice")
    ref = _indices_numpy(J[1:2], Jq[1:2], M, act, (15, 15, 15, 1, 1, 1), "slice")
    for q, v in ref.items():
        assert np.array_equal(out[q][1:2], v), q
    assert out["sens_translational"][1] == np.inf and np.isfinite(out["sens_rotational"][1])


def test_chunks_change_nothing(presets):
    """Evaluating in chunks of 7 poses gives the same bits as one call."""
    mech = presets["octo"]
    P = random_reachable_poses(mech, 40, 30, seed=5)
    ok1, v1 = evaluate_poses(mech, P)
    ok2, v2 = evaluate_poses(mech, P, chunk=7)
    assert np.array_equal(ok1, ok2)
    for q in QUANTITIES:
        assert np.array_equal(v1[q], v2[q]), q


@pytest.mark.parametrize("keep", [(0, 1, 2), (3, 4, 5)])
def test_split_sign_enumeration_against_numpy_enumeration(presets, keep):
    """L = 8: the split-sign kernel against zonotope_best (numpy, the same candidates)
    on J# and Jᵀ."""
    mech = presets["octopod"]
    J = mech.jacobian(random_reachable_poses(mech, 200, 30, seed=8))
    N, L, _ = J.shape
    c, r = np.zeros((N, L)), np.ones((N, L))
    for G in (np.linalg.pinv(J), np.swapaxes(J, 1, 2)):
        a = slice_farthest_unit(G, keep)
        b = zonotope_best(G, c, r, [keep])[0]
        assert rel_err(a, b) < 1e-12


def test_zonotope_worst_in_chunks_changes_nothing(presets):
    """The capability kernel in chunks of 5 poses gives the same bits as one chunk."""
    from distkin.indices.zonotope import zonotope_worst
    mech = presets["octopod"]
    G = np.swapaxes(mech.jacobian(random_reachable_poses(mech, 23, 30, seed=4)), 1, 2)
    G[7, 5, :] = 0.0                                   # one flat set among them
    N, _, L = G.shape
    c, r = np.zeros((N, L)), np.full((N, L), 2.5)
    keeps = [(0, 1, 2, 3, 4, 5), (0, 1, 2), (3, 4, 5)]
    assert np.array_equal(zonotope_worst(G, c, r, keeps, chunk=5),
                          zonotope_worst(G, c, r, keeps, chunk=4096))


def test_reference_route_uses_the_walk_and_split_kernel_agrees_with_it(presets):
    """The split-sign kernel against the Gray-code walk (the previous kernel) on the
    same generators: same candidates, sums associated differently."""
    mech = presets["octo"]
    J = mech.jacobian(random_reachable_poses(mech, 200, 30, seed=9))
    for G in (np.linalg.pinv(J), np.swapaxes(J, 1, 2)):
        for keep in ((0, 1, 2), (3, 4, 5)):
            a = slice_farthest_unit(G, keep)
            b = slice_farthest_unit(G, keep, walk=True)
            assert rel_err(a, b) < 1e-13


def test_readings_match_numpy_svd_under_an_ill_conditioned_scaling(presets):
    """σ of ST⁻¹Jᵀ and ST⁻¹Jxᵀ (jacobi_lanes) against numpy's SVD, with the default
    scaling (κ about 15) and with ST = (1, 1, 1, 1e-3, 1e-3, 1e-3) (κ of 3e2 or more)."""
    mech = presets["octopod"]
    P = random_reachable_poses(mech, 40, 30, seed=12)
    Jq, Jx = mech.jq_jx(P)
    J = Jx / Jq[..., None]
    M = np.array([mech.mass] * 3 + [mech.inertia] * 3)
    act = {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0}
    for st in ((15, 15, 15, 1, 1, 1), (1, 1, 1, 1e-3, 1e-3, 1e-3)):
        st = np.array(st, float)
        sig = study_indices(J, Jq, M, act, st)[3]
        for k, A in ((0, np.swapaxes(J, 1, 2) / st[:, None]),
                     (3, np.swapaxes(J * Jq[..., None], 1, 2) / st[:, None])):
            s = np.linalg.svd(A, compute_uv=False)
            kappa = s[:, 0] / s[:, -1]
            assert rel_err(sig[:, 2 * k], s[:, -1]) < 1e-10
            assert rel_err(sig[:, 2 * k + 1], s[:, 0]) < 1e-12
        if st[3] < 1:
            assert kappa.min() > 100


def test_lane_kernel_shares_the_feasibility_allowance_and_any_block_position(presets):
    """The SIMD kernel (slice_lanes) uses the walk's rounding allowance, and a pose's
    value does not depend on its place in a block of LANES poses (padding of the last
    block included): the same bits one by one and in a block."""
    from distkin.indices import slice_farthest, slice_lanes
    assert (slice_lanes._TOL, slice_lanes._EPS) == (slice_farthest._TOL, slice_farthest._EPS)
    mech = presets["octopod"]
    G = np.linalg.pinv(mech.jacobian(random_reachable_poses(mech, 37, 30, seed=2)))
    whole = slice_farthest_unit(G, (0, 1, 2))
    one = np.array([slice_farthest_unit(G[i:i + 1], (0, 1, 2))[0] for i in range(5)])
    assert np.array_equal(whole[:5], one)
    assert np.array_equal(slice_farthest_unit(G[3:], (0, 1, 2)), whole[3:])


@pytest.mark.parametrize("name", ["hunt", "octopod"])
def test_compiled_loop_kinematics_equal_the_batched_kernels(presets, name):
    """The study's kinematics (reach_jq_jx: the generated loop twins of reach and jq_jx,
    compiled by numba) against the batched kernels: the same formulas, the same bits
    here; the loop kernel run as plain Python on a few poses too."""
    from distkin.indices.study_compiled import reach_jq_jx
    mech = presets[name]
    rng = np.random.default_rng(7)
    P = np.c_[rng.uniform(-0.1, 0.1, (300, 3)) + [0, 0, mech.z0],
              np.deg2rad(rng.uniform(-35, 35, (300, 3)))]
    valid, Jq, J = reach_jq_jx(mech, P)
    assert np.array_equal(valid, mech.reachable(P)) and 0 < valid.sum() < len(P)
    Jq2, Jx2 = mech.jq_jx(P, warn=False)       # the unreachable poses compared too
    assert np.array_equal(Jq, Jq2)
    assert np.array_equal(J[valid], (Jx2 / Jq2[..., None])[valid])
    out = np.empty((3, mech.L, 7))
    mech.kernels("batched").loops["jq_jx"](P[:3], out)          # uncompiled
    assert np.allclose(out, mech.kernels("batched").jq_jx(P[:3]), rtol=1e-14, atol=0)


def test_transposed_generators_are_read_in_place_with_the_same_bits(presets):
    """Jᵀ given as J (transposed=True) gives the bits of the copied transpose, in the
    split-sign kernel (read in place) and in the walk (copied)."""
    mech = presets["octopod"]
    J = mech.jacobian(random_reachable_poses(mech, 70, 30, seed=6))
    Gw = np.ascontiguousarray(np.swapaxes(J, 1, 2))
    for keep in ((0, 1, 2), (3, 4, 5)):
        for walk in (False, True):
            assert np.array_equal(slice_farthest_unit(J, keep, walk=walk, transposed=True),
                                  slice_farthest_unit(Gw, keep, walk=walk))


def test_l6_lane_kernels_against_the_walk_and_the_inverse(presets):
    """L = 6: the split-sign lane kernel on Jᵀ against the Gray-code walk (same
    candidates, sums associated differently), and the slab lane kernel on J_S against
    the walk on J⁻¹ (the zonotope route it replaces for square Jacobians)."""
    from distkin.indices.slice_farthest import slab_farthest_unit
    for name in ("hunt", "ergin"):
        mech = presets[name]
        J = mech.jacobian(random_reachable_poses(mech, 150, 20, seed=10))
        Jinv = np.linalg.inv(J)
        for keep in ((0, 1, 2), (3, 4, 5)):
            a = slice_farthest_unit(J, keep, transposed=True)
            b = slice_farthest_unit(J, keep, transposed=True, walk=True)
            assert rel_err(a, b) < 1e-13
            s = slab_farthest_unit(np.ascontiguousarray(J[:, :, list(keep)]))
            assert rel_err(s, slice_farthest_unit(Jinv, keep, walk=True)) < 1e-10


def test_compiled_kinematics_of_a_derived_geometry_load_in_a_second_process(tmp_path):
    """A geometry without a committed module (derived into the derivation cache): its
    compiled loop kernels, kept in numba's disk cache, load in another process (numba
    records the module of what it compiles; an unregistered module was '<dynamic>' and
    the second process failed), with the same values."""
    import os
    import subprocess
    import sys
    code = (
        "import numpy as np\n"
        "from distkin.indices.study_compiled import reach_jq_jx\n"
        "from distkin.mechanisms.platforms import platform_mechanism\n"
        "m = platform_mechanism(([[0, 0, 0], [6, 'sqrt(108)', 0], [12, 0, 0]],\n"
        "                        [[0, 0, 0], [6, 0, 0], [3, 'sqrt(27)', 0]]),\n"
        "                       unit=0.01, height=17, name='gd_loop')\n"
        "rng = np.random.default_rng(4)\n"
        "X = m.home + rng.uniform(-1, 1, (50, 6)) * [0.01, 0.01, 0.01, 0.1, 0.1, 0.1]\n"
        "ok, Jq, J = reach_jq_jx(m, X)\n"
        "Jq2, Jx2 = m.jq_jx(X)\n"
        "assert ok.all() and np.array_equal(J, Jx2 / Jq2[..., None])\n"
        "print('same')\n")
    env = dict(os.environ, DISTKIN_CACHE=str(tmp_path))
    for _ in range(2):                       # derive and compile; load both from disk
        r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                           text=True)
        assert r.returncode == 0 and r.stdout.strip() == "same", r.stderr[-2000:]
