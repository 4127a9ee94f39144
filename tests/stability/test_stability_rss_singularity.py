"""Stability at the extremes (issue 8): RSS poses approaching a parallel singularity.

The extreme: the HEXA preset under the radial reading of Fig. 2 (``layout="radial"``,
which has singularities at zero rotation like the paper's Fig. 3) (L = 6) on the straight line from the workspace centre
towards the corner (-75, -75, +75) mm of the Table II cube at zero rotation; det Jx
changes sign on that line (located by bisection, :mod:`stability_helpers`).  The poses
approach the crossing from the regular side at distances d = 10^-1 ... 10^-8 m.

At a *simple* crossing one singular value of J passes through zero linearly, so
σmin(J) ≈ c·d with c = |u_minᵀ (dJ/dt) v_min| (first-order perturbation of a simple
singular value; dJ/dt by central finite differences at the crossing).  Everything
that is a distance to the boundary of a set squashed in one direction (worst-case
wrench and acceleration capabilities, the scaled κ of eq. (4)) must go to 0 in
proportion to d; maximum sensitivities, which see J⁻¹, grow like 1/d.
"""

import numpy as np
import pytest

from stability_helpers import first_order_sigma_slope, hexa_crossing

DIST = 10.0 ** -np.arange(1, 9)          # m, from far to close
EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def approach():
    from distkin.mechanisms import preset
    mech = preset("hexa", layout="radial")
    t_star, u = hexa_crossing(mech)
    poses = mech.home + (t_star - DIST)[:, None] * u
    return mech, t_star, u, poses


def _loglog_slope(d, y):
    return np.polyfit(np.log10(d), np.log10(y), 1)[0]


def test_sigma_min_vanishes_linearly_as_first_order_theory_predicts(approach):
    """Extreme: d → 1e-8 m from a simple singular crossing.

    Expected: σmin(J) finite, positive and strictly decreasing; log-log slope of σmin
    against d equal to 1 within 0.01 over d <= 1e-3 m; σmin/d equal to the first-order
    slope c (finite differences, step 1e-6 m) within 1e-3 relative for d <= 1e-4 m
    (the neglected terms are O(d) relative, float64 rounding about κ·eps <= 1e-7).
    """
    mech, t_star, u, poses = approach
    J = mech.jacobian(poses)
    assert np.all(np.isfinite(J))
    assert mech.reachable(poses).all()
    s = np.linalg.svd(J, compute_uv=False)
    smin, smax = s[:, -1], s[:, 0]
    assert np.all(smin > 0) and np.all(np.diff(smin) < 0)
    near = DIST <= 1e-3
    assert abs(_loglog_slope(DIST[near], smin[near]) - 1) < 0.01
    c = first_order_sigma_slope(mech, t_star, u)
    close = DIST <= 1e-4
    np.testing.assert_allclose(smin[close] / DIST[close], c, rtol=1e-3)
    # the largest singular value stays bounded: κ grows like 1/d
    assert np.ptp(smax[near]) / smax[near].mean() < 0.05


def test_scaled_condition_number_goes_to_zero_like_the_distance(approach):
    """Extreme: as above, the scaled inverse condition number κ = σmin/σmax of
    W = ST⁻¹Jᵀ (eq. (4), :func:`distkin.indices.condition_number`).

    Expected: in (0, 1], strictly decreasing, log-log slope 1 within 0.01 for
    d <= 1e-3 m (σmax of W bounded, σmin(W) ∝ d as for J: ST is a fixed invertible
    scaling).
    """
    from distkin.indices import condition_number
    mech, _, _, poses = approach
    k = condition_number(mech.jacobian(poses))
    assert np.all((k > 0) & (k <= 1)) and np.all(np.diff(k) < 0)
    near = DIST <= 1e-3
    assert abs(_loglog_slope(DIST[near], k[near]) - 1) < 0.01


def test_capabilities_go_smoothly_to_zero_without_nan_or_sign_flip(approach):
    """Extreme: as above; the study's per-pose indices (:func:`evaluate_poses`).

    Expected: every quantity finite (no NaN, no inf); the six worst-case capabilities
    stay positive (no sign flip: the origin stays inside the output set); those of
    the wrench and acceleration maps (force, torque, acceleration, angular
    acceleration) decrease strictly and vanish like d (log-log slope 1 within 0.01
    for d <= 1e-3 m); the twist capabilities (velocity, angular velocity) stay
    finite (their map is J⁻¹, whose set only grows); the paper's sliced maximum
    sensitivities (the study's default, eqs. (14)/(16)) stay finite and converge (the
    slice cuts the set's long direction, which mixes translation and rotation): the
    last two distances agree to 1e-6; Cardou's projected translational and rotational
    sensitivities (J⁻¹) grow like 1/d (slope -1 within 0.01).
    """
    from distkin.indices.study import CAPABILITIES, evaluate_poses
    mech, _, _, poses = approach
    ok, v = evaluate_poses(mech, poses)
    assert ok.all()
    for name, arr in v.items():
        assert np.all(np.isfinite(arr)), name
    near = DIST <= 1e-3
    for cap in CAPABILITIES:
        assert np.all(v[cap[0]] > 0), cap[0]
    for name in ("force", "torque", "acceleration", "angular_acceleration"):
        assert np.all(np.diff(v[name]) < 0), name
        assert abs(_loglog_slope(DIST[near], v[name][near]) - 1) < 0.01, name
    for name in ("velocity", "angular_velocity"):
        assert v[name].max() / v[name].min() < 1.2, name
    for name in ("sens_translational", "sens_rotational", "sens_force", "sens_torque"):
        assert abs(v[name][-1] / v[name][-2] - 1) < 1e-6, name
    from distkin.indices.sensitivity import max_sensitivities
    proj = max_sensitivities(mech.jacobian(poses), mode="projection")
    for name in ("translational", "rotational"):
        assert abs(_loglog_slope(DIST[near], proj[name][near]) + 1) < 0.01, name


def test_worst_case_force_agrees_with_the_hull_algorithm_to_kappa_eps(approach):
    """Extreme: as above; second route: the paper's Qhull polytope algorithm
    (Kühne et al., steps (a)-(d)) on the same Jacobians.

    Expected: the zonotope kernel and Qhull agree within 100·κ(J)·eps relative, κ the
    2-norm condition number of J (both lose the digits the conditioning predicts, no
    more), down to d = 1e-8 m.
    """
    from distkin.indices import worst_case_output
    mech, _, _, poses = approach
    J = mech.jacobian(poses)
    G = np.swapaxes(J, 1, 2)
    zono = worst_case_output(G, -2.5, 2.5, keep=(0, 1, 2))
    kappa = np.linalg.cond(J)
    for i in range(len(DIST)):
        hull = worst_case_output(G[i], -2.5, 2.5, keep=(0, 1, 2), method="hull")
        assert abs(hull - zono[i]) <= 100 * kappa[i] * EPS * abs(zono[i]), DIST[i]
