"""The study flags the poses whose J float64 does not resolve (QA 25a F4): next to the
Octopod's reach boundary, at (0, 0, 0.49732875444719654 m), evaluate_poses gave
σmax = 3.194e7 where the certified J gives 2.781e7 (15 % off), without a word, while
``mech.jacobian`` warned.  Now such a pose is marked (``J_unresolved``), warned about
(ConditioningWarning), and left out of the sweep's extremes and counted.

Reference: the certified tier (arb balls) of J at the same poses, its σ of ST⁻¹Jᵀ by
numpy's SVD of the ball midpoints (radii far below the differences tested)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.indices.isotropy import ST_DEFAULT
from distkin.indices.paper_tables import TABLE3_ROWS
from distkin.indices.study import _ROWS, Device, evaluate_poses, study_chunk, summarise
from distkin.indices.workspace import PoseGrid
from distkin.mechanisms.kinematics_tiers import jacobian_tier

ZB = 0.49732875444719654          # QA's pose: legs at their reach boundary (z, m)


def _sigma_certified(mech, X):
    t = jacobian_tier(mech, X, "certified")
    assert np.all(t.J_error < 1e-6 * np.abs(t.J).max())
    W = np.swapaxes(t.J, 1, 2) / np.asarray(ST_DEFAULT)[:, None]
    s = np.linalg.svd(W, compute_uv=False)
    return s[:, -1], s[:, 0]


@pytest.mark.parametrize("route", ["kernels", "numpy"])
def test_a_pose_next_to_the_reach_boundary_is_flagged(presets, route):
    mech = presets["octopod"]
    X = np.array([[0, 0, 0.30, 0, 0, 0], [0, 0, ZB, 0, 0, 0]])
    with pytest.warns(ConditioningWarning, match=r"at 1 of 2 reachable pose\(s\).*pose 1"):
        ok, v = evaluate_poses(mech, X, route=route)
    assert ok.all()
    assert v["J_unresolved"].tolist() == [False, True]
    smin, smax = _sigma_certified(mech, X)
    # the regular pose agrees with the certified J; the flagged one does not
    assert v["sigma_max"][0] == pytest.approx(smax[0], rel=1e-10)
    assert v["sigma_min"][0] == pytest.approx(smin[0], rel=1e-10)
    assert abs(v["sigma_max"][1] / smax[1] - 1) > 0.01


def test_a_regular_grid_is_not_flagged_and_says_nothing(presets):
    mech = presets["octopod"]
    X = np.array([[x, 0, 0.30 + z, 0.2, -0.1, 0.3] for x in (-0.05, 0, 0.05)
                  for z in (-0.05, 0, 0.05)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        ok, v = evaluate_poses(mech, X)
    assert ok.all() and not v["J_unresolved"].any()


def test_the_sweep_leaves_the_pose_out_and_counts_it(presets):
    mech = presets["octopod"]
    grid = PoseGrid((0.0,), (0.0,), (ZB - 0.2, ZB), (0.0,), (0.0,), (0.0,))
    spec = {"mech": mech, "grid": grid, "lo": 0, "hi": 2,
            "actuators": {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0},
            "ST": ST_DEFAULT, "inner": None, "route": "kernels"}
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)   # counted, not warned
        per = study_chunk(spec)
    assert per["n_ok"].tolist() == [1, 1]                     # still reachable
    assert per["n_unresolved"].tolist() == [0, 1]
    assert per["n_flagged"].tolist() == [0, 0]
    assert per["sigma_max_max"][1] == -np.inf and per["sigma_min_min"][1] == np.inf
    smin, smax = _sigma_certified(mech, np.array([[0, 0, ZB - 0.2, 0, 0, 0]]))
    assert per["sigma_max_max"][0] == pytest.approx(smax[0], rel=1e-10)
    s = summarise(Device("Octopod", mech, grid), per)
    assert s["unresolved_poses"] == 1 and s["reachable_poses"] == 2
    assert s["isotropy"]["sigma_max"] == pytest.approx(smax[0], rel=1e-10)


def test_paper_table3_rows_are_the_study_rows():
    assert tuple(_ROWS) == TABLE3_ROWS
