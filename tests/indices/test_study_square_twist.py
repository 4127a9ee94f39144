"""L = 6: the velocity and angular velocity of eq. (5) are the worst cases of the slab set
{ẋ : |J ẋ|∞ <= q̇max} (J square: J⁻¹·box is that set), computed from J itself on both
routes (QA round H 2).  The zonotope of J⁻¹ dropped them to exactly 0 once κ < 1e-12 (its
flat route), next to poses where they are finite; they are now continuous through the
singularity.  Checked against the zonotope of J⁻¹ (worst_case_output) at regular poses and
against the analytic slab distance q̇max / max_l ||J_{l,S}|| at a singular one."""

from __future__ import annotations

import numpy as np
import pytest
from indices_helpers import random_reachable_poses, rel_err

from distkin.indices import worst_case_output
from distkin.indices.study import ACTUATORS, evaluate_poses
from distkin.indices.study import _indices_compiled, _indices_numpy

ST = (15, 15, 15, 1, 1, 1)
QDOT = ACTUATORS["velocity"]


def _J(mech, P):
    Jq, Jx = mech.jq_jx(P)
    return Jq, Jx / Jq[..., None]


def _slab(J, S):
    return QDOT / np.linalg.norm(J[:, :, list(S)], axis=2).max(axis=1)


@pytest.mark.parametrize("name", ["hexa", "hunt"])
@pytest.mark.parametrize("compiled", [True, False])
def test_regular_poses_keep_the_zonotope_values(presets, name, compiled):
    """At regular poses the slab formula is the zonotope of J⁻¹·box (the route before)."""
    mech = presets[name]
    P = random_reachable_poses(mech, 40, 20, seed=17)
    ok, v = evaluate_poses(mech, P, compiled=compiled)
    _, J = _J(mech, P[ok])
    Ji = np.linalg.inv(J)
    for cap, S in (("velocity", [0, 1, 2]), ("angular_velocity", [3, 4, 5])):
        ref = [worst_case_output(Ji[k], -QDOT, QDOT, S) for k in range(len(Ji))]
        assert rel_err(v[cap], ref) < 1e-12, cap


@pytest.mark.parametrize("route", ["compiled", "numpy"])
def test_the_twist_worst_cases_are_continuous_through_a_singularity(presets, route):
    """J with its smallest singular value removed (σmin = 0) and neighbours at
    κ = 1e-8 and 1e-13 (the latter below RANK_TOL: the flat route before, which gave 0):
    the values are the analytic slab distances, and move by O(κ) between them."""
    mech = presets["hunt"]
    P = random_reachable_poses(mech, 1, 20, seed=4)
    Jq, J0 = _J(mech, P)
    U, s, Vt = np.linalg.svd(J0[0])
    Js = [J0[0] - (s[-1] - t * s[0]) * np.outer(U[:, -1], Vt[-1]) for t in (0.0, 1e-13, 1e-8)]
    J = np.array(Js)
    Jq = np.repeat(Jq, 3, axis=0)
    M = np.array([mech.mass] * 3 + [mech.inertia] * 3)
    run = _indices_compiled if route == "compiled" else _indices_numpy
    args = (J, Jq, M, dict(ACTUATORS), ST, "slice")
    out = run(*args)
    for cap, S in (("velocity", (0, 1, 2)), ("angular_velocity", (3, 4, 5))):
        v = out[cap]
        assert np.all(v > 0), (cap, v)
        np.testing.assert_allclose(v, _slab(J, S), rtol=1e-14)
        assert abs(v[2] - v[0]) <= 1e-6 * v[0]                # continuous
        # the regular neighbour's zonotope of J⁻¹ agrees (independent route)
        ref = worst_case_output(np.linalg.inv(J[2]), -QDOT, QDOT, list(S))
        assert v[2] == pytest.approx(ref, rel=1e-6)
